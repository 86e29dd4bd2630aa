// A glTF file's material extensions that assimp does not read
// (gltf_materials.hpp).
#include "assets/gltf_materials.hpp"

#include "assets/gltf_extensions.hpp"
#include "assets/yaml_util.hpp"
#include "facet/error.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string_view>

namespace facet {

namespace {

constexpr const char* kRead[] = {"KHR_texture_transform", "KHR_materials_emissive_strength",
                                 "KHR_materials_ior", "KHR_materials_specular"};

// node[key] of a map, or an undefined node: a fuzzed file's value may be of
// any type, and only a map is indexed.
YAML::Node child(const YAML::Node& node, const char* key) {
    if (!node || !node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& c = node;  // const: reading never adds the key
    return c[key];
}

class MaterialReader {
public:
    MaterialReader(std::string& notes, std::string material) : notes_(notes), material_(std::move(material)) {}

    // A number within [lo, hi], or `fallback` (noted when the file gave something else).
    float number(const YAML::Node& node, const std::string& what, float fallback, float lo, float hi) {
        if (!node) return fallback;
        const std::optional<double> v = node.IsScalar() ? yaml::parse_number(node) : std::nullopt;
        if (v && *v >= lo && *v <= hi) return float(*v);
        note(what + " is not a number from " + shown(lo) + " to " + shown(hi) + ": " + shown(fallback) + " is used");
        return fallback;
    }
    glm::vec2 pair(const YAML::Node& node, const std::string& what, glm::vec2 fallback) {
        if (!node) return fallback;
        if (!node.IsSequence() || node.size() != 2) {
            note(what + " is not two numbers: the default is used");
            return fallback;
        }
        return {number(node[0], what, fallback.x, -1e6f, 1e6f), number(node[1], what, fallback.y, -1e6f, 1e6f)};
    }
    glm::vec3 colour(const YAML::Node& node, const std::string& what) {
        if (!node.IsSequence() || node.size() != 3) {
            note(what + " is not three numbers: white is used");
            return glm::vec3(1.0f);
        }
        return {number(node[0], what, 1.0f, 0.0f, 1e6f), number(node[1], what, 1.0f, 0.0f, 1e6f),
                number(node[2], what, 1.0f, 0.0f, 1e6f)};
    }
    // KHR_texture_transform on textureInfo `info`, under `key`.
    void transform(const YAML::Node& info, const char* key, GltfMaterialExtensions& m) {
        const YAML::Node t = child(child(info, "extensions"), "KHR_texture_transform");
        if (!t) return;
        const std::string what = std::string(key) + "'s KHR_texture_transform ";
        GltfTextureTransform& out = m.transforms[key];
        out.transform.offset = pair(child(t, "offset"), what + "offset", glm::vec2(0.0f));
        out.transform.scale = pair(child(t, "scale"), what + "scale", glm::vec2(1.0f));
        out.transform.rotation = number(child(t, "rotation"), what + "rotation", 0.0f, -1e4f, 1e4f);
        if (const YAML::Node set = child(t, "texCoord"))
            out.tex_coord = int(number(set, what + "texCoord", 0.0f, 0.0f, 255.0f));
    }
    void note(const std::string& line) { notes_ += "material '" + material_ + "': " + line + "\n"; }

private:
    static std::string shown(float v) {
        std::string s = std::to_string(v);
        s.erase(s.find_last_not_of('0') + 1);
        if (s.back() == '.') s.pop_back();
        return s;
    }
    std::string& notes_;
    std::string material_;
};

// The order in which assimp 5.2.5 reads a file's materials, which is the
// order of its aiScene::mMaterials: as its glTF reader first meets them,
// walking the default scene's nodes depth first (a node's children before
// its own mesh, a mesh's primitives in order), then each skin's joints and
// each animation's target nodes. Materials it never meets are not read.
class AssimpOrder {
public:
    explicit AssimpOrder(const YAML::Node& root) : root_(root) {
        const YAML::Node scene = element(child(root, "scenes"), index_of(child(root, "scene")).value_or(0));
        for_indices(child(scene, "nodes"), [&](size_t n) { node(n); });
        for_elements(child(root, "skins"), [&](const YAML::Node& skin) {
            for_indices(child(skin, "joints"), [&](size_t n) { node(n); });
        });
        for_elements(child(root, "animations"), [&](const YAML::Node& animation) {
            for_elements(child(animation, "channels"), [&](const YAML::Node& channel) {
                if (const std::optional<size_t> n = index_of(child(child(channel, "target"), "node")))
                    node(*n);
            });
        });
    }
    const std::vector<size_t>& materials() const { return order_; }

private:
    static YAML::Node element(const YAML::Node& list, size_t i) {
        if (!list || !list.IsSequence() || i >= list.size()) return YAML::Node(YAML::NodeType::Undefined);
        const YAML::Node& l = list;
        return l[i];
    }
    static std::optional<size_t> index_of(const YAML::Node& n) {
        const std::optional<double> v = n && n.IsScalar() ? yaml::parse_number(n) : std::nullopt;
        if (!v || !(*v >= 0 && *v <= 1e9)) return std::nullopt;
        return size_t(*v);
    }
    // f(index) for each index in a list of them ("nodes": [0, 3]).
    template <class F>
    static void for_indices(const YAML::Node& list, F f) {
        if (!list || !list.IsSequence()) return;
        for (size_t i = 0; i < list.size(); ++i)
            if (const std::optional<size_t> v = index_of(element(list, i))) f(*v);
    }
    // f(element) for each element of a list of objects ("skins": [{...}]).
    template <class F>
    static void for_elements(const YAML::Node& list, F f) {
        if (!list || !list.IsSequence()) return;
        for (size_t i = 0; i < list.size(); ++i) f(element(list, i));
    }
    void node(size_t n) {
        if (!seen_nodes_.insert(n).second) return;
        const YAML::Node json = element(child(root_, "nodes"), n);
        for_indices(child(json, "children"), [&](size_t c) { node(c); });
        if (const std::optional<size_t> m = index_of(child(json, "mesh"))) mesh(*m);
    }
    void mesh(size_t m) {
        if (!seen_meshes_.insert(m).second) return;
        for_elements(child(element(child(root_, "meshes"), m), "primitives"), [&](const YAML::Node& p) {
            const std::optional<size_t> material = index_of(child(p, "material"));
            if (material && seen_materials_.insert(*material).second) order_.push_back(*material);
        });
    }

    const YAML::Node& root_;
    std::set<size_t> seen_nodes_, seen_meshes_, seen_materials_;
    std::vector<size_t> order_;
};

GltfMaterialExtensions read_material(const YAML::Node& json, size_t index, std::string& notes) {
    GltfMaterialExtensions m;
    if (const YAML::Node name = child(json, "name"); name && name.IsScalar()) m.name = name.Scalar();
    MaterialReader r(notes, m.name.empty() ? "#" + std::to_string(index) : m.name);
    const YAML::Node pbr = child(json, "pbrMetallicRoughness"), ext = child(json, "extensions");
    for (const char* key : {"baseColorTexture", "metallicRoughnessTexture"})
        r.transform(child(pbr, key), key, m);
    for (const char* key : {"normalTexture", "occlusionTexture", "emissiveTexture"})
        r.transform(child(json, key), key, m);
    const YAML::Node coat = child(ext, "KHR_materials_clearcoat");
    for (const char* key : {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"})
        r.transform(child(coat, key), key, m);
    const YAML::Node gloss = child(ext, "KHR_materials_pbrSpecularGlossiness");
    r.transform(child(gloss, "diffuseTexture"), "diffuseTexture", m);
    if (const YAML::Node e = child(ext, "KHR_materials_emissive_strength"))
        m.emissive_strength = r.number(child(e, "emissiveStrength"), "emissiveStrength", 1.0f, 0.0f, 1e6f);
    if (const YAML::Node e = child(ext, "KHR_materials_ior")) {
        // 0 is allowed: a Fresnel term of 1 (((0 - 1) / (0 + 1))^2 = 1).
        m.ior = r.number(child(e, "ior"), "ior", 1.5f, 0.0f, 1e6f);
        if (*m.ior > 0.0f && *m.ior < 1.0f) {
            r.note("ior " + std::to_string(*m.ior) + " is below 1 and not 0: 1.5 is used");
            m.ior = 1.5f;
        } else if (*m.ior > 10.0f) {
            r.note("ior " + std::to_string(*m.ior) + " is held to 10");
            m.ior = 10.0f;
        }
    }
    if (const YAML::Node e = child(ext, "KHR_materials_specular")) {
        m.specular = r.number(child(e, "specularFactor"), "specularFactor", 1.0f, 0.0f, 1.0f);
        if (const YAML::Node c = child(e, "specularColorFactor")) m.specular_color = r.colour(c, "specularColorFactor");
        m.specular_textures = child(e, "specularTexture") || child(e, "specularColorTexture");
    }
    return m;
}

}  // namespace

GltfMaterials read_gltf_materials(const std::filesystem::path& path) {
    GltfMaterials out;
    const std::string json = gltf_json_text(path);
    bool wanted = false;
    for (const char* name : kRead) wanted = wanted || json.find(std::string("\"") + name + "\"") != std::string::npos;
    if (!wanted) return out;
    try {
        const YAML::Node root = yaml::load_text(json, path.string());
        const YAML::Node materials = child(root, "materials");
        if (!materials || !materials.IsSequence()) return out;
        const std::vector<size_t> order = AssimpOrder(root).materials();  // a copy: the walk ends here
        for (const size_t i : order)
            out.materials.push_back(i < materials.size() ? read_material(materials[i], i, out.notes)
                                                         : GltfMaterialExtensions{});
    } catch (const Error& e) {
        if (e.code() == ErrorCode::over_budget) throw;
        out.materials.clear();
        out.notes += std::string("its JSON could not be read for the material extensions facet reads "
                                 "itself (KHR_texture_transform, KHR_materials_emissive_strength, ior "
                                 "and specular), which are left out: ") + e.what() + "\n";
    } catch (const YAML::Exception& e) {
        out.materials.clear();
        out.notes += std::string("its JSON could not be read for the material extensions facet reads "
                                 "itself, which are left out: ") + e.what() + "\n";
    }
    return out;
}

}  // namespace facet
