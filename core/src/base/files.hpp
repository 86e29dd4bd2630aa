// Files a user names (scenes, materials, meshes, textures, plugins).
//
// Takes: a path from a config, the command line or a search.
// Gives: nothing, or an Error naming the path and what is there instead of
// a regular file. Opening a named pipe blocks until something writes to it,
// and a device or a folder is not a file to read: both are refused before
// anything opens the path.
#pragma once

#include <filesystem>

namespace facet {

// Throws Error(file_not_found) when nothing is at `path` (a name too long
// for the system, or a dangling link, is nothing too), and
// Error(not_a_file), saying what is there, when it is not a regular file
// (after following links), or why the path cannot be followed (a loop of
// links, a folder on the way that may not be searched).
void require_regular_file(const std::filesystem::path& path);

}  // namespace facet
