// What a glTF file's materials say in the extensions that assimp 5.2.5
// (Debian 12's) does not read, or not whole (private to the core; run where
// the importer runs).
//
// Takes: a .gltf file, or a GLB (its JSON chunk), of at most 64 MiB of JSON.
// Gives: for each material assimp reads, in assimp's order (the order its
// glTF reader first meets them in the default scene's nodes, then in skins
// and animations: mMaterials; its default material, added last, has none):
//   - KHR_materials_emissive_strength: the strength;
//   - KHR_materials_ior: the index of refraction;
//   - KHR_materials_specular: its factor and colour factor, and whether
//     it has textures (which facet does not read);
//   - KHR_texture_transform: the transform of each textureInfo that has
//     one, and the UV set it moves the texture to.
// The JSON is parsed (yaml-cpp reads JSON) only when extensionsUsed names
// one of these, within the memory budget. A value of the wrong type or
// range is replaced by its default, and said in `notes`.
#pragma once

#include "facet/texture.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace facet {

struct GltfTextureTransform {
    UvTransform transform;
    int tex_coord = -1;  // the transform's texCoord: the UV set it reads; -1: the textureInfo's
};

struct GltfMaterialExtensions {
    std::string name;
    float emissive_strength = 1.0f;
    std::optional<float> ior;
    std::optional<float> specular;
    std::optional<glm::vec3> specular_color;
    bool specular_textures = false;
    // By the textureInfo's key: "baseColorTexture", "metallicRoughnessTexture",
    // "normalTexture", "occlusionTexture", "emissiveTexture",
    // "clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture".
    std::map<std::string, GltfTextureTransform> transforms;
};

struct GltfMaterials {
    std::vector<GltfMaterialExtensions> materials;
    std::string notes;  // a line each: values replaced, or why the JSON was not read
};

GltfMaterials read_gltf_materials(const std::filesystem::path& path);

}  // namespace facet
