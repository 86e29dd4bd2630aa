// Triangle meshes, loaded through assimp.
//
// A Mesh is indexed triangles with per-vertex attribute arrays. Positions are
// always present; the other arrays are either empty or as long as positions.
// load_mesh() triangulates, joins identical vertices, generates smooth
// normals where the file has none, and tangents (tangents.hpp) where it has
// texture coordinates but no tangents. Meshes are immutable once loaded and
// shared between objects.
//
// A mesh file keeps its parts: each of its meshes (a glTF primitive, an OBJ
// group per material) placed by its node is a MeshPart, a range of the
// triangles with its own vertices, drawn with its own material. The file's
// materials come along as ImportedMaterials (mesh_materials.cpp says how
// each format's are mapped); a scene draws a part with its imported
// material unless it names one (scene.hpp).
//
// A file with node animation (glTF) keeps the nodes that place its parts
// (Mesh::nodes) with their tracks; pose_parts() gives each part's motion
// from where the file puts it at rest, at a time.
#pragma once

#include "facet/animation.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace facet {

struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
};

// A material of a mesh file, as a facet material file would write it: a
// YAML map with the keys of a material file (material.hpp), its texture
// files relative to the mesh file's folder.
struct ImportedMaterial {
    std::string name;     // as the file names it ("" when it names none)
    std::string yaml;
    std::string notes;    // what the mapping left out, a line each, for a warning
    std::string problem;  // why it cannot be used, or "": an error when a part is drawn with it
};

// One part of a mesh: triangles [first_index / 3, (first_index +
// index_count) / 3), whose indices all lie in [first_vertex, first_vertex
// + vertex_count) (they index the whole mesh's arrays).
struct MeshPart {
    std::string name;          // the file's name for the part, unique in the mesh
    uint32_t first_index = 0;
    uint32_t index_count = 0;
    uint32_t first_vertex = 0;
    uint32_t vertex_count = 0;
    int material = -1;         // into Mesh::materials; -1: the file gives none
    Bounds bounds;             // of its vertices (load_mesh sets it; set it for parts made in code)
    int node = -1;             // into Mesh::nodes: the node that places it; -1: none moves it

    uint32_t triangle_count() const { return index_count / 3; }
};

// A node of a mesh file's hierarchy, kept when the file animates nodes.
struct MeshNode {
    std::string name;
    int parent = -1;        // into Mesh::nodes, before this one; -1: a root
    Transform rest;         // its place in its parent, as the file gives it
    TransformTracks tracks; // the file's animation of it (none: it stays at rest)
};

struct Mesh {
    std::string source;                // file it came from, for messages
    std::vector<glm::vec3> positions;  // object space
    std::vector<glm::vec3> normals;    // unit length
    std::vector<glm::vec2> uvs;
    std::vector<glm::vec4> colors;     // linear RGBA
    // Unit, perpendicular to the normal, pointing along +u; w = +1 or -1,
    // the handedness: the bitangent (along +v as the texture is drawn, that
    // is towards its top row) is cross(normal, tangent) * w, as glTF has it.
    std::vector<glm::vec4> tangents;
    std::vector<uint32_t> indices;     // three per triangle
    // Empty: the whole mesh is one part (whole_part()).
    std::vector<MeshPart> parts;
    std::vector<ImportedMaterial> materials;
    // Images embedded in the file (a .glb's, a data: URI's), as their image
    // files' bytes (PNG, JPEG, ...): an ImportedMaterial names image i as
    // the file "<this mesh file's name>#i" beside it (TextureCache::add_encoded).
    std::vector<std::shared_ptr<const std::string>> images;  // null: raw texels
    Bounds bounds;
    // Parents first. Empty unless the file animates its nodes; the vertices
    // are where the nodes put them at rest.
    std::vector<MeshNode> nodes;

    size_t vertex_count() const { return positions.size(); }
    size_t triangle_count() const { return indices.size() / 3; }
    size_t part_count() const { return parts.empty() ? 1 : parts.size(); }
    // Part i, or the whole mesh as one part when `parts` is empty.
    MeshPart part(size_t i) const { return parts.empty() ? whole_part() : parts[i]; }
    MeshPart whole_part() const;
    // The index of the part named `name`, or -1.
    int find_part(const std::string& name) const;
};

// How load_mesh() runs the importer.
enum class MeshImport {
    // In another process (facet-sandbox, in ../libexec beside the
    // program), limited to the memory budget (facet/memory.hpp) and to 30 s
    // plus 1 s per MiB of file: an importer that crashes, aborts, allocates
    // without bound or loops ends that process, and the load is an error
    // naming the file. The default; without facet-sandbox installed, it
    // imports in this process, with a warning.
    isolated,
    // In this process, unguarded: for callers that isolate it themselves,
    // and for the fuzzer (which must see the importer's coverage).
    in_process,
};

// Loads OBJ, glTF 2.0, PLY and the other formats assimp reads. All meshes in
// the file are merged into one, with their node transforms applied.
// Throws Error(file_not_found | not_a_file | mesh_load_failed | mesh_invalid);
// an OFF or PLY header that declares more than its file holds is
// mesh_load_failed before assimp allocates for it. Isolated, an import
// that needs more than the memory budget is Error(over_budget), and one
// that crashes or runs out of time is mesh_load_failed.
std::shared_ptr<const Mesh> load_mesh(const std::filesystem::path& path,
                                      MeshImport how = MeshImport::isolated);

// Checks the invariants above: array sizes, index range, finite positions,
// parts that tile the triangles in order and keep to their vertex ranges,
// material indices in range.
// Throws Error(mesh_invalid) naming the first problem.
void validate_mesh(const Mesh& mesh);

// Each part's motion at time t, from its place at rest to where its node's
// animation puts it (identity for a part no animated node moves), into
// `poses` (one per part). `mesh` has nodes.
void pose_parts(const Mesh& mesh, double t, std::vector<glm::mat4>& poses);
// When the mesh's node animation ends (0: it has none).
double animation_end(const Mesh& mesh);

// Recomputes bounds from positions.
Bounds compute_bounds(const std::vector<glm::vec3>& positions);

}  // namespace facet
