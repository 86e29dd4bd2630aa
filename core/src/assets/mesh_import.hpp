// Mesh import as facet-sandbox runs it (load_mesh, MeshImport::isolated).
//
// Takes: a mesh file (after load_mesh's checks of it).
// Gives: the mesh assimp makes of it, flattened into one, as bytes: each
// array's length, then its elements (positions, normals, both UV sets,
// colours, tangents, indices, and the rest of Mesh), which load_mesh()
// reads back. Throws what the import throws:
// Error(mesh_load_failed), or std::bad_alloc when memory ran out.
#pragma once

#include <filesystem>
#include <string>

namespace facet {

std::string import_mesh_bytes(const std::filesystem::path& path);

}  // namespace facet
