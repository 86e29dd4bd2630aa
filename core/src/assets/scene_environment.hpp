// A scene's `environment:` (facet/environment_map.hpp), read and loaded:
//
//     environment: sky.hdr                 # the short form: one image, both uses
//     environment:
//       file: sky.hdr                      # or faces: [px, nx, py, ny, pz, nz]
//       rotation: 90                       # degrees about Y, or [x, y, z]
//       intensity: 1.0
//       use: both                          # background, lighting or both
//       blur: 0.0                          # the background's roughness
//       size: 512                          # level 0's faces; default: the image's
//       samples: 64                        # GGX samples per texel
//
// Files are relative to the scene file. Errors are at the node, a file's
// own error moved into the detail.
#pragma once

#include "assets/yaml_util.hpp"

#include "facet/environment_map.hpp"

#include <filesystem>

namespace facet {

Environment read_environment(const yaml::Context& ctx, const YAML::Node& node,
                             const std::filesystem::path& folder);

}  // namespace facet
