// A mesh file's materials as facet materials (private to the core; run
// where the importer runs, in facet-sandbox).
//
// Takes: one of assimp's materials, and the format it came from.
// Gives: an ImportedMaterial (mesh.hpp): the YAML of a facet material file
// that draws it. docs/MATERIALS.md is the user's table of the mapping:
//   - glTF 2.0 (.gltf, .glb) goes to the `pbr` shader: base colour and its
//     texture, metallic and roughness and their texture (roughness in G,
//     metallic in B), the normal texture and its scale, the occlusion
//     texture (R) and its strength, emissive colour and texture; alphaMode
//     MASK becomes alpha_cutoff, BLEND `blend: alpha`; doubleSided `cull:
//     none`. Samplers give each texture's wrap and filter.
//   - every other format (OBJ's .mtl first) goes to `phong`: Kd, Ks, Ns and
//     Ke, map_Kd as base_texture and a normal map (`norm`) as normal_texture.
// What has no counterpart (textures of a second UV set, transmission,
// OBJ's dissolve and bump maps, ...) is listed in ImportedMaterial::notes;
// a texture embedded in the file (a .glb's, a data: URI) makes the material
// unusable (ImportedMaterial::problem), not silently untextured.
#pragma once

#include "facet/mesh.hpp"

#include <filesystem>

struct aiMaterial;
struct aiScene;

namespace facet {

// Whether `path` names a format whose materials are glTF's metallic-roughness.
bool is_gltf(const std::filesystem::path& path);

ImportedMaterial import_material(const aiScene& scene, const aiMaterial& material, bool gltf);

}  // namespace facet
