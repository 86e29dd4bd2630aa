// GLB preflight.
//
// Takes: a file that starts with the GLB magic "glTF" (whatever its name:
// assimp picks its glTF readers by content too).
// Gives: nothing if its header and chunks fit in the file; otherwise
// Error(mesh_load_failed) naming the file and the length that does not fit.
//
// Why: assimp 5.2 tries its glTF readers on a GLB by loading it, and a
// header or chunk length past the end of the file sends it through
// allocations of hundreds of megabytes and seconds of work for a file of a
// few dozen bytes (tests/fuzz_regressions/gltf/). The lengths are checked
// here against the file's size in a few dozen bytes.
#pragma once

#include <filesystem>

namespace facet {

bool looks_like_glb(const std::filesystem::path& path);

void check_glb(const std::filesystem::path& path);

// A file named .glb that does not start with the GLB magic (or with a JSON
// object), or one named .gltf that does not start with a JSON object (or
// the magic), is Error(mesh_load_failed) before the importer sees it.
// Why: when its glTF reader declines a file, assimp tries its other
// readers by content, and the fuzzer found one (OpenGEX's) spinning for
// seconds on 155 bytes named .glb.
void check_gltf_name(const std::filesystem::path& path);

}  // namespace facet
