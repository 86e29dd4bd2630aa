// A mesh file's node animation (private to the core): what import_mesh
// keeps of assimp's animations, and its checks.
#pragma once

#include "facet/mesh.hpp"

#include <vector>

struct aiNode;
struct aiScene;

namespace facet {

// Keeps the nodes of `scene` in Mesh::nodes, with the tracks of its first
// animation, and points each part at the node that places it (`placed_by`,
// in the parts' order). Keeps nothing when no animation moves a node.
void import_node_animation(const aiScene& scene, const std::vector<const aiNode*>& placed_by,
                           Mesh& mesh);

// Throws Error(mesh_invalid) unless every part's node and every node's
// parent is in range (parents first), and every track has a finite,
// increasing time and a finite value per key.
void validate_nodes(const Mesh& mesh);

}  // namespace facet
