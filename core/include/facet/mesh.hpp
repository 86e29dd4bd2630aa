// Triangle meshes, loaded through assimp.
//
// A Mesh is indexed triangles with per-vertex attribute arrays. Positions are
// always present; the other arrays are either empty or as long as positions.
// load_mesh() triangulates, joins identical vertices, and generates smooth
// normals where the file has none. Meshes are immutable once loaded and
// shared between objects.
#pragma once

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

struct Mesh {
    std::string source;                // file it came from, for messages
    std::vector<glm::vec3> positions;  // object space
    std::vector<glm::vec3> normals;    // unit length
    std::vector<glm::vec2> uvs;
    std::vector<glm::vec4> colors;     // linear RGBA
    std::vector<uint32_t> indices;     // three per triangle
    Bounds bounds;

    size_t vertex_count() const { return positions.size(); }
    size_t triangle_count() const { return indices.size() / 3; }
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

// Checks the invariants above: array sizes, index range, finite positions.
// Throws Error(mesh_invalid) naming the first problem.
void validate_mesh(const Mesh& mesh);

// Recomputes bounds from positions.
Bounds compute_bounds(const std::vector<glm::vec3>& positions);

}  // namespace facet
