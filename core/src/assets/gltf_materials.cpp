// A glTF file's material extensions that assimp does not read
// (gltf_materials.hpp).
#include "assets/gltf_materials.hpp"

#include "assets/gltf_extensions.hpp"
#include "assets/yaml_util.hpp"
#include "facet/error.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
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
    if (const YAML::Node e = child(ext, "KHR_materials_emissive_strength"))
        m.emissive_strength = r.number(child(e, "emissiveStrength"), "emissiveStrength", 1.0f, 0.0f, 1e6f);
    if (const YAML::Node e = child(ext, "KHR_materials_ior"))
        m.ior = r.number(child(e, "ior"), "ior", 1.5f, 1.0f, 10.0f);
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
        for (size_t i = 0; i < materials.size(); ++i)
            out.materials.push_back(read_material(materials[i], i, out.notes));
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
