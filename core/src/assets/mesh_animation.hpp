// A mesh file's animation (private to the core): what import_mesh keeps of
// assimp's nodes, clips, skins and morph targets, its checks, and where a
// clip puts the nodes.
#pragma once

#include "facet/error.hpp"
#include "facet/mesh.hpp"

#include <glm/glm.hpp>

#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

struct aiMesh;
struct aiNode;
struct aiScene;

namespace facet {

// The nodes of a file being imported: Mesh::nodes, and how to find them.
struct NodeIndex {
    std::unordered_map<const aiNode*, int> by_node;
    std::unordered_map<std::string, int> by_name;  // the first node of each name
    std::unordered_set<std::string> ambiguous;     // names more than one node has
};

// Error(mesh_invalid) naming the mesh's file.
inline Error mesh_invalid(const Mesh& mesh, const std::string& problem) {
    return Error(ErrorCode::mesh_invalid, problem, mesh.source);
}

// Whether the file animates or deforms anything: then import_mesh keeps
// its nodes.
bool has_animation(const aiScene& scene);

// Keeps the nodes of `scene` in Mesh::nodes, parents first.
NodeIndex import_nodes(const aiScene& scene, Mesh& mesh);

// Keeps each of the file's animations as a clip (node tracks, and morph
// weights for the parts whose nodes they name), and points each part at the
// node that places it (`placed_by`, in the parts' order). Lines for what
// it leaves out or mends go to mesh.notes.
void import_clips(const aiScene& scene, const std::vector<const aiNode*>& placed_by,
                  const NodeIndex& nodes, Mesh& mesh);

// The deformation of a part made of `src` (its skin goes to mesh.skins),
// given the part's vertices as the file gives them (`raw`: positions,
// normals, tangents, in the part's own space). Weights
// past 8 a vertex, or that do not sum to 1, are mended with a line in
// mesh.notes; a weight that is not finite, or a joint the file has no node
// for, is Error(mesh_invalid).
PartDeformation import_deformation(const aiMesh& src, const Mesh& raw,
                                   const NodeIndex& nodes, Mesh& mesh);

// Throws Error(mesh_invalid) unless every part's node and every node's
// parent is in range (parents first), every track has a finite, increasing
// time and a finite value per key, and every skin, influence, morph target
// and weight track fits the part and skin it belongs to.
void validate_nodes(const Mesh& mesh);

// The skins' and deformations' part of validate_nodes.
void validate_deformations(const Mesh& mesh);

// Each node's place in the file's space at time t of clip `clip` (-1: at
// rest), in double.
void place_nodes(const Mesh& mesh, int clip, double t, std::vector<glm::dmat4>& places);

}  // namespace facet
