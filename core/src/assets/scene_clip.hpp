// Which of a mesh file's own animations an object plays, and the morph
// weights a scene sets (private to the core):
//
//     animation: {clip: wave}          # the scene's default for every file with clips
//     objects:
//       - mesh: tentacle.gltf
//         animate: {clip: curl}        # a name, or an index from 0
//       - mesh: blob.gltf
//         animate: {clip: none, weights: {spikes: 0.8}}   # none: the file's rest
//
// A file with clips plays its first unless the object or the scene names
// another. Weights name morph targets of the file; they hold over the
// clip's and the file's own.
#pragma once

#include "assets/yaml_util.hpp"

#include "facet/mesh.hpp"

#include <vector>

namespace facet {

// The clip `node` names in `mesh` (-1 for `none`). Throws Error at the
// node, listing the file's clips, when it names none of them.
int read_clip(const yaml::Context& ctx, const YAML::Node& node, const Mesh& mesh);

// The clip an object plays: its own `animate: {clip}`, else the scene's
// `animation: {clip}` (`scene_clip`, or a null node), else the file's first
// (-1 when it has none).
int choose_clip(const yaml::Context& ctx, const YAML::Node& animate, const YAML::Node& scene_clip,
                const Mesh& mesh);

// `animate: {weights: {TARGET: w, ...}}`: each key a morph target of the
// mesh, each weight finite and within [-10, 10].
std::vector<WeightOverride> read_weights(const yaml::Context& ctx, const YAML::Node& node,
                                         const Mesh& mesh);

}  // namespace facet
