// The extensions a glTF file uses, and what facet does with each (private
// to the core).
//
// Takes: a .gltf file, or a GLB (by its magic).
// Gives: the names in its `extensionsUsed`, read from its JSON (a GLB's
// first chunk) with a small scanner bounded by the file's size: no JSON
// tree is built, so a large file costs no more than reading its JSON.
// Each is drawn, approximated or left out (gltf_extension_use); load_mesh
// lists them at -v and warns of each that is not drawn as the file means.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace facet {

// The file's JSON: the .gltf's text, or a GLB's first chunk if it is JSON;
// "" when it cannot be read or is over 64 MiB (a .gltf with its buffers
// inline in base64 can be hundreds of MiB).
std::string gltf_json_text(const std::filesystem::path& path);

// Nothing when its JSON cannot be read, or is over 64 MiB.
std::optional<std::vector<std::string>> gltf_extensions_used(const std::filesystem::path& path);

// What facet does with extension `name`: "drawn", "approximated: WHY" or
// "left out: WHY".
std::string gltf_extension_use(const std::string& name);

}  // namespace facet
