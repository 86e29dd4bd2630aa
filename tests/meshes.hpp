// Meshes made in code, shared by the tests and the benchmarks.
#pragma once

#include <facet/mesh.hpp>

#include <glm/vec3.hpp>

namespace facet::test {

// A closed UV sphere: `rings` rings of 2 * `rings` quads (4 * rings^2
// triangles), the ellipsoid of semi-axes `radii` around `centre`. Each
// triangle winds counter-clockwise seen from outside. Positions, unit
// normals and UVs (u around the equator, v from the +Y pole); the seam
// column repeats its first column's positions exactly, so the surface has
// no cracks there.
Mesh uv_sphere(int rings, glm::vec3 radii = glm::vec3(1.0f), glm::vec3 centre = glm::vec3(0.0f));

}  // namespace facet::test
