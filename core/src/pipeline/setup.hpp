// Triangle setup.
//
// Takes: three clip-space vertices that lie inside the guard band (clip.hpp
// guarantees it), their varyings, the viewport and the culling state. A
// vertex with w <= 0 (only the origin survives clipping with w = 0) makes
// the triangle degenerate.
// Gives: a TriangleSetup: vertices snapped to fixed point with the
// viewport's sub-pixel bits (8 by default, as D3D10+ requires), three integer edge functions with the top-left fill rule folded in,
// the pixel bounding box clipped to the viewport, and what the fragment
// stage needs to interpolate (window depth, 1/w, varyings) - or a reason the
// triangle draws nothing.
//
// Exactness: snapped coordinates are below 2^28 in magnitude anywhere in the
// guard band (|x|, |y| < 2^20 pixels), so an edge function, a difference of
// two products of 29-bit numbers, stays below 2^59 and int64 never overflows.
// Inside one 4x4 block the values are smaller: an edge function changes by
// at most |dx| + |dy| (the edge's extent in sub-pixels) per sub-pixel step,
// and every lane and MSAA sample of a block the edge crosses lies within
// 1024 sub-pixels (4 pixels) of a point where it is zero. So a triangle
// whose edges span less than kNarrowEdgeSpan sub-pixels has every lane of a
// partly covered block within 32 bits (rasterize.hpp), exactly.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

namespace facet {

// The fixed-point grid every position and edge function lives on: 8 bits
// below the pixel. Vertices snap to a coarser grid when the viewport asks
// for fewer sub-pixel bits, but pixel centres and MSAA sample positions
// (multiples of 1/16 pixel) stay exact on this one.
constexpr int kSubpixelBits = 8;
constexpr int64_t kSubpixelOne = int64_t(1) << kSubpixelBits;
// Half-width of the guard band in pixels: window coordinates stay within
// +-kGuardBandPixels, which is what keeps the edge functions exact.
constexpr double kGuardBandPixels = double(1 << 20);
// Triangles whose every edge has |dx| + |dy| below this (4096 pixels) are
// rasterized with 32-bit lanes: a partly covered block's edge values, MSAA
// samples included, then lie within 1024 (|dx| + |dy|) < 2^30 of zero.
constexpr int64_t kNarrowEdgeSpan = int64_t(1) << 20;

struct Viewport {
    int width = 0;
    int height = 0;
    int samples = 1;  // MSAA: the bounding box then reaches every sample position
    // Vertex precision: window positions round to 1 / 2^subpixel_bits of a
    // pixel, 1..kSubpixelBits. Fewer bits model coarser hardware (Vulkan
    // asks for at least 4); the quality sweep in facet-bench --pareto uses it.
    int subpixel_bits = kSubpixelBits;
    // A band of the viewport (DrawCall::image_height): the target holds rows
    // [first_row, first_row + rows) of the `height` the positions map to.
    // Window positions are the band's, moved up by first_row pixels after
    // snapping, which is exact. rows 0: all of them.
    int first_row = 0;
    int rows = 0;
    int target_rows() const { return rows > 0 ? rows : height; }
    // Guard-band half-width in NDC units for this viewport (see clip.hpp).
    double guard_ndc() const;
};

struct SetupVertex {
    glm::dvec4 clip;          // clip-space position
    const float* varyings;    // its varying floats
};

// E(P) = (X1 - X0) * (Py - Y0) - (Y1 - Y0) * (Px - X0) for the edge from
// vertex k to vertex k+1, in sub-pixel units. A pixel centre P is inside
// when E(P) + bias >= 0 for all three edges: bias is 0 on a top or left
// edge and -1 otherwise, so a point exactly on an edge belongs to the
// triangle on its top or left side only.
// The coordinates fit 32 bits (below 2^29 after snapping, their
// differences below 2^30); the products are taken in 64.
struct EdgeFunction {
    int32_t x0, y0;   // start vertex
    int32_t dx, dy;   // end minus start
    int32_t bias;     // 0 or -1
    int64_t at(int64_t px, int64_t py) const {
        return int64_t(dx) * (py - y0) - int64_t(dy) * (px - x0);
    }
};

enum class SetupResult { ok, culled_backface, degenerate, no_pixels, clipped_away };

struct TriangleSetup {
    // Left uninitialized: setup_triangle() sets every member of a setup it
    // keeps, and a set-up stage that zeroed each setup it appends (as an
    // aggregate's value-initialization would) wrote every byte twice.
    TriangleSetup() {}

    // Edge k runs from vertex k to vertex k+1 and is opposite vertex k+2, so
    // the barycentric weight of vertex k+2 is edge[k].at(P) / area2.
    EdgeFunction edge[3];
    int64_t area2;            // twice the signed area, > 0 after orientation
    int x0, y0, x1, y1;       // inclusive pixel bounding box
    bool narrow;              // every edge spans less than kNarrowEdgeSpan
    // The weights' rounding, scaled by the ratio of the 1/w, may leave the
    // perspective weights more than 2^-17 below 0 on an edge: covered
    // lanes hold theirs at 0 or above (BlockCoverage and NarrowCoverage,
    // in the depth-only route too; with one sample).
    bool clamp_weights;
    // The weights as planes: vertex k's weight changes by bary_dx[k] from
    // one pixel to the next in x (bary_dy[k] in y), and is edge[k + 1]'s
    // value times inv_area2 (both rasterize.hpp).
    double inv_area2;
    float bary_dx[3], bary_dy[3];
    float z[3];               // window depth per vertex, 0..1
    float inv_w[3];           // 1 / w per vertex, all scaled by one power of two (only
                              // their ratios are used, and 1 / w overflows float for tiny w)
    const float* varyings[3]; // varying floats per vertex; flat ones take vertex 0's
    bool front_facing;
};

struct CullState {
    bool cull_back = true;
    bool cull_front = false;
    bool front_ccw = true;  // counter-clockwise on screen (y up) faces the viewer
};

// `orientation`, if not 0, is the sign the triangle's area must have (the
// sign of the clipped polygon it was cut from): a fan piece that snapping
// flipped is dropped as degenerate rather than drawn facing the other way.
SetupResult setup_triangle(const SetupVertex v[3], const Viewport& viewport,
                           const CullState& cull, TriangleSetup& out, int orientation = 0);

// A vertex projected and snapped once, for every triangle that shares it
// (the first half of setup_triangle). Snapping clamps to 2^29 sub-pixels, so
// the coordinates fit 32 bits.
struct WindowVertex {
    int32_t x, y;   // window position on the sub-pixel grid, y down
    float z;        // window depth z / w
    uint32_t user;  // free for the caller (vertex.cpp keeps clip outcodes here)
    double w;       // clip w, > 0
    double inv_w;   // 1 / w: divided once a vertex, not once a triangle that shares it
};

// Projects a clip-space vertex inside the guard band; false when w <= 0.
bool project_vertex(const glm::dvec4& clip, const Viewport& viewport, WindowVertex& out);

// setup_triangle from projected vertices and their varyings.
SetupResult setup_triangle(const WindowVertex* const v[3], const float* const varyings[3],
                           const Viewport& viewport, const CullState& cull, TriangleSetup& out,
                           int orientation = 0);

// The first step of setup_triangle, which culls most of the triangles it
// drops; inline, so that primitive assembly drops them without a call.
// Twice the signed area of the projected triangle (sub-pixels squared).
inline int64_t window_area2(const WindowVertex* const v[3]) {
    return (int64_t(v[1]->x) - v[0]->x) * (int64_t(v[2]->y) - v[0]->y) -
           (int64_t(v[2]->x) - v[0]->x) * (int64_t(v[1]->y) - v[0]->y);
}
// Whether a triangle of signed area `area2` faces the viewer: y runs down
// the window, so a triangle counter-clockwise as seen has negative area.
inline bool front_facing(int64_t area2, const CullState& cull) {
    return cull.front_ccw ? area2 < 0 : area2 > 0;
}
// ok, or why a triangle of signed area `area2` draws nothing
// (setup_triangle's `orientation`).
inline SetupResult facing_result(int64_t area2, const CullState& cull, int orientation = 0) {
    if (area2 == 0 || (orientation != 0 && (area2 > 0) != (orientation > 0)))
        return SetupResult::degenerate;
    const bool front = front_facing(area2, cull);
    return (front && cull.cull_front) || (!front && cull.cull_back) ? SetupResult::culled_backface
                                                                    : SetupResult::ok;
}
// The rest of setup_triangle, for a triangle facing_result() kept.
SetupResult setup_kept_triangle(const WindowVertex* const v[3], const float* const varyings[3],
                                int64_t area2, const Viewport& viewport, const CullState& cull,
                                TriangleSetup& out);
// Whether a set-up triangle whose box is at most 2x2 pixels covers none of
// their centres (false for a larger box, which is not tested). With one
// sample per pixel such a triangle draws nothing, and setup drops it
// (SetupResult::no_pixels): a detailed mesh far away has many triangles
// that fall between the pixel centres, and each would cost binning and a
// block's coverage set-up in every tile it touches.
bool misses_small_box(const TriangleSetup& t);
// The last step of setup_kept_triangle, once the edges, area, inv_area2
// and the weights' planes are set (by it, or by the wide assembly kernel
// in lanes): the depth, 1/w and varyings of the corners `c`, in the
// setup's order, and clamp_weights; `span` is the largest |dx| + |dy| of an
// edge.
void set_corners(const WindowVertex* const c[3], const float* const varyings[3], int64_t span,
                 TriangleSetup& out);

// Moves a set-up triangle's window depth by Vulkan's depth bias
// (PipelineState::depth_bias_constant and depth_bias_slope), its corners
// held inside 0..1: no nearer than 1 - 2^-24 and no farther than the
// smallest normal float, unless a corner already lay beyond.
void add_depth_bias(TriangleSetup& t, double constant, double slope);

// Window position of a clip-space point (pixel units, y down), as setup uses.
glm::dvec2 to_window(const glm::dvec4& clip, const Viewport& viewport);

}  // namespace facet
