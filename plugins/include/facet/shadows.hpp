// facet shadow filtering for shaders (C++20, header-only): percentage-closer
// filtering of the host's shadow maps, for kLanes points at once. Included
// by <facet/lighting.hpp>; light_visibility() there is what a lit shader
// calls. The host gives each shadow-casting light a map (a cube of six for
// a point light) as 16-bit distances from the light, with planes that
// bound them tile by tile, from which the filter settles most receivers
// without reading a texel (facet_shadow_map in <facet/shader_abi.h>). The
// filter gathers four texels of a row at a time; its lane-order tricks
// follow x86's.
#pragma once

#include <facet/shader.hpp>

#include <algorithm>
#include <bit>
#include <cstdint>

namespace facet::sdk {

// ---- a light's maps, as the host gives them ------------------------------------

// A light's shadow map (shadow_of), or one that reads false.
struct ShadowMap {
    const facet_shadow_map* map = nullptr;
    explicit operator bool() const { return map != nullptr; }
};

// A point light's cube map (cube_shadow_of): six faces of 90 degrees, +X,
// -X, +Y, -Y, +Z, -Z of the direction from the light.
struct CubeShadow {
    const facet_shadow_map* faces = nullptr;
    glm::vec3 light{0.0f};  // the light's position
    explicit operator bool() const { return faces != nullptr; }
    ShadowMap face(int f) const { return {faces + f}; }
};

// Light i's shadow as the draw has it: NULL, or its record.
inline const facet_shadow* shadow_record(const Draw& d, uint32_t i) {
    return d.raw->shadows && i < d.raw->light_count ? &d.raw->shadows[i] : nullptr;
}

// Light i's shadow map, or one that reads false if it casts none.
inline ShadowMap shadow_of(const Draw& d, uint32_t i) {
    const facet_shadow* s = shadow_record(d, i);
    return s && s->map_count == 1 ? ShadowMap{s->maps} : ShadowMap{};
}

// Point light i's cube map, or one that reads false if it casts none.
inline CubeShadow cube_shadow_of(const Draw& d, uint32_t i) {
    const facet_shadow* s = shadow_record(d, i);
    if (!s || s->map_count != 6) return {};
    return {s->maps, glm::make_vec3(d.raw->lights[i].position)};
}

// Whether light i has a map or a cube this draw can filter.
inline bool has_shadow(const Draw& d, uint32_t i) {
    const facet_shadow* s = shadow_record(d, i);
    return s && s->map_count > 0;
}

// ---- the filter ------------------------------------------------------------------

namespace detail {
// sqrt(i * i + j * j), the distance in texels of the taps at |dx| = i and
// |dy| = j from a kernel's centre, rounded to float (tests hold the table
// to std::sqrt): constants for the filters below, each of which makes the
// table a local constexpr (a namespace-scope one would be a symbol shared
// by the per-path builds, which facet_isa_objects cannot make local).
struct TapDistances {
    float at[8][8];
    constexpr TapDistances() : at{} {
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j) {
                const double n = double(i * i + j * j);
                double r = n > 1.0 ? n / 2.0 : n;
                for (int k = 0; k < 64 && r > 0.0; ++k) r = 0.5 * (r + n / r);
                at[i][j] = float(r);
            }
    }
};


// tap_threshold for each lane.
inline wide::Mask tap_threshold(const wide::Float& q) {
    using namespace wide;
    const Float c = clamp(q, 0.0f, 65535.0f);
#if FACET_WIDE_AVX
    const Float up = ceil(c);
#else
    // No rounding instruction before SSE4.1: the ceiling of a float in
    // 0..65535 is its truncation, plus one where that fell below it.
    const Float t = __builtin_convertvector(__builtin_convertvector(c, Mask), Float);
    const Float up = select(t < c, t + 1.0f, t);
#endif
    return __builtin_convertvector(select(q == q, up, splat(65535.0f)), Mask);
}

// tap_bound for each lane.
inline wide::Float tap_bound(const wide::Float& q) {
    using namespace wide;
    return select(q == q, clamp(q, 0.0f, 65535.0f), splat(65535.0f));
}

// kTaps.at[r][r] of TapDistances, sqrt(2 r^2), for r in 0..7: a constant
// for each r (the whole table, a local, would be stored on the stack at
// every call).
inline float diagonal_tap(int r) {
    constexpr TapDistances kTaps{};
    switch (r) {
        case 0: return kTaps.at[0][0];
        case 1: return kTaps.at[1][1];
        case 2: return kTaps.at[2][2];
        case 3: return kTaps.at[3][3];
        case 4: return kTaps.at[4][4];
        case 5: return kTaps.at[5][5];
        case 6: return kTaps.at[6][6];
        default: return kTaps.at[7][7];
    }
}

// Four 16-bit values in each 64-bit lane, half a call's lanes at a time:
// half 0 holds lanes 0, 1, 4, 5, 8, 9, ... and half 1 lanes 2, 3, 6, 7, ...,
// the order in which x86 interleaves two registers within each 128 bits, so
// that moving lanes between the layouts costs one instruction.
using Quad16 = uint16_t __attribute__((vector_size(4 * wide::kLanes)));
using QuadCounts = int16_t __attribute__((vector_size(4 * wide::kLanes)));

// The lanes of `half` of (lo, hi) as 64-bit lanes lo | hi << 32.
inline wide::Quads interleave(const wide::Mask& lo, const wide::Mask& hi, int half) {
    using wide::Mask;
#if FACET_WIDE_LANES == 16
    const Mask v = half ? __builtin_shufflevector(lo, hi, 2, 18, 3, 19, 6, 22, 7, 23, 10, 26, 11,
                                                  27, 14, 30, 15, 31)
                        : __builtin_shufflevector(lo, hi, 0, 16, 1, 17, 4, 20, 5, 21, 8, 24, 9,
                                                  25, 12, 28, 13, 29);
#elif FACET_WIDE_LANES == 8
    const Mask v = half ? __builtin_shufflevector(lo, hi, 2, 10, 3, 11, 6, 14, 7, 15)
                        : __builtin_shufflevector(lo, hi, 0, 8, 1, 9, 4, 12, 5, 13);
#else
    const Mask v = half ? __builtin_shufflevector(lo, hi, 2, 6, 3, 7)
                        : __builtin_shufflevector(lo, hi, 0, 4, 1, 5);
#endif
    return std::bit_cast<wide::Quads>(v);
}

// The lanes of `half` of v.
inline wide::HalfIndex half_lanes(const wide::Mask& v, int half) {
#if FACET_WIDE_LANES == 16
    return half ? __builtin_shufflevector(v, v, 2, 3, 6, 7, 10, 11, 14, 15)
                : __builtin_shufflevector(v, v, 0, 1, 4, 5, 8, 9, 12, 13);
#elif FACET_WIDE_LANES == 8
    return half ? __builtin_shufflevector(v, v, 2, 3, 6, 7)
                : __builtin_shufflevector(v, v, 0, 1, 4, 5);
#else
    return half ? __builtin_shufflevector(v, v, 2, 3) : __builtin_shufflevector(v, v, 0, 1);
#endif
}

// Back: the low 32 bits of each 64-bit lane of the two halves, in lane order.
inline wide::Mask join_halves(const wide::Quads& a, const wide::Quads& b) {
    using wide::Mask;
    const Mask x = std::bit_cast<Mask>(a), y = std::bit_cast<Mask>(b);
#if FACET_WIDE_LANES == 16
    return __builtin_shufflevector(x, y, 0, 2, 16, 18, 4, 6, 20, 22, 8, 10, 24, 26, 12, 14, 28, 30);
#elif FACET_WIDE_LANES == 8
    return __builtin_shufflevector(x, y, 0, 2, 8, 10, 4, 6, 12, 14);
#else
    return __builtin_shufflevector(x, y, 0, 2, 4, 6);
#endif
}

// How many taps of a (2R + 1)^2 kernel around each lane's centre texel are
// lit, with `receiver` the centre tap's distance and `step` how much
// deeper each texel further out sees it. A row is read four texels at a time
// from the kernel's first column, so one gather element brings up to four
// taps and one comparison of 16-bit quarters tests them; the texels past
// the kernel get threshold 0, always lit, and are taken off at the end.
template <int R>
inline wide::Mask lit_distances(const facet_shadow_map& d, const wide::Mask& cx,
                                const wide::Mask& cy, const wide::Float& receiver,
                                const wide::Float& step) {
    using namespace wide;
    constexpr int kQuads = (2 * R + 1 + 3) / 4;  // per row
    constexpr int kExtra = 4 * kQuads - (2 * R + 1);
    constexpr TapDistances kTaps{};
    Mask threshold[R + 1][R + 1];
#pragma GCC unroll 16
    for (int i = 0; i <= R; ++i)
#pragma GCC unroll 16
        for (int j = 0; j <= i; ++j)
            threshold[i][j] = tap_threshold(receiver - step * kTaps.at[i][j]);
    const auto tap = [&](int dx, int ay) {
        const int ax = dx < 0 ? -dx : dx;
        return ax > R ? Mask{} : threshold[std::max(ax, ay)][std::min(ax, ay)];
    };
    // Thresholds of quad k of a row |dy| = ay away, for each half of the lanes.
    Quad16 packed[R + 1][kQuads][2];
#pragma GCC unroll 16
    for (int ay = 0; ay <= R; ++ay)
#pragma GCC unroll 16
        for (int k = 0; k < kQuads; ++k) {
            const int dx = 4 * k - R;
            const Mask lo = tap(dx, ay) | tap(dx + 1, ay) << 16;
            const Mask hi = tap(dx + 2, ay) | tap(dx + 3, ay) << 16;
            for (int h = 0; h < 2; ++h)
                packed[ay][k][h] = std::bit_cast<Quad16>(interleave(lo, hi, h));
        }
    const int stride = int(d.stride);
    const Mask first = cy * stride + (cx - R);  // the kernel's first texel in its middle row
    const HalfIndex start[2] = {half_lanes(first, 0), half_lanes(first, 1)};
    QuadCounts count[2] = {};
#pragma GCC unroll 16
    for (int dy = -R; dy <= R; ++dy)
#pragma GCC unroll 16
        for (int k = 0; k < kQuads; ++k)
            for (int h = 0; h < 2; ++h) {
                const Quad16 texels = std::bit_cast<Quad16>(
                    gather_quads(d.texels, start[h] + (dy * stride + 4 * k)));
                count[h] -= texels >= packed[dy < 0 ? -dy : dy][k][h];  // 0 or -1
            }
    // Each 64-bit lane's four counts, added: 16-bit pairs, then 32-bit pairs.
    Quads sum[2];
    for (int h = 0; h < 2; ++h) {
        const Mask c = std::bit_cast<Mask>(count[h]);
        const Mask pairs = (c & 0xFFFF) + ((c >> 16) & 0xFFFF);
        sum[h] = std::bit_cast<Quads>(pairs) + (std::bit_cast<Quads>(pairs) >> 32);
    }
    return join_halves(sum[0], sum[1]) - kExtra * (2 * R + 1);
}

// The lowest and the highest distance a kernel of radius r <=
// FACET_SHADOW_REACH around texel (cx, cy) can read, for each lane, from the
// planes of the tile that holds (cx, cy): the planes at (cx, cy), moved
// apart by the most they rise or fall r texels away on each axis, and by a
// quarter unit more than float rounding can move them (the ABI bounds the
// slopes by 2048 units a texel and the planes by 2^17, so no sum here
// reaches 2^18, below which each rounding is within 1/64). It settles only
// receivers that every tap or no tap of the kernel lights.
static_assert(FACET_SHADOW_TILE == 8, "a texel's tile is its coordinates >> 3");
struct WideSlab {
    wide::Float low, high;
};
inline WideSlab slab(const facet_shadow_map& g, const wide::Mask& cx, const wide::Mask& cy,
                     int r) {
    using namespace wide;
    Float tile[4] = {};
    gather4(g.tiles, 4 * ((cy >> 3) * int(g.tile_stride) + (cx >> 3)), tile);
    const Float nearest0 = tile[0], dx = tile[1], dy = tile[2], depth = tile[3];
    const Float nearest = nearest0 + dx * __builtin_convertvector(cx & 7, Float) +
                          dy * __builtin_convertvector(cy & 7, Float);
    const Float spread = (abs(dx) + abs(dy)) * float(r);
    return {nearest - spread - 0.25f, nearest + depth + spread + 0.25f};
}

// The share of the (2r + 1)^2 taps around each lane's texel (cx, cy) that
// are lit, for the receivers the planes did not settle: out of line, so that
// the calls the planes settle need no stack frame for it.
[[gnu::noinline]] inline wide::Float filter_distances(const facet_shadow_map& d, int r,
                                                      wide::Mask cx, wide::Mask cy,
                                                      wide::Float receiver, wide::Float step) {
    using namespace wide;
    Mask lit;
    switch (r) {  // each kernel's loops unrolled
        case 0: lit = lit_distances<0>(d, cx, cy, receiver, step); break;
        case 1: lit = lit_distances<1>(d, cx, cy, receiver, step); break;
        case 2: lit = lit_distances<2>(d, cx, cy, receiver, step); break;
        case 3: lit = lit_distances<3>(d, cx, cy, receiver, step); break;
        case 4: lit = lit_distances<4>(d, cx, cy, receiver, step); break;
        case 5: lit = lit_distances<5>(d, cx, cy, receiver, step); break;
        case 6: lit = lit_distances<6>(d, cx, cy, receiver, step); break;
        default: lit = lit_distances<7>(d, cx, cy, receiver, step); break;
    }
    return __builtin_convertvector(lit, Float) / float((2 * r + 1) * (2 * r + 1));
}
}  // namespace detail

// Fraction of a kernel x kernel block of shadow-map texels (percentage-closer
// filtering) around world points p that sees the light, each lane on its
// own. The receiver is moved toward the light by (bias + slope_bias *
// tan(theta)) texels, theta being the angle between the surface normal and
// the light (n_dot_l is its cosine): a slope-scaled bias, which keeps
// surfaces from shadowing themselves ("acne") at any angle. A tap k texels
// from the centre sees the tilted receiver k * tan(theta) texels deeper, so
// its bias grows by that much too. A tap is lit where the stored distance
// is at least the tap's (rounded up to the map's units). In distance units
// the receiver and its taps are straight lines in the bias, so each class
// of tap (by its distance from the centre) costs one subtraction, and a
// perspective map's point needs one division. A point whose centre texel is
// off the map is lit; taps past the map's edge read its border, which is
// lit. kernel is clamped to 1..15.
[[gnu::always_inline]] inline wide::Float shadow_visibility(const ShadowMap& m,
                                                            const wide::Vec3& p,
                                                            const wide::Float& n_dot_l, int kernel,
                                                            float bias, float slope_bias) {
    using namespace wide;
    const facet_shadow_map& sm = *m.map;
    const float* v = sm.view_projection;  // column-major
    const auto row = [&](int r) {
        return (v[r] * p.x + v[4 + r] * p.y) + (v[8 + r] * p.z + splat(v[12 + r]));
    };
    const float scale = 65535.0f / (sm.far_plane - sm.near_plane);
    Float x = row(0), y = row(1), q, texel;
    Mask seen;
    if (sm.projection == FACET_SHADOW_ORTHOGRAPHIC) {
        q = row(2) * 65535.0f;
        texel = splat(sm.texel_size * scale);
        seen = q <= 65535.0f;
    } else {
        const Float w = row(3);
        const Float inv_w = 1.0f / w;
        x = x * inv_w;
        y = y * inv_w;
        q = (w - sm.near_plane) * scale;
        texel = (sm.texel_size * scale) * w;
        seen = w > 0.0f && q <= 65535.0f;
    }
    // The texel (cx, cy) is (floor(tx), floor(ty)): on the
    // map tx and ty are at least 0, where truncation is the floor.
    const float width = float(sm.width), height = float(sm.height);
    const Float tx = (x * 0.5f + 0.5f) * width, ty = (0.5f - y * 0.5f) * height;
    seen &= tx >= 0.0f && tx < width && ty >= 0.0f && ty < height;  // false for NaN
    if (!any(seen)) return splat(1.0f);
    // Lanes off the map read around texel (0, 0), inside the border.
    const Mask cx = __builtin_convertvector(select(seen, tx, splat(0.0f)), Mask);
    const Mask cy = __builtin_convertvector(select(seen, ty, splat(0.0f)), Mask);
    const Float cos_t = clamp(n_dot_l, 0.1f, 1.0f);
    const Float tan_t = sqrt(1.0f - cos_t * cos_t) / cos_t;
    const Float receiver = q - texel * (bias + slope_bias * tan_t);
    const Float step = texel * tan_t;
    const int r = std::clamp(kernel, 1, 15) / 2;
    if (sm.tiles && r <= FACET_SHADOW_REACH) {  // lane by lane
        const detail::WideSlab s = detail::slab(sm, cx, cy, r);
        const Float centre = detail::tap_bound(receiver - step * 0.0f);
        const Float corner = detail::tap_bound(receiver - step * detail::diagonal_tap(r));
        const Mask all_lit = s.low >= centre;
        const Mask none_lit = s.high < corner;
        if (!any(seen & !(all_lit | none_lit)))
            return select(seen & none_lit, splat(0.0f), splat(1.0f));
    }
    return select(seen, detail::filter_distances(sm, r, cx, cy, receiver, step),
                  splat(1.0f));
}

// The same over a point light's cube map, each lane from the face that holds
// the direction from the light to its point: every face some lane needs is
// filtered, for those lanes.
inline wide::Float shadow_visibility(const CubeShadow& c, const wide::Vec3& p,
                                     const wide::Float& n_dot_l, int kernel, float bias,
                                     float slope_bias) {
    using namespace wide;
    const Vec3 d = p - Vec3(c.light);
    const Float ax = abs(d.x), ay = abs(d.y), az = abs(d.z);
    const Mask x = ax >= ay && ax >= az, y = !x && ay >= az;
    const Mask face = select(x, select(d.x > 0.0f, Mask{}, Mask{} + 1),
                             select(y, select(d.y > 0.0f, Mask{} + 2, Mask{} + 3),
                                    select(d.z > 0.0f, Mask{} + 4, Mask{} + 5)));
    Float visible = splat(1.0f);
    for (int f = 0; f < 6; ++f) {
        const Mask here = face == f;
        if (!any(here)) continue;
        visible = select(here, shadow_visibility(c.face(f), p, n_dot_l, kernel, bias, slope_bias),
                         visible);
    }
    return visible;
}

}  // namespace facet::sdk
