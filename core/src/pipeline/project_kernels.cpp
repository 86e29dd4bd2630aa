// Vertex projection (one of the per-ISA kernels, kernels.hpp): each
// vertex's outcodes and window position (vertex.hpp), four vertices at a
// time in double lanes.
//
// The lanes take the scalar operations of outcode() (clip.cpp) and
// project_vertex() and snap() (setup.cpp) in the same order, each exactly
// rounded as IEEE requires and none fused (-ffp-contract=off), so every
// path writes the same bits as the scalar code (test_raster.cpp holds them
// to it).
#include "pipeline/clip.hpp"
#include "pipeline/setup.hpp"
#include "pipeline/vertex.hpp"
#include "base/simd.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>

namespace facet::FACET_KERNEL_NS {

namespace {

// Four vertices at a time: their clip positions load as four rows of
// floats and are turned into columns, and their window vertices (32 bytes
// each) are stored whole. Four double lanes are one register with AVX2
// and AVX-512 (where the divisions, not the width, set the pace) and two
// with SSE2.
constexpr int kLanes = 4;
using Row = simd::Row;                                              // 4 floats
using IntRow = int32_t __attribute__((vector_size(16)));           // 4 int32
using Double = double __attribute__((vector_size(8 * kLanes)));    // 4 doubles
using Mask = int64_t __attribute__((vector_size(8 * kLanes)));     // a comparison's lanes
using Pair = double __attribute__((vector_size(16)));              // 2 doubles

Mask bit_where(const Mask& m, uint32_t bit) { return m & int64_t(bit); }

// outcode(p, guard) of each lane.
Mask outcodes(const Double& x, const Double& y, const Double& z, const Double& w,
               const Double& guard) {
    const Double gw = guard * w;
    return bit_where(w - z < 0.0, kPlaneNear) | bit_where(z < 0.0, kPlaneFar) |
           bit_where(x + gw < 0.0, kPlaneLeft) | bit_where(gw - x < 0.0, kPlaneRight) |
           bit_where(y + gw < 0.0, kPlaneBottom) | bit_where(gw - y < 0.0, kPlaneTop);
}

// What every vertex of a viewport shares, in lanes: broadcast once, not
// at every use.
struct Projection {
    explicit Projection(const Viewport& viewport)
        : guard(Double{} + viewport.guard_ndc()), width(Double{} + double(viewport.width)),
          height(Double{} + double(viewport.height)) {
        const int bits = std::clamp(viewport.subpixel_bits, 1, kSubpixelBits);
        to_grid = Double{} + double(int64_t(1) << bits);
        to_finest = Double{} + double(int64_t(1) << (kSubpixelBits - bits));
        first_row = Double{} + double(int64_t(viewport.first_row) * kSubpixelOne);
    }
    Double guard, width, height;
    Double to_grid, to_finest;  // 2^bits, and 2^(kSubpixelBits - bits)
    Double first_row;           // in units of the finest grid
};

// snap(window, bits) in units of 2^-kSubpixelBits pixel, less `shift`
// (exact: every value on the way is an integer below 2^31 in magnitude).
IntRow snapped(const Double& window, const Projection& p, const Double& shift) {
    const double limit = kGuardBandPixels * 2.0;
    Double c = window < limit ? window : limit;  // NaN: the limit
    c = c > -limit ? c : -limit;
    const Double v = c * p.to_grid;  // |v| <= 2^29: truncates exactly
    const Double t = __builtin_convertvector(__builtin_convertvector(v, IntRow), Double);
    const Double f = v - t;
    const Double one = Double{} + 1.0, none = Double{};
    const Double r = t + (f >= 0.5 ? one : none) - (f <= -0.5 ? one : none);
    return __builtin_convertvector(r * p.to_finest - shift, IntRow);
}

// Rows a, b, c, d turned into columns: out[j] holds element j of each.
void transpose(const IntRow& a, const IntRow& b, const IntRow& c, const IntRow& d, IntRow out[4]) {
    const IntRow ab_lo = __builtin_shufflevector(a, b, 0, 4, 1, 5);
    const IntRow cd_lo = __builtin_shufflevector(c, d, 0, 4, 1, 5);
    const IntRow ab_hi = __builtin_shufflevector(a, b, 2, 6, 3, 7);
    const IntRow cd_hi = __builtin_shufflevector(c, d, 2, 6, 3, 7);
    out[0] = __builtin_shufflevector(ab_lo, cd_lo, 0, 1, 4, 5);
    out[1] = __builtin_shufflevector(ab_lo, cd_lo, 2, 3, 6, 7);
    out[2] = __builtin_shufflevector(ab_hi, cd_hi, 0, 1, 4, 5);
    out[3] = __builtin_shufflevector(ab_hi, cd_hi, 2, 3, 6, 7);
}

// Vertices [0, 4) of `clip` into `out`.
void project_lanes(const glm::vec4* clip, const Projection& p, WindowVertex* out) {
    IntRow column[4];  // x, y, z and w of the four, as float bits
    transpose(simd::load<IntRow>(clip), simd::load<IntRow>(clip + 1), simd::load<IntRow>(clip + 2),
              simd::load<IntRow>(clip + 3), column);
    const auto lanes = [](const IntRow& bits) {
        return __builtin_convertvector(std::bit_cast<Row>(bits), Double);
    };
    const Double x = lanes(column[0]), y = lanes(column[1]), z = lanes(column[2]),
                 w = lanes(column[3]);
    // A float is finite when it minus itself is 0 (not NaN), in double too.
    const Mask finite = (x - x == 0.0) & (y - y == 0.0) & (z - z == 0.0) & (w - w == 0.0);
    const Mask view = outcodes(x, y, z, w, Double{} + 1.0), band = outcodes(x, y, z, w, p.guard);
    const Mask no_window = (band == 0) & ~(w > 0.0);
    const Mask user =
        finite ? view | band << 8 | bit_where(no_window, kNoWindow) : Mask{} + kInvalid;
    const Double inv_w = 1.0 / w;
    const Double wx = (x * inv_w + 1.0) * 0.5 * p.width;
    const Double wy = (1.0 - y * inv_w) * 0.5 * p.height;
    const Row depth = __builtin_convertvector(z / w, Row);
    // Lanes that were not projected (outside the band, invalid, or w <= 0)
    // keep values no triangle reads: setup takes only projected vertices.
    IntRow head[4];  // x, y, z and user of each vertex
    transpose(snapped(wx, p, Double{}), snapped(wy, p, p.first_row),
              std::bit_cast<IntRow>(depth), __builtin_convertvector(user, IntRow), head);
    static_assert(sizeof(WindowVertex) == 32 && offsetof(WindowVertex, w) == 16);
    const Pair tail[4] = {Pair{w[0], inv_w[0]}, Pair{w[1], inv_w[1]}, Pair{w[2], inv_w[2]},
                          Pair{w[3], inv_w[3]}};
    for (int j = 0; j < kLanes; ++j) {
        simd::store(&out[j], head[j]);
        simd::store(&out[j].w, tail[j]);
    }
}

}  // namespace

void project_vertices(const glm::vec4* clip, size_t count, const Viewport& viewport,
                      WindowVertex* out) {
    const Projection p(viewport);
    size_t i = 0;
    for (; i + kLanes <= count; i += kLanes) project_lanes(clip + i, p, out + i);
    if (i == count) return;
    glm::vec4 rest[kLanes] = {};  // the last few, padded with the origin at w = 1
    WindowVertex done[kLanes];
    for (int j = 0; j < kLanes; ++j) rest[j].w = 1.0f;
    std::copy(clip + i, clip + count, rest);
    project_lanes(rest, p, done);
    std::copy(done, done + (count - i), out + i);
}

}  // namespace facet::FACET_KERNEL_NS
