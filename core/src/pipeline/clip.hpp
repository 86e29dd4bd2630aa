// Homogeneous clipping.
//
// Takes: a triangle (or a line's or point's quadrilateral) in clip space
// (position x, y, z, w plus its varyings).
// Gives: the convex polygon of the part that lies inside the depth range
// 0 <= z <= w and inside the guard band |x|, |y| <= g * w, as at most
// kMaxClipVertices vertices, ready to be split into a fan.
//
// The depth planes are always clipped against; they also remove everything
// at w < 0 (only a vertex at the origin, x = y = z = w = 0, survives with
// w = 0, and setup drops it), so a triangle that crosses w = 0 keeps its
// visible part. The
// side planes are the guard band, not the viewport: a triangle is cut there
// only when it would leave the range where the fixed-point rasterizer is
// exact, which for normal scenes is never. The vertices' outcodes tell which
// planes a triangle needs (against the guard band) and whether it lies
// wholly outside the view (against g = 1); most triangles need no plane and
// skip clip_polygon() entirely.
#pragma once

#include "facet/mesh.hpp"

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <cstdint>

namespace facet {

// A vertex as clipping sees it. The position is double: an intersection
// a + t (b - a) between two far-apart vertices cancels catastrophically.
// In double the clipped vertex stays within a sub-pixel for vertices out to
// about 1e11 viewport widths (float manages about 100).
struct ClipVertex {
    glm::dvec4 position;
    float varyings[FACET_MAX_VARYING_FLOATS];
};

// Plane i of a position's outcode is bit i.
enum ClipPlane : uint32_t {
    kPlaneNear = 1u << 0,    // z <= w   (depth 1 side with reversed-Z)
    kPlaneFar = 1u << 1,     // z >= 0
    kPlaneLeft = 1u << 2,    // x >= -g w
    kPlaneRight = 1u << 3,   // x <= g w
    kPlaneBottom = 1u << 4,  // y >= -g w
    kPlaneTop = 1u << 5,     // y <= g w
};

// A quadrilateral (a line's rectangle, a point's square) cut by six planes.
constexpr int kMaxClipVertices = 4 + 6;

// The planes p lies outside of, for side planes at +-g w (g = 1: the view
// frustum itself; `guard` is the guard-band half-width in NDC units).
uint32_t outcode(const glm::dvec4& p, double guard);

// True when all eight corners of `b`, transformed by `mvp` to clip space,
// lie outside one plane of the view frustum: nothing of what b bounds can
// be seen through mvp.
bool outside_frustum(const Bounds& b, const glm::mat4& mvp);

// Clips polygon `in` (n vertices, each with `floats` varyings) against the
// planes in `planes`. `interpolation` gives each varying float's
// facet_interpolation: screen-linear floats are interpolated by screen
// distance, the others by clip-space distance. Writes the result to `out`
// and returns its vertex count (0 if nothing is left). Shared edges clip
// identically from both sides, so clipped meshes stay watertight.
int clip_polygon(const ClipVertex* in, int n, uint32_t planes, double guard, int floats,
                 const uint8_t* interpolation, ClipVertex* out);

}  // namespace facet
