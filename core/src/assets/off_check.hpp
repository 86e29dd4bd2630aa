// OFF preflight.
//
// Takes: a file that assimp may read as OFF (named .off, or starting with an
// OFF keyword: OFF, COFF, NOFF, STOFF, nOFF, ...).
// Gives: nothing if the counts in its header fit in the file; otherwise
// Error(mesh_load_failed) naming the file and the counts.
//
// Why: assimp 5.2's OFF reader allocates for the header's counts before it
// reads a vertex, so a 45-byte file that declares a billion faces takes
// gigabytes. Every vertex and face takes some bytes of the file, so counts
// the file cannot hold are a lie, found here in a few hundred bytes.
#pragma once

#include <filesystem>

namespace facet {

bool looks_like_off(const std::filesystem::path& path);

void check_off(const std::filesystem::path& path);

}  // namespace facet
