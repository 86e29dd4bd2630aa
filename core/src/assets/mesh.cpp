// Mesh loading: assimp's scene graph flattened into one indexed triangle
// mesh in the file's root space, a part per mesh placed by a node.
#include "facet/mesh.hpp"

#include "facet/error.hpp"
#include "facet/math.hpp"
#include "assets/import_files.hpp"
#include "assets/mesh_animation.hpp"
#include "assets/mesh_cameras.hpp"
#include "assets/mesh_import.hpp"
#include "assets/gltf_materials.hpp"
#include "assets/mesh_materials.hpp"
#include "assets/tangents.hpp"
#include "assets/glb_check.hpp"
#include "assets/gltf_extensions.hpp"
#include "assets/off_check.hpp"
#include "assets/ply_check.hpp"
#include "base/files.hpp"
#include "base/isolated.hpp"
#include "facet/memory.hpp"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <spdlog/spdlog.h>
#include <assimp/Importer.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

namespace facet {

namespace {

// ValidateDataStructure runs first and refuses out-of-range face indices,
// which the later steps would follow out of bounds (a fuzzed PLY did).
constexpr unsigned kImportFlags = aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                  aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                                  aiProcess_FlipUVs | aiProcess_SortByPType;

// Optional attributes the merged mesh carries: those any part has. Parts
// without them get zero UVs or white.
struct Layout {
    bool uvs = false;
    bool uvs1 = false;
    bool colors = false;
};

bool is_triangles(const aiMesh& mesh) {
    return (mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) != 0;
}

Layout find_layout(const aiScene& scene) {
    Layout layout;
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        const aiMesh& mesh = *scene.mMeshes[i];
        if (!is_triangles(mesh)) continue;
        layout.uvs |= mesh.HasTextureCoords(0);
        layout.uvs1 |= mesh.HasTextureCoords(1);
        layout.colors |= mesh.HasVertexColors(0);
    }
    return layout;
}

glm::mat4 to_glm(const aiMatrix4x4& m) {
    return glm::transpose(glm::make_mat4(&m.a1));  // assimp is row-major
}

glm::vec3 unit_or_z(const glm::vec3& n) {
    const float length = glm::length(n);
    return std::isfinite(length) && length > 0.0f ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

void append_vertices(const aiMesh& src, const glm::mat4& model, Layout layout, Mesh& out) {
    const glm::mat3 normals = normal_matrix(model);
    for (unsigned i = 0; i < src.mNumVertices; ++i) {
        const aiVector3D& p = src.mVertices[i];
        out.positions.push_back(glm::vec3(model * glm::vec4(p.x, p.y, p.z, 1.0f)));
        const aiVector3D n = src.HasNormals() ? src.mNormals[i] : aiVector3D(0.0f);
        out.normals.push_back(unit_or_z(normals * glm::vec3(n.x, n.y, n.z)));
        if (layout.uvs) {
            const aiVector3D t =
                src.HasTextureCoords(0) ? src.mTextureCoords[0][i] : aiVector3D(0.0f);
            out.uvs.emplace_back(t.x, t.y);
        }
        if (layout.uvs1) {
            const aiVector3D t =
                src.HasTextureCoords(1) ? src.mTextureCoords[1][i] : aiVector3D(0.0f);
            out.uvs1.emplace_back(t.x, t.y);
        }
        if (layout.colors) {
            const aiColor4D c = src.HasVertexColors(0) ? src.mColors[0][i] : aiColor4D(1.0f);
            out.colors.emplace_back(c.r, c.g, c.b, c.a);
        }
    }
}

// A mirroring transform turns the winding around; `flip` turns it back.
void append_triangles(const aiMesh& src, bool flip, Mesh& out) {
    for (unsigned f = 0; f < src.mNumFaces; ++f) {
        const aiFace& face = src.mFaces[f];
        if (face.mNumIndices != 3) continue;
        out.indices.push_back(face.mIndices[0]);
        out.indices.push_back(face.mIndices[flip ? 2 : 1]);
        out.indices.push_back(face.mIndices[flip ? 1 : 2]);
    }
}

// The file's own tangents, in root space; w from its bitangents (assimp
// gives glTF's cross(normal, tangent) * w), so a mirroring node keeps it right.
void file_tangents(const aiMesh& src, const glm::mat4& model, Mesh& part) {
    const glm::mat3 m(model);
    for (unsigned i = 0; i < src.mNumVertices; ++i) {
        const glm::vec3 n = part.normals[i];
        const aiVector3D& t = src.mTangents[i];
        const aiVector3D& b = src.mBitangents[i];
        glm::vec3 tangent = m * glm::vec3(t.x, t.y, t.z);
        tangent -= n * glm::dot(n, tangent);
        const float length = glm::length(tangent);
        // None left across the normal: no frame, and a normal map leaves n alone.
        tangent = std::isfinite(length) && length > 0.0f ? tangent / length : glm::vec3(0.0f);
        const glm::vec3 bitangent = m * glm::vec3(b.x, b.y, b.z);
        part.tangents.emplace_back(tangent,
                                   glm::dot(glm::cross(n, tangent), bitangent) < 0.0f ? -1.0f : 1.0f);
    }
}

// The part names given so far, and for each name the next number to try
// after it: a mesh placed by thousands of nodes is named in linear time.
struct PartNames {
    std::unordered_set<std::string> used;
    std::unordered_map<std::string, int> next;

    // The mesh's name, else its node's, else "part N"; made unique with
    // "#2", "#3", ...
    std::string make(const aiMesh& src, const aiNode& node, size_t index) {
        std::string base = src.mName.C_Str();
        if (base.empty()) base = node.mName.C_Str();
        if (base.empty()) base = "part " + std::to_string(index);
        std::string name = base;
        for (int& k = next.try_emplace(base, 2).first->second; !used.insert(name).second; ++k)
            name = base + "#" + std::to_string(k);
        return name;
    }
};

// The vertices and triangles of `src` placed by `model`, with tangents
// where it has texture coordinates.
Mesh placed_vertices(const aiMesh& src, const glm::mat4& model, bool flip, Layout layout) {
    Mesh part;
    append_vertices(src, model, layout, part);
    append_triangles(src, flip, part);
    if (layout.uvs) {
        if (src.HasTangentsAndBitangents()) file_tangents(src, model, part);
        else generate_tangents(part);
    }
    return part;
}

bool deforms(const aiMesh& src) { return src.mNumBones > 0 || src.mNumAnimMeshes > 0; }

// A place whose inverse float cannot hold (a scale of 0, or near it): a
// part placed so keeps its own vertices, since its motion from rest could
// not be recovered from the collapsed ones.
bool singular(const glm::mat4& model) {
    const glm::dmat4 inverse = glm::inverse(glm::dmat4(model));
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!(std::abs(inverse[c][r]) <= 1e30)) return true;
    return false;
}

// The file's nodes, when it animates or deforms anything: parts that a skin
// or morph targets deform keep what deforms them.
struct Animated {
    const NodeIndex* nodes = nullptr;
};

// One aiMesh placed by a node: a part of its own. A skinned part ignores
// its node's place (its joints place it); its vertices are posed at rest
// once the whole file is read.
void append_part(const aiMesh& src, const aiNode& node, const glm::mat4& model, Layout layout,
                 Animated animated, PartNames& names, Mesh& out,
                 std::vector<const aiNode*>& placed_by) {
    const bool deformed = animated.nodes && (deforms(src) || singular(model));
    const bool flip = src.mNumBones == 0 && glm::determinant(glm::mat3(model)) < 0.0f;
    Mesh part = placed_vertices(src, model, flip, layout);
    MeshPart p;
    p.name = names.make(src, node, out.parts.size());
    p.first_index = uint32_t(out.indices.size());
    p.index_count = uint32_t(part.indices.size());
    p.first_vertex = uint32_t(out.positions.size());
    p.vertex_count = uint32_t(part.positions.size());
    p.material = int(src.mMaterialIndex);
    const auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
    append(out.positions, part.positions);
    append(out.normals, part.normals);
    append(out.uvs, part.uvs);
    append(out.uvs1, part.uvs1);
    append(out.colors, part.colors);
    append(out.tangents, part.tangents);
    for (uint32_t i : part.indices) out.indices.push_back(p.first_vertex + i);
    out.parts.push_back(std::move(p));
    placed_by.push_back(&node);
    if (animated.nodes)
        out.deformations.push_back(
            deformed ? import_deformation(src, placed_vertices(src, glm::mat4(1.0f), flip, layout),
                                          *animated.nodes, out)
                     : PartDeformation{});
}

// Each part's node goes to `placed_by`, in the parts' order.
void append_node(const aiScene& scene, const aiNode& node, const glm::mat4& parent, Layout layout,
                 Animated animated, PartNames& names, Mesh& out,
                 std::vector<const aiNode*>& placed_by) {
    const glm::mat4 model = parent * to_glm(node.mTransformation);
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
        const aiMesh& src = *scene.mMeshes[node.mMeshes[i]];
        if (is_triangles(src) && src.mNumFaces > 0)
            append_part(src, node, model, layout, animated, names, out, placed_by);
    }
    for (unsigned i = 0; i < node.mNumChildren; ++i)
        append_node(scene, *node.mChildren[i], model, layout, animated, names, out, placed_by);
}

// The nodes, clips and deformations of a file that animates or deforms
// anything; none of them when nothing moves. The deformed parts are posed
// at rest.
void keep_animation(const aiScene& scene, const NodeIndex& nodes,
                    const std::vector<const aiNode*>& placed_by, Mesh& mesh) {
    import_clips(scene, placed_by, nodes, mesh);
    const bool deformed = std::any_of(mesh.deformations.begin(), mesh.deformations.end(),
                                      [](const PartDeformation& d) { return d.deforms(); });
    const bool moves = std::any_of(mesh.clips.begin(), mesh.clips.end(), [](const MeshClip& c) {
        return c.moves_nodes() || !c.weights.empty();
    });
    if (!deformed) mesh.deformations.clear();
    if (!deformed && !moves) {
        mesh.nodes.clear();
        mesh.clips.clear();
        for (MeshPart& p : mesh.parts) p.node = -1;
        return;
    }
    if (deformed) {
        validate_deformations(mesh);  // before posing reads them
        pose_mesh(mesh, -1, 0.0, {}, mesh);
    }
}

bool is_finite(const glm::vec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

Error invalid(const Mesh& mesh, const std::string& problem) {
    return Error(ErrorCode::mesh_invalid, problem, mesh.source);
}

void check_attribute(const Mesh& mesh, size_t size, const char* name) {
    if (size != 0 && size != mesh.vertex_count())
        throw invalid(mesh, "it has " + std::to_string(size) + " " + name + " for " +
                                std::to_string(mesh.vertex_count()) + " vertices");
}

// Parts tile the triangles in order, each within its vertex range.
void validate_parts(const Mesh& mesh) {
    uint64_t next = 0;
    for (const MeshPart& p : mesh.parts) {
        const std::string which = "part '" + p.name + "'";
        if (p.first_index != next || p.index_count % 3 != 0 ||
            uint64_t(p.first_index) + p.index_count > mesh.indices.size())
            throw invalid(mesh, which + " does not follow the one before it with whole triangles");
        if (uint64_t(p.first_vertex) + p.vertex_count > mesh.vertex_count())
            throw invalid(mesh, which + "'s vertices lie past the mesh's");
        for (uint32_t i = p.first_index; i < p.first_index + p.index_count; ++i)
            if (mesh.indices[i] < p.first_vertex || mesh.indices[i] - p.first_vertex >= p.vertex_count)
                throw invalid(mesh, which + " uses vertex " + std::to_string(mesh.indices[i]) +
                                        ", outside its own");
        if (p.material < -1 || p.material >= int(mesh.materials.size()))
            throw invalid(mesh, which + " names material " + std::to_string(p.material) + " of " +
                                    std::to_string(mesh.materials.size()));
        next = uint64_t(p.first_index) + p.index_count;
    }
    if (!mesh.parts.empty() && next != mesh.indices.size())
        throw invalid(mesh, "its parts leave triangles out");
}

// The importer proper: assimp, flattened into one mesh. Unguarded.
Mesh import_mesh(const std::filesystem::path& path) {
    Assimp::Importer importer;
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    auto* files = new RegularFilesOnly;  // the importer owns it
    importer.SetIOHandler(files);
    const aiScene* scene = importer.ReadFile(path.string(), kImportFlags);
    if (const std::optional<Error> refused = files->refused())
        throw Error(ErrorCode::not_a_file,
                    "it names " + refused->file() + ", which it cannot read: " + refused->detail(),
                    path.string());
    if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
        // assimp catches what its readers throw and keeps only the message:
        // an allocation that failed is told by its what().
        if (importer.GetErrorString() == std::string_view(std::bad_alloc().what()))
            throw std::bad_alloc();
        throw Error(ErrorCode::mesh_load_failed, importer.GetErrorString(), path.string());
    }
    Mesh mesh;
    mesh.source = path.string();
    PartNames names;
    std::vector<const aiNode*> placed_by;
    NodeIndex nodes;
    Animated animated;
    if (has_animation(*scene)) {
        nodes = import_nodes(*scene, mesh);
        animated.nodes = &nodes;
    }
    append_node(*scene, *scene->mRootNode, glm::mat4(1.0f), find_layout(*scene), animated, names,
                mesh, placed_by);
    if (animated.nodes) keep_animation(*scene, nodes, placed_by, mesh);
    const GltfMaterials extensions = is_gltf(path) ? read_gltf_materials(path) : GltfMaterials{};
    mesh.notes += extensions.notes;
    for (unsigned i = 0; i < scene->mNumMaterials; ++i)
        mesh.materials.push_back(import_material(*scene, i, path, &extensions));
    mesh.images = embedded_images(*scene);
    mesh.cameras = import_cameras(*scene, path);
    // assimp gives parts of a file without materials (an OBJ without .mtl)
    // one of its own; glTF's default material is the format's, and kept.
    if (!is_gltf(path))
        for (MeshPart& p : mesh.parts)
            if (p.material >= 0 && mesh.materials[size_t(p.material)].name == AI_DEFAULT_MATERIAL_NAME)
                p.material = -1;
    if (is_obj(path)) check_obj_libraries(path, mesh.materials);
    return mesh;
}

// A mesh's arrays as bytes, to come back from facet-sandbox: each
// array's length, then its elements.
template <typename T>
void put_array(std::string& out, const std::vector<T>& v) {
    const uint64_t n = v.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof n);
    if (!v.empty()) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <typename T>
void get_array(std::string_view& in, std::vector<T>& v) {
    uint64_t n = 0;
    if (in.size() < sizeof n) throw std::length_error("a truncated mesh");
    std::memcpy(&n, in.data(), sizeof n);
    in.remove_prefix(sizeof n);
    if (n > in.size() / sizeof(T)) throw std::length_error("a truncated mesh");
    v.resize(n);
    if (n) std::memcpy(v.data(), in.data(), n * sizeof(T));
    in.remove_prefix(n * sizeof(T));
}

void put_string(std::string& out, const std::string& s) {
    put_array(out, std::vector<char>(s.begin(), s.end()));
}

std::string get_string(std::string_view& in) {
    std::vector<char> chars;
    get_array(in, chars);
    return {chars.begin(), chars.end()};
}

template <typename T>
void put_value(std::string& out, T v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <typename T>
T get_value(std::string_view& in) {
    T v;
    if (in.size() < sizeof v) throw std::length_error("a truncated mesh");
    std::memcpy(&v, in.data(), sizeof v);
    in.remove_prefix(sizeof v);
    return v;
}

template <typename T>
void put_track(std::string& out, const Track<T>& track) {
    put_array(out, track.times);
    put_array(out, track.values);
}

template <typename T>
void get_track(std::string_view& in, Track<T>& track) {
    get_array(in, track.times);
    get_array(in, track.values);
}

// A count of items that each take at least a byte.
uint64_t get_count(std::string_view& in) {
    const auto n = get_value<uint64_t>(in);
    if (n > in.size()) throw std::length_error("a truncated mesh");
    return n;
}

// A camera's numbers after its name, as one value.
struct CameraNumbers {
    glm::vec3 position, forward, up;
    float fov_y, ortho_height, near, far;
    uint8_t orthographic;
};

void put_cameras(std::string& out, const Mesh& m) {
    put_value(out, uint64_t(m.cameras.size()));
    for (const MeshCamera& c : m.cameras) {
        put_string(out, c.name);
        put_value(out, CameraNumbers{c.position, c.forward, c.up, c.fov_y, c.ortho_height, c.near,
                                     c.far, uint8_t(c.orthographic)});
    }
}

void put_animation(std::string& out, const Mesh& m) {
    put_value(out, uint64_t(m.clips.size()));
    for (const MeshClip& c : m.clips) {
        put_string(out, c.name);
        put_value(out, uint64_t(c.nodes.size()));
        for (const TransformTracks& n : c.nodes) {
            put_track(out, n.position);
            put_track(out, n.rotation);
            put_track(out, n.scale);
        }
        put_value(out, uint64_t(c.weights.size()));
        for (const WeightsTrack& w : c.weights) {
            put_array(out, w.times);
            put_array(out, w.values);
        }
    }
    put_value(out, uint64_t(m.skins.size()));
    for (const MeshSkin& skin : m.skins) {
        put_string(out, skin.name);
        put_array(out, skin.joints);
        put_array(out, skin.inverse_binds);
    }
    put_value(out, uint64_t(m.deformations.size()));
    for (const PartDeformation& d : m.deformations) {
        put_value(out, int32_t(d.skin));
        put_array(out, d.positions);
        put_array(out, d.normals);
        put_array(out, d.tangents);
        put_array(out, d.joints);
        put_array(out, d.weights);
        put_value(out, uint64_t(d.targets.size()));
        for (const MorphTarget& t : d.targets) {
            put_string(out, t.name);
            put_array(out, t.positions);
            put_array(out, t.normals);
            put_array(out, t.tangents);
        }
    }
}

// Each of a count's items reads at least a byte (or throws): a count past
// what the bytes hold fails before it allocates much.
template <class T, class Read>
void get_items(std::string_view& in, std::vector<T>& items, Read read) {
    const uint64_t n = get_count(in);
    for (uint64_t i = 0; i < n; ++i) read(items.emplace_back());
}

void get_cameras(std::string_view& in, Mesh& m) {
    get_items(in, m.cameras, [&](MeshCamera& c) {
        c.name = get_string(in);
        const auto n = get_value<CameraNumbers>(in);
        c.position = n.position, c.forward = n.forward, c.up = n.up;
        c.fov_y = n.fov_y, c.ortho_height = n.ortho_height, c.near = n.near, c.far = n.far;
        c.orthographic = n.orthographic != 0;
    });
}

void get_animation(std::string_view& in, Mesh& m) {
    get_items(in, m.clips, [&](MeshClip& c) {
        c.name = get_string(in);
        get_items(in, c.nodes, [&](TransformTracks& n) {
            get_track(in, n.position);
            get_track(in, n.rotation);
            get_track(in, n.scale);
        });
        get_items(in, c.weights, [&](WeightsTrack& w) {
            get_array(in, w.times);
            get_array(in, w.values);
        });
    });
    get_items(in, m.skins, [&](MeshSkin& skin) {
        skin.name = get_string(in);
        get_array(in, skin.joints);
        get_array(in, skin.inverse_binds);
    });
    get_items(in, m.deformations, [&](PartDeformation& d) {
        d.skin = get_value<int32_t>(in);
        get_array(in, d.positions);
        get_array(in, d.normals);
        get_array(in, d.tangents);
        get_array(in, d.joints);
        get_array(in, d.weights);
        get_items(in, d.targets, [&](MorphTarget& t) {
            t.name = get_string(in);
            get_array(in, t.positions);
            get_array(in, t.normals);
            get_array(in, t.tangents);
        });
    });
}

std::string to_bytes(const Mesh& m) {
    std::string out;
    put_string(out, m.notes);
    put_array(out, m.positions);
    put_array(out, m.normals);
    put_array(out, m.uvs);
    put_array(out, m.uvs1);
    put_array(out, m.colors);
    put_array(out, m.tangents);
    put_array(out, m.indices);
    put_value(out, uint64_t(m.parts.size()));
    for (const MeshPart& p : m.parts) {
        put_string(out, p.name);
        for (uint32_t v : {p.first_index, p.index_count, p.first_vertex, p.vertex_count})
            put_value(out, v);
        put_value(out, int32_t(p.material));
        put_value(out, int32_t(p.node));
    }
    put_value(out, uint64_t(m.nodes.size()));
    for (const MeshNode& n : m.nodes) {
        put_string(out, n.name);
        put_value(out, int32_t(n.parent));
        put_value(out, n.rest);
    }
    put_animation(out, m);
    put_cameras(out, m);
    put_value(out, uint64_t(m.materials.size()));
    for (const ImportedMaterial& im : m.materials)
        for (const std::string* s : {&im.name, &im.yaml, &im.notes, &im.problem}) put_string(out, *s);
    put_value(out, uint64_t(m.images.size()));
    for (const auto& image : m.images) {
        put_value(out, uint8_t(image != nullptr));
        if (image) put_string(out, *image);
    }
    return out;
}

void from_bytes(std::string_view in, Mesh& m) {
    m.notes = get_string(in);
    get_array(in, m.positions);
    get_array(in, m.normals);
    get_array(in, m.uvs);
    get_array(in, m.uvs1);
    get_array(in, m.colors);
    get_array(in, m.tangents);
    get_array(in, m.indices);
    const auto parts = get_value<uint64_t>(in);
    if (parts > in.size()) throw std::length_error("a truncated mesh");
    for (uint64_t i = 0; i < parts; ++i) {
        MeshPart& p = m.parts.emplace_back();
        p.name = get_string(in);
        for (uint32_t* v : {&p.first_index, &p.index_count, &p.first_vertex, &p.vertex_count})
            *v = get_value<uint32_t>(in);
        p.material = get_value<int32_t>(in);
        p.node = get_value<int32_t>(in);
    }
    const auto nodes = get_value<uint64_t>(in);
    if (nodes > in.size()) throw std::length_error("a truncated mesh");
    for (uint64_t i = 0; i < nodes; ++i) {
        MeshNode& n = m.nodes.emplace_back();
        n.name = get_string(in);
        n.parent = get_value<int32_t>(in);
        n.rest = get_value<Transform>(in);
    }
    get_animation(in, m);
    get_cameras(in, m);
    const auto materials = get_value<uint64_t>(in);
    if (materials > in.size()) throw std::length_error("a truncated mesh");
    for (uint64_t i = 0; i < materials; ++i) {
        ImportedMaterial& im = m.materials.emplace_back();
        for (std::string* s : {&im.name, &im.yaml, &im.notes, &im.problem}) *s = get_string(in);
    }
    const auto images = get_value<uint64_t>(in);
    if (images > in.size()) throw std::length_error("a truncated mesh");
    for (uint64_t i = 0; i < images; ++i)
        m.images.push_back(get_value<uint8_t>(in)
                               ? std::make_shared<const std::string>(get_string(in))
                               : nullptr);
}

// 30 s, and 1 s more per MiB: assimp reads tens of MiB a second.
std::chrono::milliseconds import_time_limit(const std::filesystem::path& path) {
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    return std::chrono::milliseconds(30000 + (ec ? 0 : size / 1024 * 1000 / 1024));
}

// import_mesh() in facet-sandbox, limited in memory and time; in this
// process, with a warning, where the sandbox is not installed.
Mesh import_isolated(const std::filesystem::path& path) {
    const std::string file = path.string();
    if (in_sandbox()) return import_mesh(path);  // a trial frame's scene, limited already
    if (!sandbox_program()) {
        spdlog::warn("{}: facet-sandbox is not installed beside this program; importing in this "
                     "process, without limits", file);
        return import_mesh(path);
    }
    const IsolationLimits limits{memory_budget(), import_time_limit(path)};
    const IsolatedResult r = run_sandboxed("import", {file}, limits);
    switch (r.end) {
        case IsolatedResult::End::finished: {
            // Its bytes and the arrays made of them, at once.
            require_within_budget(2 * uint64_t(r.output.size()), "the imported mesh", file);
            Mesh mesh;
            mesh.source = file;
            try {
                from_bytes(r.output, mesh);
            } catch (const std::length_error&) {
                throw Error(ErrorCode::mesh_load_failed, "the importer's result was cut short",
                            file);
            }
            return mesh;
        }
        case IsolatedResult::End::error: throw *r.error;
        case IsolatedResult::End::out_of_memory:
            throw Error(ErrorCode::over_budget,
                        "importing it needs more than the memory budget of " +
                            memory_text(limits.memory) +
                            " (set it with --max-memory or FACET_MAX_MEMORY)",
                        file);
        case IsolatedResult::End::out_of_time:
            throw Error(ErrorCode::mesh_load_failed,
                        "the importer did not finish within its limit of " +
                            std::to_string(limits.time.count() / 1000) + " s",
                        file);
        case IsolatedResult::End::crashed: break;
    }
    throw Error(ErrorCode::mesh_load_failed, "the importer failed: " + r.output, file);
}

// What the file animates and deforms (-v), and what the import left out
// or mended (warnings).
void log_animation(const Mesh& mesh) {
    for (size_t i = 0; i < mesh.clips.size(); ++i)
        spdlog::debug("  clip {} '{}': {:g} s", i, mesh.clips[i].name, mesh.clips[i].end());
    for (const MeshSkin& skin : mesh.skins)
        spdlog::debug("  skin '{}': {} joints", skin.name, skin.joints.size());
    for (size_t p = 0; p < mesh.deformations.size(); ++p)
        for (const MorphTarget& t : mesh.deformations[p].targets)
            spdlog::debug("  part '{}': morph target '{}'", mesh.parts[p].name, t.name);
    size_t start = 0;
    while (start < mesh.notes.size()) {
        size_t end = mesh.notes.find('\n', start);
        if (end == std::string::npos) end = mesh.notes.size();
        spdlog::warn("{}: {}", mesh.source, mesh.notes.substr(start, end - start));
        start = end + 1;
    }
}

// Each extension the glTF file uses: -v lists it, and one not drawn as the
// file means is a warning.
void log_gltf_extensions(const std::filesystem::path& path) {
    const auto used = gltf_extensions_used(path);
    if (!used) {
        spdlog::warn("{}: its JSON could not be read for the extensions it uses (over 64 MiB?); "
                     "its materials' texture transforms, emissive strength, ior and specular are "
                     "left out, and "
                     "they are not listed", path.string());
        return;
    }
    for (const std::string& name : *used) {
        const std::string use = gltf_extension_use(name);
        if (use == "drawn") spdlog::debug("  extension {}: drawn", name);
        else spdlog::warn("{}: extension {}: {}", path.string(), name, use);
    }
}

}  // namespace

std::string import_mesh_bytes(const std::filesystem::path& path) {
    return to_bytes(import_mesh(path));
}

std::shared_ptr<const Mesh> load_mesh(const std::filesystem::path& path, MeshImport how) {
    require_regular_file(path);
    if (looks_like_ply(path)) check_ply(path);  // clear errors for bad PLY, OFF and GLB
    if (looks_like_off(path)) check_off(path);  // headers, without starting the importer
    if (looks_like_glb(path)) check_glb(path);
    check_gltf_name(path);
    auto mesh = std::make_shared<Mesh>(how == MeshImport::isolated ? import_isolated(path)
                                                                    : import_mesh(path));
    validate_mesh(*mesh);
    mesh->bounds = compute_bounds(mesh->positions);
    for (MeshPart& p : mesh->parts)
        p.bounds = compute_bounds({mesh->positions.begin() + p.first_vertex,
                                   mesh->positions.begin() + p.first_vertex + p.vertex_count});
    spdlog::debug("mesh {}: {} vertices, {} triangles{}{}{}{}, {} parts", mesh->source,
                  mesh->vertex_count(), mesh->triangle_count(), mesh->uvs.empty() ? "" : ", uvs",
                  mesh->uvs1.empty() ? "" : ", a second UV set", mesh->colors.empty() ? "" : ", colours",
                  mesh->tangents.empty() ? "" : ", tangents", mesh->part_count());
    for (const MeshPart& p : mesh->parts)
        spdlog::debug("  part '{}': {} triangles, material '{}'", p.name, p.triangle_count(),
                      p.material >= 0 ? mesh->materials[size_t(p.material)].name : "");
    log_animation(*mesh);
    if (is_gltf(path)) log_gltf_extensions(path);
    return mesh;
}

MeshPart Mesh::whole_part() const {
    MeshPart p;
    p.name = "whole";
    p.index_count = uint32_t(indices.size());
    p.vertex_count = uint32_t(positions.size());
    p.bounds = bounds;
    return p;
}

int Mesh::find_part(const std::string& name) const {
    for (size_t i = 0; i < parts.size(); ++i)
        if (parts[i].name == name) return int(i);
    return -1;
}

void validate_mesh(const Mesh& mesh) {
    if (mesh.positions.empty()) throw invalid(mesh, "it has no vertices");
    if (mesh.indices.empty()) throw invalid(mesh, "it has no triangles");
    if (mesh.indices.size() % 3 != 0)
        throw invalid(mesh, "its index count " + std::to_string(mesh.indices.size()) +
                                " is not a multiple of 3");
    check_attribute(mesh, mesh.normals.size(), "normals");
    check_attribute(mesh, mesh.uvs.size(), "uvs");
    check_attribute(mesh, mesh.uvs1.size(), "second UV set's uvs");
    check_attribute(mesh, mesh.colors.size(), "colours");
    check_attribute(mesh, mesh.tangents.size(), "tangents");
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        if (!is_finite(mesh.positions[i]))
            throw invalid(mesh, "vertex " + std::to_string(i) + " has a non-finite position");
    for (size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= mesh.vertex_count())
            throw invalid(mesh, "triangle " + std::to_string(i / 3) + " uses vertex " +
                                    std::to_string(mesh.indices[i]) + " of " +
                                    std::to_string(mesh.vertex_count()));
    validate_parts(mesh);
    validate_nodes(mesh);
    for (const MeshCamera& c : mesh.cameras)
        if (!is_finite(c.position) || !is_finite(c.forward) || !is_finite(c.up) ||
            !(c.fov_y > 0.0f && c.fov_y < 180.0f) || !(c.ortho_height >= 0.0f) ||
            !(c.near >= 0.0f) || !(c.far >= 0.0f) || std::isinf(c.ortho_height) ||
            std::isinf(c.near) || std::isinf(c.far))
            throw invalid(mesh, "camera '" + c.name + "' is not a camera: a place, field of view "
                                "or clip distance that is not finite, or out of range");
}

Bounds compute_bounds(const std::vector<glm::vec3>& positions) {
    if (positions.empty()) return {};
    Bounds b{positions[0], positions[0]};
    for (const glm::vec3& p : positions) {
        b.min = glm::min(b.min, p);
        b.max = glm::max(b.max, p);
    }
    return b;
}

}  // namespace facet
