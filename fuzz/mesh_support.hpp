// What the two mesh targets share (mesh_import.cpp, gltf.cpp): the checks
// every loaded mesh must pass, and importing in a fork first, so that a
// crash inside assimp (which facet's programs contain in facet-sandbox) is
// passed over rather than reported.
#pragma once

#include <facet/mesh.hpp>

#include <filesystem>
#include <memory>

namespace facet::fuzz {

// mesh.hpp's invariants, checked on their own rather than through
// validate_mesh(): indexed triangles whose indices are in range, finite
// positions, one unit-length normal per vertex (generated where the file
// has none), UV and colour arrays empty or one per vertex, and bounds that
// are exactly the positions' extent. Throws Failure.
void check_mesh(const Mesh& mesh);

// load_mesh(file) in this process, unless importing it would end the
// process (a crash, an abort or a sanitizer's report inside assimp, or an
// allocation past a limit that stands for facet-sandbox's memory budget,
// tried in a fork first: facet-sandbox's to contain). Null then (after
// facet's own checks before assimp have run here, where a crash in them is
// a finding), and when load_mesh refuses the file with an error id that
// mesh.hpp documents; throws Failure for any other error or exception.
std::shared_ptr<const Mesh> import_checked(const std::filesystem::path& file);

}  // namespace facet::fuzz
