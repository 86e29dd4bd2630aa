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
// turns the importer's crashes into errors. So an input on which assimp
// itself crashes (a null pointer in its Collada reader, say) is handled:
// each input is first imported in a fork, and one that ends the fork is
// passed over, as is one that allocates past a limit there (as the
// sandbox's memory budget refuses it). facet's own code before and after
// assimp (the PLY and OFF preflights, the flattening, the checks) runs in
// either.
//
// Checks:
//  - load_mesh() returns a mesh or throws facet::Error with one of the ids
//    mesh.hpp documents (file_not_found, mesh_load_failed, mesh_invalid);
//    any other exception is a finding;
//  - a mesh that loaded keeps mesh.hpp's invariants (check_mesh,
//    mesh_support.hpp).
#include "mesh_support.hpp"
#include "support.hpp"

#include <facet/mesh.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace facet::fuzz {

namespace {

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
    if (const std::shared_ptr<const Mesh> mesh = import_checked(input.path())) check_mesh(*mesh);
}

}  // namespace facet::fuzz
