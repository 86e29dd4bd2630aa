// PLY preflight.
//
// Takes: a file that assimp would read as PLY.
// Gives: nothing if the header is well formed and the body holds every
// element it declares; otherwise Error(mesh_load_failed) naming the file,
// the header line or the element where it falls short.
//
// Why: assimp 5.2's PLY reader loops forever on some malformed headers and
// reads past the end of a truncated binary body (a crash), and its
// triangulation aborts on a face of fewer than three vertices. Checking
// first turns each into a clear error.
#pragma once

#include <filesystem>

namespace facet {

// True if assimp would read the file as PLY: its extension is .ply (any
// case), or it starts with "ply" (any case, after white space).
bool looks_like_ply(const std::filesystem::path& path);

void check_ply(const std::filesystem::path& path);

}  // namespace facet
