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
// (Mesh::nodes) and its clips (Mesh::clips, each with tracks for the nodes);
// pose_parts() gives each part's motion from where the file puts it at
// rest, at a time. A part that a skin or morph targets deform keeps the
// file's own vertices and what deforms them (PartDeformation), and
// pose_mesh() gives its vertices at a time.
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

// A node of a mesh file's hierarchy, kept when the file animates nodes or
// deforms a part.
struct MeshNode {
    std::string name;
    int parent = -1;        // into Mesh::nodes, before this one; -1: a root
    Transform rest;         // its place in its parent, as the file gives it
};

// A track of a part's morph-target weights: `targets` weights a key.
struct WeightsTrack {
    std::vector<double> times;  // seconds, strictly increasing
    std::vector<float> values;  // times.size() * targets
    Interpolation interpolation = Interpolation::linear;

    bool empty() const { return times.empty(); }
    double end() const { return times.empty() ? 0.0 : times.back(); }
    // The weights at time t, held before the first key and after the last,
    // into out[0, targets).
    void at(double t, size_t targets, float* out) const;
};

// One of a file's animations.
struct MeshClip {
    std::string name;                   // as the file names it, or "clip N"
    std::vector<TransformTracks> nodes; // one per Mesh::nodes (empty: it stays at rest)
    std::vector<WeightsTrack> weights;  // one per part (empty: its weights stay)

    double end() const;
    bool moves_nodes() const;
};

// A skin: the joints that deform a part, each with its inverse bind matrix
// (from the part's own space, as the file gives its vertices, to the
// joint's space at bind).
struct MeshSkin {
    std::string name;
    std::vector<int> joints;               // into Mesh::nodes
    std::vector<glm::mat4> inverse_binds;  // one per joint
};

// Up to 8 joints a vertex: indices into its skin's joints, weights summing
// to 1 in decreasing order; an unused slot has weight 0.
constexpr int kMaxJointsPerVertex = 8;
struct JointWeights {
    uint16_t joint[kMaxJointsPerVertex] = {};
    float weight[kMaxJointsPerVertex] = {};
};

// A morph target: offsets for each vertex of its part (normals and
// tangents are empty when the file gives it none: those stay).
struct MorphTarget {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec3> tangents;
};

// What deforms a part, and its vertices as the file gives them (in the
// part's own space, before any skin or morph). The mesh's arrays hold the
// part as pose_mesh() puts it at rest. A part without a skin is placed by
// its node's place at each time: so is one whose node's place at rest is
// singular (a scale of 0), which its motion could not be recovered from.
struct PartDeformation {
    int skin = -1;                      // into Mesh::skins; -1: no skin
    std::vector<glm::vec3> positions;   // one per vertex of the part; empty: it does not deform
    std::vector<glm::vec3> normals;
    std::vector<glm::vec4> tangents;    // empty when the mesh has none
    std::vector<JointWeights> joints;   // with a skin: one per vertex
    std::vector<MorphTarget> targets;
    std::vector<float> weights;         // one per target: its weight at rest

    bool deforms() const { return !positions.empty(); }
};

// A camera a mesh file holds, placed where its node puts it at rest, in
// the file's space.
struct MeshCamera {
    std::string name;
    glm::vec3 position{0.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit
    glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit
    bool orthographic = false;
    float fov_y = 45.0f;         // degrees, perspective
    float ortho_height = 2.0f;   // orthographic
    float near = 0.0f;           // 0: none given
    float far = 0.0f;            // 0: none given (glTF's infinite projection)
};

struct Mesh {
    std::string source;                // file it came from, for messages
    std::vector<glm::vec3> positions;  // object space
    std::vector<glm::vec3> normals;    // unit length
    std::vector<glm::vec2> uvs;
    std::vector<glm::vec2> uvs1;       // a second set (glTF's TEXCOORD_1), or none
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
    // What the import left out of the file or mended, a line each: load_mesh
    // warns of each.
    std::string notes;
    // Parents first. Empty unless the file animates its nodes or deforms a
    // part; the vertices are where the nodes put them at rest.
    std::vector<MeshNode> nodes;
    std::vector<MeshClip> clips;      // the file's animations, in its order
    std::vector<MeshSkin> skins;
    // One per part, or empty: no part deforms.
    std::vector<PartDeformation> deformations;
    std::vector<MeshCamera> cameras;  // the file's, in its order

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

// Each part's motion at time t in clip `clip` (-1: none, every node at
// rest), from its place at rest to where its node's animation puts it
// (identity for a part no animated node moves, and for a deformed part,
// which pose_mesh places), into `poses` (one per part). `mesh` has nodes.
void pose_parts(const Mesh& mesh, int clip, double t, std::vector<glm::mat4>& poses);
// When clip `clip` of the mesh ends (0: it has none).
double animation_end(const Mesh& mesh, int clip);
// The index of the clip named `name`, or -1.
int find_clip(const Mesh& mesh, const std::string& name);

// Morph weights a scene sets for a part's targets, over the file's.
struct WeightOverride {
    std::string target;  // a target's name
    float weight = 0.0f;
};

// The mesh's deformed parts posed at time t in clip `clip` (-1: at rest),
// with `weights` over the clip's and the file's morph weights: `out`
// becomes `mesh` with those parts' positions, normals and tangents
// replaced, and its bounds and their parts' bounds made again. Linear
// blend skinning, in float, the same on every ISA path and thread count.
void pose_mesh(const Mesh& mesh, int clip, double t, const std::vector<WeightOverride>& weights,
               Mesh& out);

// Recomputes bounds from positions.
Bounds compute_bounds(const std::vector<glm::vec3>& positions);

}  // namespace facet
