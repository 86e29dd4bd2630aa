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
//     none`. Samplers give each texture's wrap and filter, and
//     KHR_texture_transform its `transform:`. The clear coat, emissive
//     strength, ior and specular extensions give their parameters (what
//     assimp does not read comes from the file's JSON: gltf_materials.hpp).
//   - every other format (OBJ's .mtl first) goes to `phong`: Kd, Ks, Ns and
//     Ke, map_Kd as base_texture and a normal map (`norm`) as normal_texture.
// What has no counterpart (textures of a second UV set, transmission,
// OBJ's dissolve and bump maps, ...) is listed in ImportedMaterial::notes.
// A texture embedded in the file (a .glb's, a data: URI's) is named as
// Mesh::images says; one stored as raw texels, which glTF never does, makes
// the material unusable (ImportedMaterial::problem), not silently untextured.
#pragma once

#include "facet/mesh.hpp"

#include <filesystem>
#include <vector>

struct aiMaterial;
struct aiScene;

namespace facet {

struct GltfMaterials;

// Whether `path` names a format whose materials are glTF's metallic-roughness.
bool is_gltf(const std::filesystem::path& path);

// Material `index` of `scene`; `file` is the mesh file, whose name
// embedded images are named after. A material the file leaves unnamed is
// called "material #INDEX". A glTF file's `extensions` (read_gltf_materials)
// add what assimp does not read.
ImportedMaterial import_material(const aiScene& scene, unsigned index,
                                 const std::filesystem::path& file,
                                 const GltfMaterials* extensions = nullptr);

bool is_obj(const std::filesystem::path& path);

// assimp gives an OBJ whose material library is missing, or whose usemtl
// names a material no library defines, grey materials of those names: this
// gives each of them a problem (ImportedMaterial::problem) saying so.
void check_obj_libraries(const std::filesystem::path& obj, std::vector<ImportedMaterial>& materials);

// The images embedded in `scene`, by their index (Mesh::images); a raw one
// (not an image file) is null.
std::vector<std::shared_ptr<const std::string>> embedded_images(const aiScene& scene);

}  // namespace facet
