// A glTF file's `extensionsUsed`, and what facet does with each extension.
#include "assets/gltf_extensions.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string_view>
#include <utility>

namespace facet {

namespace {

// Past this the JSON is not read for its extensions (a .gltf with its
// buffers inline in base64 can be hundreds of MiB).
constexpr uint64_t kMaxJson = 64ull << 20;

}  // namespace

std::string gltf_json_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    char header[20] = {};
    if (!in.read(header, sizeof header)) return {};
    uint32_t length = 0;
    if (std::memcmp(header, "glTF", 4) == 0) {
        std::memcpy(&length, header + 12, 4);
        if (std::memcmp(header + 16, "JSON", 4) != 0 || length > kMaxJson) return {};
    } else {
        in.seekg(0, std::ios::end);
        const std::streamoff size = in.tellg();
        if (size < 0 || uint64_t(size) > kMaxJson) return {};
        length = uint32_t(size);
        in.seekg(0);
    }
    std::string text(length, '\0');
    in.read(text.data(), std::streamsize(length));
    text.resize(size_t(in.gcount()));
    return text;
}

namespace {

// The strings of the JSON array that follows `"key"` and a colon, or none.
std::vector<std::string> string_array(std::string_view json, std::string_view key) {
    std::vector<std::string> out;
    const std::string quoted = "\"" + std::string(key) + "\"";
    size_t at = json.find(quoted);
    if (at == std::string_view::npos) return out;
    at = json.find_first_not_of(" \t\r\n", at + quoted.size());
    if (at == std::string_view::npos || json[at] != ':') return out;
    at = json.find_first_not_of(" \t\r\n", at + 1);
    if (at == std::string_view::npos || json[at] != '[') return out;
    for (++at; at < json.size() && json[at] != ']'; ++at) {
        if (json[at] != '"') continue;
        const size_t end = json.find('"', at + 1);  // extension names have no escapes
        if (end == std::string_view::npos) break;
        out.emplace_back(json.substr(at + 1, end - at - 1));
        at = end;
    }
    return out;
}

// What facet draws of each: what assimp 5.2.5 (Debian 12's) reads, and
// what facet reads itself (gltf_materials.hpp). What a material leaves out
// of one that is drawn (a clear coat's normal texture, a texture of a
// second UV set, ...) is said for that material.
constexpr std::pair<const char*, const char*> kUses[] = {
    {"KHR_materials_unlit", "drawn"},
    {"KHR_draco_mesh_compression", "drawn"},
    {"KHR_mesh_quantization", "drawn"},
    {"KHR_xmp_json_ld", "drawn"},
    {"KHR_materials_pbrSpecularGlossiness",
     "approximated: as metallic-roughness (its diffuse as the base, roughness 1 - glossiness)"},
    {"KHR_texture_transform", "drawn"},
    {"KHR_materials_emissive_strength", "drawn"},
    {"KHR_materials_clearcoat", "drawn"},
    {"KHR_materials_sheen", "left out: no sheen is drawn"},
    {"KHR_materials_transmission", "left out: the surface is drawn opaque"},
    {"KHR_materials_volume", "left out: the surface is drawn without its volume"},
    {"KHR_materials_ior", "drawn"},
    {"KHR_materials_specular", "drawn"},
    {"KHR_materials_iridescence", "left out: no iridescence is drawn"},
    {"KHR_materials_anisotropy", "left out: highlights are isotropic"},
    {"KHR_materials_variants", "left out: the default materials are drawn"},
    {"KHR_lights_punctual", "left out: the scene's lights light the model"},
    {"KHR_texture_basisu", "left out: KTX2 images cannot be decoded"},
    {"EXT_texture_webp", "left out: WebP images cannot be decoded"},
    {"EXT_meshopt_compression", "left out: the importer cannot decode it"},
    {"EXT_mesh_gpu_instancing", "left out: each mesh is drawn once, not per instance"},
};

}  // namespace

std::optional<std::vector<std::string>> gltf_extensions_used(const std::filesystem::path& path) {
    const std::string json = gltf_json_text(path);
    if (json.empty()) return std::nullopt;
    return string_array(json, "extensionsUsed");
}

std::string gltf_extension_use(const std::string& name) {
    for (const auto& [known, use] : kUses)
        if (name == known) return use;
    return "left out: facet does not know it";
}

}  // namespace facet
