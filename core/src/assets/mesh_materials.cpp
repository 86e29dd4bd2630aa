// A mesh file's materials as facet materials (mesh_materials.hpp).
#include "assets/mesh_materials.hpp"

#include "assets/gltf_materials.hpp"

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/texture.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <functional>
#include <unordered_set>
#include <optional>
#include <string>

namespace facet {

namespace {

// One texture of a material, as the YAML of a texture parameter.
struct TextureRef {
    std::string file;
    std::string filter = "trilinear";
    std::string wrap = "repeat";
    UvTransform transform;
    int uv_set = 0;
};

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

class Mapper {
public:
    Mapper(const aiScene& scene, const aiMaterial& m, std::string file_name, unsigned index,
           const GltfMaterialExtensions* extensions)
        : scene_(scene), m_(m), file_name_(std::move(file_name)), extensions_(extensions) {
        aiString name;
        if (m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) out_.name = name.C_Str();
        if (out_.name.empty()) out_.name = "material #" + std::to_string(index);
    }

    std::optional<float> number(const char* key, unsigned type, unsigned index) const {
        float v = 0.0f;
        if (m_.Get(key, type, index, v) == AI_SUCCESS) return v;
        return std::nullopt;
    }
    std::optional<aiColor4D> color(const char* key, unsigned type, unsigned index) const {
        aiColor4D c;
        if (m_.Get(key, type, index, c) == AI_SUCCESS) return c;
        return std::nullopt;
    }

    // Texture `index` of `type`, or nothing; `key` names its glTF
    // textureInfo, whose KHR_texture_transform places it. Notes what cannot
    // be honoured.
    std::optional<TextureRef> texture(aiTextureType type, const char* what, const char* key = nullptr,
                                      unsigned which = 0) {
        if (m_.GetTextureCount(type) <= which) return std::nullopt;
        aiString path;
        aiTextureMapMode mode[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
        unsigned uv_set = 0;
        if (m_.GetTexture(type, which, &path, nullptr, &uv_set, nullptr, nullptr, mode) != AI_SUCCESS)
            return std::nullopt;
        const GltfTextureTransform* placed = transform_of(key);
        if (placed && placed->tex_coord >= 0) uv_set = unsigned(placed->tex_coord);
        std::string file = path.C_Str();
        if (file.empty()) return std::nullopt;
        if (const auto [embedded, index] = scene_.GetEmbeddedTextureAndIndex(path.C_Str());
            embedded) {
            if (embedded->mHeight != 0) {  // raw texels, not an image file
                if (out_.problem.empty())
                    out_.problem = "its " + std::string(what) +
                                   " is embedded as raw texels, which facet does not read: name "
                                   "a material for these parts in the scene";
                return std::nullopt;
            }
            file = file_name_ + "#" + std::to_string(index);
        }
        if (uv_set > (second_uv_ ? 1u : 0u)) {
            note(std::string(what) + " reads texture coordinates set " + std::to_string(uv_set) +
                 (second_uv_ ? ", and facet has two: left out"
                             : ", and this material's shader reads only the first: left out"));
            return std::nullopt;
        }
        TextureRef t;
        t.file = file;
        t.uv_set = int(uv_set);
        if (placed) t.transform = placed->transform;
        std::replace(t.file.begin(), t.file.end(), '\\', '/');  // OBJ files from Windows
        switch (mode[0]) {
            case aiTextureMapMode_Clamp:
            case aiTextureMapMode_Decal: t.wrap = "clamp"; break;
            case aiTextureMapMode_Mirror: t.wrap = "mirror"; break;
            default: break;
        }
        if (mode[1] != mode[0]) note(std::string(what) + " wraps u and v differently; facet uses u's way for both");
        // glTF samplers: 9728 NEAREST, 9729 LINEAR, 9984.. the mipmapped ones.
        unsigned min_filter = 0;
        if (m_.Get(AI_MATKEY_GLTF_MAPPINGFILTER_MIN(type, which), min_filter) == AI_SUCCESS) {
            if (min_filter == 9728) t.filter = "nearest";
            else if (min_filter == 9729) t.filter = "bilinear";
        }
        return t;
    }

    void note(const std::string& line) { out_.notes += line + "\n"; }

    void param(const char* name, double v) { params_.push_back({name, [v](YAML::Emitter& e) { e << v; }}); }
    void param(const char* name, bool v) { params_.push_back({name, [v](YAML::Emitter& e) { e << v; }}); }
    void param(const char* name, std::initializer_list<double> v) {
        std::vector<double> values(v);
        params_.push_back({name, [values](YAML::Emitter& e) {
                               e << YAML::Flow << YAML::BeginSeq;
                               for (double x : values) e << x;
                               e << YAML::EndSeq;
                           }});
    }
    void param(const char* name, const TextureRef& t) {
        params_.push_back({name, [t](YAML::Emitter& e) {
                               e << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
                                 << YAML::Value << t.file << YAML::Key << "filter"
                                 << YAML::Value << t.filter << YAML::Key << "wrap" << YAML::Value
                                 << t.wrap;
                               if (!t.transform.identity()) emit(e, t.transform);
                               if (t.uv_set != 0) e << YAML::Key << "uv_set" << YAML::Value << t.uv_set;
                               e << YAML::EndMap;
                           }});
    }
    static void emit(YAML::Emitter& e, const UvTransform& t) {
        e << YAML::Key << "transform" << YAML::Value << YAML::BeginMap;
        e << YAML::Key << "offset" << YAML::Value << YAML::BeginSeq << t.offset.x << t.offset.y << YAML::EndSeq;
        e << YAML::Key << "rotation" << YAML::Value << t.rotation;
        e << YAML::Key << "scale" << YAML::Value << YAML::BeginSeq << t.scale.x << t.scale.y << YAML::EndSeq;
        e << YAML::EndMap;
    }
    // What the file's JSON says that assimp does not read, or null.
    const GltfMaterialExtensions* extensions() const { return extensions_; }
    // Whether the material's shader has a second UV set (pbr does), so that
    // its textures may read it.
    void allow_second_uv() { second_uv_ = true; }

    ImportedMaterial finish(const std::string& shader, const std::string& blend, bool two_sided) {
        YAML::Emitter e;
        e.SetDoublePrecision(6);
        e << YAML::BeginMap << YAML::Key << "shader" << YAML::Value << shader;
        if (!blend.empty()) e << YAML::Key << "blend" << YAML::Value << blend;
        if (two_sided) e << YAML::Key << "cull" << YAML::Value << "none";
        e << YAML::Key << "params" << YAML::Value << YAML::BeginMap;
        for (const auto& [name, write] : params_) {
            e << YAML::Key << name << YAML::Value;
            write(e);
        }
        e << YAML::EndMap << YAML::EndMap;
        out_.yaml = std::string(e.c_str()) + "\n";
        return out_;
    }

    std::optional<std::string> text(const char* key, unsigned type, unsigned index) const {
        aiString s;
        if (m_.Get(key, type, index, s) == AI_SUCCESS) return std::string(s.C_Str());
        return std::nullopt;
    }
    bool has_texture(aiTextureType type, unsigned index = 0) const { return m_.GetTextureCount(type) > index; }
    bool integer(const char* key, unsigned type, unsigned index, int& out) const {
        return m_.Get(key, type, index, out) == AI_SUCCESS;
    }

    bool flag(const char* key, unsigned type, unsigned index) const {
        int v = 0;
        return m_.Get(key, type, index, v) == AI_SUCCESS && v != 0;
    }

private:
    const GltfTextureTransform* transform_of(const char* key) const {
        if (!extensions_ || !key) return nullptr;
        const auto it = extensions_->transforms.find(key);
        return it == extensions_->transforms.end() ? nullptr : &it->second;
    }

    const aiScene& scene_;
    const aiMaterial& m_;
    const std::string file_name_;
    const GltfMaterialExtensions* extensions_;
    bool second_uv_ = false;
    ImportedMaterial out_;
    std::vector<std::pair<std::string, std::function<void(YAML::Emitter&)>>> params_;
};

double clamp01(float v) { return std::clamp(double(v), 0.0, 1.0); }

// KHR_materials_clearcoat, as assimp reads it: a coat of index 1.5 over
// the base, its strength and roughness times the R and G of their textures.
void gltf_clearcoat(Mapper& m) {
    const float coat = std::clamp(m.number(AI_MATKEY_CLEARCOAT_FACTOR).value_or(0.0f), 0.0f, 1.0f);
    if (!(coat > 0.0f)) return;  // and NaN: no coat
    m.param("clearcoat", double(coat));
    m.param("clearcoat_roughness", clamp01(m.number(AI_MATKEY_CLEARCOAT_ROUGHNESS_FACTOR).value_or(0.0f)));
    if (auto t = m.texture(aiTextureType_CLEARCOAT, "clear coat texture", "clearcoatTexture", 0))
        m.param("clearcoat_texture", *t);
    if (auto t = m.texture(aiTextureType_CLEARCOAT, "clear coat roughness texture",
                           "clearcoatRoughnessTexture", 1))
        m.param("clearcoat_roughness_texture", *t);
    if (m.has_texture(aiTextureType_CLEARCOAT, 2))
        m.note("a clear coat normal texture (KHR_materials_clearcoat) is left out: the coat "
               "follows the surface's interpolated normal");
}

// KHR_materials_ior and KHR_materials_specular (read from the file's JSON):
// a dielectric's reflectance at normal incidence, ((ior - 1) / (ior + 1))^2
// times the specular colour, and its weight.
void gltf_specular(Mapper& m) {
    const GltfMaterialExtensions* x = m.extensions();
    if (!x) return;
    if (x->ior) m.param("ior", double(*x->ior));
    if (x->specular) m.param("specular", double(*x->specular));
    if (x->specular_color) {  // above 1 too: pbr holds its product with f0 to 1, as the extension does
        const glm::vec3 c = *x->specular_color;
        m.param("specular_color", {c.r, c.g, c.b});
    }
    if (x->specular_textures)
        m.note("KHR_materials_specular's specularTexture and specularColorTexture are left out: "
               "its factors are drawn");
}

// KHR_materials_unlit: the base colour alone, as `unlit` draws it.
ImportedMaterial gltf_unlit(Mapper& m, const aiColor4D& base) {
    m.param("base_color", {base.r, base.g, base.b, base.a});
    if (auto t = m.texture(aiTextureType_BASE_COLOR, "base colour texture", "baseColorTexture"))
        m.param("base_texture", *t);
    const std::string mode = m.text(AI_MATKEY_GLTF_ALPHAMODE).value_or("OPAQUE");
    if (mode == "MASK")
        m.param("alpha_cutoff", clamp01(m.number(AI_MATKEY_GLTF_ALPHACUTOFF).value_or(0.5f)));
    return m.finish("unlit", mode == "BLEND" ? "alpha" : "", m.flag(AI_MATKEY_TWOSIDED));
}

ImportedMaterial gltf_material(Mapper& m) {
    aiColor4D base = m.color(AI_MATKEY_BASE_COLOR).value_or(aiColor4D(1.0f, 1.0f, 1.0f, 1.0f));
    int shading = 0;
    if (m.integer(AI_MATKEY_SHADING_MODEL, shading) && shading == aiShadingMode_Unlit)
        return gltf_unlit(m, base);
    // KHR_materials_pbrSpecularGlossiness: its diffuse as the base colour of
    // a dielectric as rough as it is not glossy.
    const std::optional<float> glossiness = m.number(AI_MATKEY_GLOSSINESS_FACTOR);
    if (glossiness) {
        base = m.color(AI_MATKEY_COLOR_DIFFUSE).value_or(base);
        m.note("a specular-glossiness material (KHR_materials_pbrSpecularGlossiness) is drawn as "
               "metallic-roughness: its diffuse colour and texture as the base, metallic 0, "
               "roughness 1 - glossiness; its specular colour and texture are left out");
    }
    m.allow_second_uv();
    m.param("base_color", {base.r, base.g, base.b, base.a});
    std::optional<TextureRef> base_texture =
        m.texture(aiTextureType_BASE_COLOR, "base colour texture", "baseColorTexture");
    if (!base_texture && glossiness)
        base_texture = m.texture(aiTextureType_DIFFUSE, "diffuse texture", "diffuseTexture");
    if (base_texture) m.param("base_texture", *base_texture);
    m.param("metallic", glossiness ? 0.0 : clamp01(m.number(AI_MATKEY_METALLIC_FACTOR).value_or(1.0f)));
    m.param("roughness", glossiness ? clamp01(1.0f - *glossiness)
                                    : clamp01(m.number(AI_MATKEY_ROUGHNESS_FACTOR).value_or(1.0f)));
    if (!glossiness) {
        const char* key = "metallicRoughnessTexture";
        std::optional<TextureRef> mr = m.texture(aiTextureType_UNKNOWN, "metallic-roughness texture", key);
        if (!mr) mr = m.texture(aiTextureType_METALNESS, "metallic-roughness texture", key);
        if (mr) m.param("metallic_roughness_texture", *mr);
    }
    if (auto t = m.texture(aiTextureType_NORMALS, "normal texture", "normalTexture")) {
        m.param("normal_texture", *t);
        if (t->uv_set != 0 || t->transform.rotation != 0.0f ||
            t->transform.scale.x * t->transform.scale.y < 0.0f)
            m.note("the normal texture reads a second UV set, or turns or mirrors its UVs: its "
                   "tangent frame still follows the first set as the file places it, so its "
                   "bumps may lean the wrong way");
        // pbr takes -16 .. 16: far past what any map means.
        const float scale = m.number(AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0)).value_or(1.0f);
        const double clamped = std::isfinite(scale) ? std::clamp(double(scale), -16.0, 16.0) : 1.0;
        if (clamped != double(scale)) m.note("normal texture scale " + std::to_string(scale) + " taken as " + std::to_string(clamped));
        m.param("normal_scale", clamped);
    }
    if (auto t = m.texture(aiTextureType_LIGHTMAP, "occlusion texture", "occlusionTexture")) {
        m.param("occlusion_texture", *t);
        m.param("occlusion_strength",
                clamp01(m.number(AI_MATKEY_GLTF_TEXTURE_STRENGTH(aiTextureType_LIGHTMAP, 0)).value_or(1.0f)));
    }
    // KHR_materials_emissive_strength scales the emissive factor (assimp
    // 5.2.5, Debian 12's, does not read it: the file's JSON is read for it).
    const aiColor4D emissive = m.color(AI_MATKEY_COLOR_EMISSIVE).value_or(aiColor4D(0.0f, 0.0f, 0.0f, 1.0f));
    const float strength = m.extensions() ? m.extensions()->emissive_strength : 1.0f;
    m.param("emissive", {emissive.r * strength, emissive.g * strength, emissive.b * strength});
    if (auto t = m.texture(aiTextureType_EMISSIVE, "emissive texture", "emissiveTexture"))
        m.param("emissive_texture", *t);
    gltf_clearcoat(m);
    gltf_specular(m);

    // OPAQUE ignores alpha, and what MASK keeps is opaque: both write alpha 1.
    const std::string mode = m.text(AI_MATKEY_GLTF_ALPHAMODE).value_or("OPAQUE");
    std::string blend;
    if (mode == "MASK")
        m.param("alpha_cutoff", clamp01(m.number(AI_MATKEY_GLTF_ALPHACUTOFF).value_or(0.5f)));
    if (mode == "BLEND") blend = "alpha";
    else m.param("opaque_alpha", true);
    return m.finish("pbr", blend, m.flag(AI_MATKEY_TWOSIDED));
}

ImportedMaterial classic_material(Mapper& m) {
    const aiColor4D kd = m.color(AI_MATKEY_COLOR_DIFFUSE).value_or(aiColor4D(0.6f, 0.6f, 0.6f, 1.0f));
    const aiColor4D ks = m.color(AI_MATKEY_COLOR_SPECULAR).value_or(aiColor4D(0.0f, 0.0f, 0.0f, 1.0f));
    const aiColor4D ke = m.color(AI_MATKEY_COLOR_EMISSIVE).value_or(aiColor4D(0.0f, 0.0f, 0.0f, 1.0f));
    m.param("diffuse", {kd.r, kd.g, kd.b});
    m.param("specular", {ks.r, ks.g, ks.b});
    m.param("emission", {ke.r, ke.g, ke.b});
    // Ns is 0..1000 in MTL; phong takes 1 .. 10000.
    m.param("shininess", std::clamp(double(m.number(AI_MATKEY_SHININESS).value_or(32.0f)), 1.0, 10000.0));
    if (auto t = m.texture(aiTextureType_DIFFUSE, "diffuse texture (map_Kd)")) m.param("base_texture", *t);
    if (auto t = m.texture(aiTextureType_NORMALS, "normal map (norm)")) m.param("normal_texture", *t);
    if (m.has_texture(aiTextureType_HEIGHT))
        m.note("a bump map (bump, map_bump) is a height map, which facet does not read: left out; "
               "a normal map (norm) is read");
    if (m.has_texture(aiTextureType_SPECULAR)) m.note("a specular map (map_Ks): left out");
    if (m.has_texture(aiTextureType_OPACITY)) m.note("an alpha map (map_d): left out");
    if (m.number(AI_MATKEY_OPACITY).value_or(1.0f) < 1.0f)
        m.note("dissolve (d, Tr) below 1: drawn opaque; name a blended material for it in the scene");
    return m.finish("phong", "", m.flag(AI_MATKEY_TWOSIDED));
}

}  // namespace

bool is_gltf(const std::filesystem::path& path) {
    const std::string ext = lower(path.extension().string());
    return ext == ".gltf" || ext == ".glb";
}

bool is_obj(const std::filesystem::path& path) { return lower(path.extension().string()) == ".obj"; }

namespace {

std::string trimmed(const std::string& s) {
    const size_t first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return {};
    return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// The rest of `line` after keyword `key` and a blank, or nothing.
std::optional<std::string> after(const std::string& line, std::string_view key) {
    const std::string t = trimmed(line);
    if (t.size() <= key.size() || t.compare(0, key.size(), key) != 0 ||
        (t[key.size()] != ' ' && t[key.size()] != '\t'))
        return std::nullopt;
    return trimmed(t.substr(key.size()));
}

}  // namespace

void check_obj_libraries(const std::filesystem::path& obj, std::vector<ImportedMaterial>& materials) {
    std::vector<std::string> missing;
    std::unordered_set<std::string> defined;
    std::ifstream in(obj);
    for (std::string line; std::getline(in, line);) {
        const std::optional<std::string> library = after(line, "mtllib");
        if (!library) continue;
        const std::filesystem::path file = obj.parent_path() / *library;
        std::ifstream mtl(file);
        if (!mtl) {
            missing.push_back(*library);
            continue;
        }
        for (std::string entry; std::getline(mtl, entry);)
            if (const std::optional<std::string> name = after(entry, "newmtl")) defined.insert(*name);
    }
    for (ImportedMaterial& m : materials) {
        if (m.name == AI_DEFAULT_MATERIAL_NAME || !m.problem.empty() || defined.count(m.name)) continue;
        m.problem = missing.empty()
                        ? "usemtl names it, and no material library (mtllib) of the file defines it"
                        : "its material library '" + missing.front() +
                              "' was not found beside the file";
    }
}

ImportedMaterial import_material(const aiScene& scene, unsigned index,
                                 const std::filesystem::path& file, const GltfMaterials* extensions) {
    // In assimp's order (read_gltf_materials); a name that differs means
    // the order was not found, and nothing is taken rather than another's.
    const GltfMaterialExtensions* x =
        extensions && index < extensions->materials.size() ? &extensions->materials[index] : nullptr;
    aiString name;
    if (x && scene.mMaterials[index]->Get(AI_MATKEY_NAME, name) == AI_SUCCESS &&
        std::string(name.C_Str()) != x->name)
        x = nullptr;
    Mapper m(scene, *scene.mMaterials[index], file.filename().string(), index, x);
    if (extensions && !extensions->materials.empty() && index < extensions->materials.size() && !x)
        m.note("its place among the file's materials was not found: its texture transforms, "
               "emissive strength, ior and specular are left out");
    return is_gltf(file) ? gltf_material(m) : classic_material(m);
}

std::vector<std::shared_ptr<const std::string>> embedded_images(const aiScene& scene) {
    std::vector<std::shared_ptr<const std::string>> images(scene.mNumTextures);
    for (unsigned i = 0; i < scene.mNumTextures; ++i) {
        const aiTexture& t = *scene.mTextures[i];
        if (t.mHeight == 0 && t.pcData)
            images[i] = std::make_shared<const std::string>(
                reinterpret_cast<const char*>(t.pcData), t.mWidth);
    }
    return images;
}

}  // namespace facet
