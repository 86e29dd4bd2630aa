// Meshes the benchmarks generate.
#pragma once

#include <facet/mesh.hpp>

#include <memory>

namespace facet::bench {

// A UV sphere of radius 1 at the origin, `rings` rings of 2 * rings quads
// (4 * rings^2 triangles), counter-clockwise seen from outside, with
// normals and UVs.
std::shared_ptr<Mesh> uv_sphere(int rings);

}  // namespace facet::bench
