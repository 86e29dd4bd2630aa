// Mesh loading: assimp's scene graph flattened into one indexed triangle
// mesh in the file's root space.
#include "facet/mesh.hpp"

#include "facet/error.hpp"
#include "facet/math.hpp"
#include "assets/off_check.hpp"
#include "assets/ply_check.hpp"
#include "base/files.hpp"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <spdlog/spdlog.h>
#include <assimp/Importer.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>

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
        if (layout.colors) {
            const aiColor4D c = src.HasVertexColors(0) ? src.mColors[0][i] : aiColor4D(1.0f);
            out.colors.emplace_back(c.r, c.g, c.b, c.a);
        }
    }
}

// A mirroring transform turns the winding around; `flip` turns it back.
void append_triangles(const aiMesh& src, uint32_t base, bool flip, Mesh& out) {
    for (unsigned f = 0; f < src.mNumFaces; ++f) {
        const aiFace& face = src.mFaces[f];
        if (face.mNumIndices != 3) continue;
        out.indices.push_back(base + face.mIndices[0]);
        out.indices.push_back(base + face.mIndices[flip ? 2 : 1]);
        out.indices.push_back(base + face.mIndices[flip ? 1 : 2]);
    }
}

void append_node(const aiScene& scene, const aiNode& node, const glm::mat4& parent, Layout layout,
                 Mesh& out) {
    const glm::mat4 model = parent * to_glm(node.mTransformation);
    const bool flip = glm::determinant(glm::mat3(model)) < 0.0f;
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
        const aiMesh& src = *scene.mMeshes[node.mMeshes[i]];
        if (!is_triangles(src)) continue;
        const auto base = static_cast<uint32_t>(out.positions.size());
        append_vertices(src, model, layout, out);
        append_triangles(src, base, flip, out);
    }
    for (unsigned i = 0; i < node.mNumChildren; ++i)
        append_node(scene, *node.mChildren[i], model, layout, out);
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

}  // namespace

std::shared_ptr<const Mesh> load_mesh(const std::filesystem::path& path) {
    require_regular_file(path);
    if (looks_like_ply(path)) check_ply(path);  // assimp 5.2 hangs or crashes on some bad PLY
    if (looks_like_off(path)) check_off(path);  // and allocates for any count an OFF declares
    Assimp::Importer importer;
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const aiScene* scene = importer.ReadFile(path.string(), kImportFlags);
    if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
        throw Error(ErrorCode::mesh_load_failed, importer.GetErrorString(), path.string());

    auto mesh = std::make_shared<Mesh>();
    mesh->source = path.string();
    append_node(*scene, *scene->mRootNode, glm::mat4(1.0f), find_layout(*scene), *mesh);
    validate_mesh(*mesh);
    mesh->bounds = compute_bounds(mesh->positions);
    spdlog::info("mesh {}: {} vertices, {} triangles{}{}", mesh->source, mesh->vertex_count(),
                 mesh->triangle_count(), mesh->uvs.empty() ? "" : ", uvs",
                 mesh->colors.empty() ? "" : ", colours");
    return mesh;
}

void validate_mesh(const Mesh& mesh) {
    if (mesh.positions.empty()) throw invalid(mesh, "it has no vertices");
    if (mesh.indices.empty()) throw invalid(mesh, "it has no triangles");
    if (mesh.indices.size() % 3 != 0)
        throw invalid(mesh, "its index count " + std::to_string(mesh.indices.size()) +
                                " is not a multiple of 3");
    check_attribute(mesh, mesh.normals.size(), "normals");
    check_attribute(mesh, mesh.uvs.size(), "uvs");
    check_attribute(mesh, mesh.colors.size(), "colours");
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        if (!is_finite(mesh.positions[i]))
            throw invalid(mesh, "vertex " + std::to_string(i) + " has a non-finite position");
    for (size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= mesh.vertex_count())
            throw invalid(mesh, "triangle " + std::to_string(i / 3) + " uses vertex " +
                                    std::to_string(mesh.indices[i]) + " of " +
                                    std::to_string(mesh.vertex_count()));
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
