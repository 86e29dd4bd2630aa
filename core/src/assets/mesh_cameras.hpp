// A mesh file's cameras (private to the core; run where the importer runs).
#pragma once

#include "facet/mesh.hpp"

#include <filesystem>
#include <vector>

struct aiScene;

namespace facet {

// Each of the file's cameras, placed by its node at rest, as it comes:
// validate_mesh checks them, and a scene that uses one checks it as a
// camera.
std::vector<MeshCamera> import_cameras(const aiScene& scene, const std::filesystem::path& path);

}  // namespace facet
