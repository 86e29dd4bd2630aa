// Materials from YAML nodes (private to the core): the part of
// load_material() that scenes share for their inline materials.
#pragma once

#include "facet/material.hpp"
#include "facet/mesh.hpp"
#include "assets/yaml_util.hpp"

#include <filesystem>
#include <memory>
#include <string>

namespace facet {

// One parameter value as written: a number, a boolean, 1..4 numbers, a
// name, or a texture (a file name or a map); texture files resolve against
// `folder`.
MaterialParam parse_param(const yaml::Context& ctx, const std::string& name,
                          const YAML::Node& value, const std::filesystem::path& folder);

// A material's `blend:`: a named mode (opaque, alpha, additive,
// premultiplied, multiply) or a map of GL's factors and equations (src,
// dst, op, and src_alpha, dst_alpha, op_alpha, which default to the
// colour's, and a constant colour), into m.blend and m.blend_func.
void parse_blend(const yaml::Context& ctx, const YAML::Node& node, Material& m);

// A material's `stencil:`, into m.stencil (on): a map of GL's test (test:
// never, less, less_equal, greater, greater_equal, equal, not_equal,
// always; ref; read_mask) and operations (fail, depth_fail, pass: keep,
// zero, replace, increment, increment_wrap, decrement, decrement_wrap,
// invert; write_mask), and `back:`, the same keys for back faces over the
// front's (stencil_yaml.cpp).
void parse_stencil(const yaml::Context& ctx, const YAML::Node& node, Material& m);

// Parses `node` (a map with the keys of a material file) and binds it to its
// shader from `registry`. Relative texture files resolve against `folder`;
// `source` becomes Material::source. Errors name ctx.file and the line in it.
std::shared_ptr<Material> material_from_yaml(const yaml::Context& ctx, const YAML::Node& node,
                                             const std::filesystem::path& folder,
                                             std::string source, PluginRegistry& registry,
                                             TextureCache& cache);

// A mesh file's material (ImportedMaterial::yaml), bound. Its texture
// files resolve against `folder`, the mesh file's; `source` (the mesh file
// and the material's name) is what errors name, with no line: the YAML is
// facet's, not the user's.
std::shared_ptr<Material> imported_material(const ImportedMaterial& material,
                                            const std::string& source,
                                            const std::filesystem::path& folder,
                                            PluginRegistry& registry, TextureCache& cache);

}  // namespace facet
