// Tangent frames for normal mapping, where a mesh file has none.
//
// Takes: one part's triangles with positions, unit normals and UVs (v down
// the texture's rows, as Mesh stores them).
// Gives: Mesh::tangents, in the spirit of MikkTSpace (Mikkelsen 2008), the
// frame glTF 2.0 asks for when a file gives none:
//   - per triangle, the directions in which u and "up" (towards the
//     texture's top row, -v) grow, from its positions and UVs;
//   - per vertex, their sums over the triangles around it, each projected
//     onto the vertex's tangent plane and weighted by the triangle's angle at
//     the vertex, so the result does not depend on how a surface is split
//     into triangles;
//   - the tangent is the sum of the u directions made perpendicular to the
//     normal; w is +1 where the up directions agree with cross(normal,
//     tangent), else -1;
//   - a vertex shared by triangles of both handednesses (a mirrored UV seam)
//     is split in two, one per handedness, so each side keeps its own frame.
// Triangles with no UV area add nothing; a vertex that none of its
// triangles gives a direction gets a zero tangent (w = +1): it has no
// frame, and a normal map leaves its normal as it is.
#pragma once

#include "facet/mesh.hpp"

namespace facet {

// Fills mesh.tangents for every vertex of `mesh` (one part: all its
// indices), appending copies of the vertices it splits to every array and
// re-pointing the indices that use them. Needs normals and uvs.
void generate_tangents(Mesh& mesh);

}  // namespace facet
