// Fuzz target: mesh import, load_mesh() (core/src/assets/mesh.cpp: assimp, with
// core/src/assets/ply_check.cpp and off_check.cpp in front of assimp's PLY
// and OFF readers).
//
// The first byte picks the file's extension (kExtensions, by its value
// modulo 8), so one target covers the formats: 'o' makes it .obj, 'p' .ply,
// 'a' .off, 'b' .stl, 'c' .gltf, 'd' .glb, 'e' .dae, 'f' .3ds. The rest is
// the file, written to the sandbox (support.hpp). assimp chooses the reader
// by extension first, then by content, so any name can reach any reader.
// The import runs in this process (MeshImport::in_process), where libFuzzer
// sees its coverage; facet's programs run it in facet-sandbox, which
// turns the importer's crashes into errors.
//
// Checks:
//  - load_mesh() returns a mesh or throws facet::Error with one of the ids
//    mesh.hpp documents (file_not_found, mesh_load_failed, mesh_invalid);
//    any other exception is a finding;
//  - a mesh that loaded keeps mesh.hpp's invariants, checked here on their
//    own rather than through validate_mesh(): indexed triangles whose
//    indices are in range, finite positions, one unit-length normal per
//    vertex (generated where the file has none), UV and colour arrays empty
//    or one per vertex, and bounds that are exactly the positions' extent.
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/mesh.hpp>

#include <cmath>
#include <string>
#include <string_view>

namespace facet::fuzz {

namespace {

void check_arrays(const Mesh& m) {
    const size_t n = m.positions.size();
    check(n > 0 && !m.indices.empty() && m.indices.size() % 3 == 0,
          "a loaded mesh has no vertices, no triangles, or a partial triangle");
    check(m.normals.size() == n, "a loaded mesh lacks normals");
    check(m.uvs.empty() || m.uvs.size() == n, "a loaded mesh has a partial UV array");
    check(m.colors.empty() || m.colors.size() == n, "a loaded mesh has a partial colour array");
    for (const uint32_t i : m.indices) check(i < n, "a loaded mesh has an index out of range");
}

void check_geometry(const Mesh& m) {
    glm::vec3 lo = m.positions[0], hi = m.positions[0];
    for (const glm::vec3& p : m.positions) {
        check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
              "a loaded mesh has a non-finite position");
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    check(m.bounds.min == lo && m.bounds.max == hi, "a loaded mesh's bounds are not its extent");
    for (const glm::vec3& n : m.normals)
        check(std::abs(glm::length(n) - 1.0f) < 1e-3f, "a loaded mesh has a non-unit normal");
}

// The extension each first byte picks, by its value modulo 8: 'o' (111)
// is .obj and 'p' (112) .ply, as when the target knew only those two; the
// others are the formats assimp reads that facet's seeds cover.
constexpr const char* kExtensions[8] = {".ply", ".off", ".stl", ".gltf", ".glb", ".dae", ".3ds",
                                        ".obj"};

}  // namespace

void mesh_import(const uint8_t* data, size_t size) {
    if (size == 0) return;
    const char* extension = kExtensions[data[0] % 8];
    const InputFile input(sandbox() / "meshes" / (std::string("input") + extension), data + 1,
                          size - 1);
    std::shared_ptr<const Mesh> mesh;
    try {
        mesh = load_mesh(input.path(), MeshImport::in_process);
    } catch (const Error& e) {
        check(e.code() == ErrorCode::file_not_found || e.code() == ErrorCode::not_a_file ||
                  e.code() == ErrorCode::mesh_load_failed || e.code() == ErrorCode::mesh_invalid,
              std::string("load_mesh threw an undocumented error id: ") + e.what());
        return;
    } catch (const std::exception& e) {
        unexpected("load_mesh", e);
    }
    check(mesh != nullptr, "load_mesh returned no mesh");
    check_arrays(*mesh);
    check_geometry(*mesh);
}

}  // namespace facet::fuzz
