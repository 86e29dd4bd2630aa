// The shadow pass's kernels (kernels.hpp): a shadow map's window depths as
// 16-bit distances from the light (facet_shadow_distances), kWidth texels
// at a time, and the planes that bound them tile by tile
// (facet_shadow_planes); one of the per-ISA kernel sources.
#include "pipeline/shadow_rows.hpp"
#include "base/simd.hpp"

#include <facet/shader_abi.h>

#include <algorithm>
#include <cmath>

namespace facet::FACET_KERNEL_NS {

using simd::Float;
using simd::Int;
using simd::kWidth;

// Distance along the light's axis, as (distance - near) / (far - near) *
// 65535 rounded up, so that a receiver at a caster's own distance reads as
// lit; 65535 where nothing was drawn (depth 1). An orthographic map's window
// depth is that fraction already. A perspective depth z is distance
// n f / (f (1 - z) + n z): 1 - z is exact where z is near 1, so the
// distance stays within a few units in the last place, below the 16-bit
// step. Every path does the same IEEE operations: the same texels.
void shadow_distance_rows(const ShadowDistanceRows& r, int first, int count) {
    using U16 = uint16_t __attribute__((vector_size(2 * kWidth)));
    const float n = r.near_plane, f = r.far_plane, scale = 65535.0f / (f - n);
    for (int y = first; y < first + count; ++y) {
        const float* depth = r.depth + size_t(y) * size_t(r.depth_stride);
        uint16_t* out = r.distances + size_t(y) * size_t(r.distance_stride);
        for (int x = 0; x < r.width; x += kWidth) {
            const Float z = simd::load<Float>(depth + x);
            Float q = r.orthographic ? z * 65535.0f : (n * f / (f * (1.0f - z) + n * z) - n) * scale;
            q = q < 0.0f ? 0.0f : q > 65535.0f ? 65535.0f : q;
            const Int whole = __builtin_convertvector(q, Int);  // q >= 0: the floor
            const Int up = whole - (simd::to_float(whole) < q);  // a comparison is 0 or -1
            simd::store(out + x, __builtin_convertvector(up, U16));
        }
    }
}

// Each tile's planes: slopes fitted to its own texels by least squares,
// then the lowest and highest distance less those slopes over the texels
// within FACET_SHADOW_REACH of it, the window's rows of 16 texels kWidth at
// a time. The slopes need not be exact (any planes bound the texels they are
// measured against), so float sums do; one past 2048 units a texel (a tile
// across a silhouette) is taken as 0, so that the planes stay within the
// ABI's +-2^17 (distances are at most 65535, and a window reaches 11
// texels from the tile's first): such a tile's planes lie far apart, and
// its receivers read their taps. The residuals' rounding is below 1/64 of
// a unit, and the planes are moved a quarter unit out each.
namespace {

// kWidth texels from `first`, as floats.
Float texels(const uint16_t* first) {
    using Texels = uint16_t __attribute__((vector_size(2 * kWidth)));
    return simd::to_float(__builtin_convertvector(simd::load<Texels>(first), Int));
}

template <class Op>
float across(const Float& v, Op op) {
    float r = v[0];
    for (int i = 1; i < kWidth; ++i) r = op(r, v[i]);
    return r;
}

}  // namespace

void shadow_plane_rows(const ShadowPlaneRows& r, int first, int count) {
    constexpr int kTile = FACET_SHADOW_TILE, kReach = FACET_SHADOW_REACH;
    constexpr int kRow = kTile + 2 * kReach, kParts = kRow / kWidth;  // a window's row
    static_assert(kTile == 8 && kRow == 16 && kReach <= FACET_SHADOW_BORDER);
    Float x_offset[kParts], in_tile[kParts], x_weight[kParts];  // x - x0; 1 in the tile; 2 (x - x0) - 7 there
    for (int p = 0; p < kParts; ++p)
        for (int i = 0; i < kWidth; ++i) {
            const int x = p * kWidth + i - kReach;
            x_offset[p][i] = float(x);
            in_tile[p][i] = x >= 0 && x < kTile ? 1.0f : 0.0f;
            x_weight[p][i] = in_tile[p][i] * float(2 * x - 7);
        }
    for (int ty = first; ty < first + count; ++ty)
        for (int tx = 0; tx < r.width / kTile; ++tx) {
            const uint16_t* row0 =  // the window's first texel in the tile's first row
                r.distances + ptrdiff_t(ty * kTile) * r.stride + ptrdiff_t(tx * kTile - kReach);
            // 336 dx = sum of (x - 3.5) d over the tile, and the same for y.
            Float sx{}, sy{};
            for (int y = 0; y < kTile; ++y)
                for (int p = 0; p < kParts; ++p) {
                    const Float d = texels(row0 + ptrdiff_t(y) * r.stride + p * kWidth);
                    sx += d * x_weight[p];
                    sy += d * (in_tile[p] * float(2 * y - 7));
                }
            const auto add = [](float a, float b) { return a + b; };
            float dx = across(sx, add) / 672.0f, dy = across(sy, add) / 672.0f;
            if (!(std::abs(dx) <= 2048.0f)) dx = 0.0f;
            if (!(std::abs(dy) <= 2048.0f)) dy = 0.0f;
            Float plane_x[kParts];
            for (int p = 0; p < kParts; ++p) plane_x[p] = dx * x_offset[p];
            Float low = Float{} + 262144.0f, high = Float{} - 262144.0f;
            for (int y = -kReach; y < kTile + kReach; ++y)
                for (int p = 0; p < kParts; ++p) {
                    const Float residual = texels(row0 + ptrdiff_t(y) * r.stride + p * kWidth) -
                                           (plane_x[p] + dy * float(y));
                    low = residual < low ? residual : low;
                    high = residual > high ? residual : high;
                }
            float* out = r.tiles + 4 * (ptrdiff_t(ty) * (r.width / kTile) + tx);
            out[0] = across(low, [](float a, float b) { return std::min(a, b); }) - 0.25f;
            out[1] = dx;
            out[2] = dy;
            out[3] = (across(high, [](float a, float b) { return std::max(a, b); }) + 0.25f) - out[0];
        }
}

}  // namespace facet::FACET_KERNEL_NS
