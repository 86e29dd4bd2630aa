// Wide primitive assembly (one of the per-ISA kernels, kernels.hpp): the
// common case of Assembler::run, eight triangles at a time.
//
// For each eight triangles, in lanes: their corners' window positions and
// outcodes (loaded from the draw's WindowVertex array, two triangles a
// register, and turned into columns), the outcome of
// each (invalid, outside the view, to be clipped, degenerate, back-facing
// or kept), and for the kept ones the edges, area, weights' planes and
// bounding box of setup_kept_triangle (setup.cpp), and whether a small box
// holds a centre it covers. Then, lane by lane in
// order, each kept triangle's setup is written and finished by the core's
// set_corners (depth, 1/w, varyings), and each one to be clipped goes back
// to the core, so the setups come in the order of the scalar loop.
//
// Every value is the scalar code's: the integers are exact, each double
// product and quotient is rounded once as there, and the conversions to
// double and to float round as the scalar ones do (test_raster.cpp holds
// every field of every setup to setup_triangle's, bit for bit).
//
// The lanes need AVX2's 256-bit integers and 32-by-32-bit multiplies: the
// portable path does nothing here, and the core's scalar loop takes its
// triangles.
#include "pipeline/assembly.hpp"
#include "pipeline/vertex.hpp"
#include "base/simd.hpp"

#include <bit>
#include <cstddef>
#include <cstdint>

namespace facet::FACET_KERNEL_NS {

#if defined(__AVX2__)

namespace {

constexpr int kLanes = 8;
using I32 = int32_t __attribute__((vector_size(4 * kLanes)));
using I64 = int64_t __attribute__((vector_size(8 * kLanes)));
using F64 = double __attribute__((vector_size(8 * kLanes)));
using F32 = float __attribute__((vector_size(4 * kLanes)));

// The position and outcodes of corner k of eight triangles: the first 16
// bytes of each WindowVertex (x, y, z, user), two triangles' a register,
// turned into columns.
void load_corners(const WideAssembly& a, const uint32_t* idx, int k, I32& x, I32& y, I32& user) {
    static_assert(offsetof(WindowVertex, x) == 0 && offsetof(WindowVertex, y) == 4 &&
                  offsetof(WindowVertex, user) == 12);
    __m256i row[4];  // triangles j and j + 4
    for (int j = 0; j < 4; ++j) {
        const WindowVertex& lo = a.window[idx[3 * j + k] - a.first_vertex];
        const WindowVertex& hi = a.window[idx[3 * (j + 4) + k] - a.first_vertex];
        row[j] = _mm256_loadu2_m128i(reinterpret_cast<const __m128i*>(&hi),
                                     reinterpret_cast<const __m128i*>(&lo));
    }
    const __m256i xy01 = _mm256_unpacklo_epi32(row[0], row[1]);  // x0 x1 y0 y1
    const __m256i xy23 = _mm256_unpacklo_epi32(row[2], row[3]);
    const __m256i zu01 = _mm256_unpackhi_epi32(row[0], row[1]);  // z0 z1 u0 u1
    const __m256i zu23 = _mm256_unpackhi_epi32(row[2], row[3]);
    x = std::bit_cast<I32>(_mm256_unpacklo_epi64(xy01, xy23));
    y = std::bit_cast<I32>(_mm256_unpackhi_epi64(xy01, xy23));
    user = std::bit_cast<I32>(_mm256_unpackhi_epi64(zu01, zu23));
}

// Lane i's bit set where lane i of a comparison is.
uint32_t bits(const I32& m) { return uint32_t(_mm256_movemask_ps(std::bit_cast<__m256>(m))); }
uint32_t bits(const I64& m) {
#if defined(__AVX512DQ__)
    return _mm512_movepi64_mask(std::bit_cast<__m512i>(m));
#else
    struct Halves { __m256d lo, hi; };
    const Halves h = std::bit_cast<Halves>(m);
    return uint32_t(_mm256_movemask_pd(h.lo)) | uint32_t(_mm256_movemask_pd(h.hi)) << 4;
#endif
}

I64 widen(const I32& v) { return __builtin_convertvector(v, I64); }

// a * b for a and b below 2^31 in magnitude: one multiply of the low
// halves, as x86 has it, rather than the compiler's three.
I64 multiply(const I64& a, const I64& b) {
#if defined(__AVX512F__)
    // The masked form: GCC 12 warns of the plain one's undefined source.
    return std::bit_cast<I64>(
        _mm512_maskz_mul_epi32(0xFF, std::bit_cast<__m512i>(a), std::bit_cast<__m512i>(b)));
#else
    struct Halves { __m256i lo, hi; };
    const Halves x = std::bit_cast<Halves>(a), y = std::bit_cast<Halves>(b);
    return std::bit_cast<I64>(Halves{_mm256_mul_epi32(x.lo, y.lo), _mm256_mul_epi32(x.hi, y.hi)});
#endif
}

// double(v), rounded to nearest as a scalar conversion rounds it, for
// |v| < 2^62. AVX-512 converts 64-bit integers; AVX2 adds the exact double
// of the high half, scaled by 2^32, to the exact double of the low half,
// which rounds the exact sum once.
F64 to_double(const I64& v) {
#if defined(__AVX512DQ__)
    return __builtin_convertvector(v, F64);
#else
    // 2^52 + 2^51 + n has the bits of its sum's integer n in its low 52
    // bits, for |n| < 2^51; and 2^52 + n for 0 <= n < 2^32.
    const I64 magic_signed = I64{} + std::bit_cast<int64_t>(0x1.8p52);
    const I64 magic = I64{} + std::bit_cast<int64_t>(0x1p52);
    const F64 high = std::bit_cast<F64>((v >> 32) + magic_signed) - 0x1.8p52;
    const F64 low = std::bit_cast<F64>((v & 0xFFFFFFFF) | magic) - 0x1p52;
    return high * 0x1p32 + low;
#endif
}

// The lanes of eight triangles that setup_kept_triangle fills in, for
// corners in the setup's order (a, b, c), and what decides each one's fate.
struct Lanes {
    alignas(32) int32_t x[3][kLanes], y[3][kLanes], dx[3][kLanes], dy[3][kLanes];
    alignas(32) int32_t bias[3][kLanes], span[kLanes], box[4][kLanes];
    alignas(64) int64_t area2[kLanes];
    alignas(64) double inv_area2[kLanes];
    alignas(32) float bary_dx[3][kLanes], bary_dy[3][kLanes];
    uint32_t flip = 0;          // corners b and c are vertices 2 and 1
    uint32_t front = 0;         // faces the viewer
    uint32_t kept = 0;          // facing and culling keep it, with area
    uint32_t clip = 0;          // a corner outside the guard band
    uint32_t no_pixels = 0;     // no pixel centre in its box
    uint32_t invalid = 0, outside = 0, back = 0, degenerate = 0;
};

// The edges, area and weights' planes of each lane (setup_kept_triangle).
void edges(const I32 x[3], const I32 y[3], const I64& area2, Lanes& out) {
    I32 flip32{};
    for (int j = 0; j < kLanes; ++j) flip32[j] = out.flip >> j & 1 ? -1 : 0;
    const I32 cx[3] = {x[0], flip32 ? x[2] : x[1], flip32 ? x[1] : x[2]};
    const I32 cy[3] = {y[0], flip32 ? y[2] : y[1], flip32 ? y[1] : y[2]};
    const I64 magnitude = area2 < 0 ? -area2 : area2;
    const F64 inv_area2 = 1.0 / to_double(magnitude);
    simd::store(out.area2, magnitude);
    simd::store(out.inv_area2, inv_area2);
    I32 span{};
    for (int k = 0; k < 3; ++k) {
        const int next = (k + 1) % 3, weight = (k + 2) % 3;  // edge k weighs vertex k + 2
        const I32 dx = cx[next] - cx[k], dy = cy[next] - cy[k];
        simd::store(out.x[k], cx[k]);
        simd::store(out.y[k], cy[k]);
        simd::store(out.dx[k], dx);
        simd::store(out.dy[k], dy);
        // Top-left rule (make_edge): 0 on a top or left edge, else -1.
        simd::store(out.bias[k], ~((dy < 0) | ((dy == 0) & (dx > 0))));
        const I32 extent = (dx < 0 ? -dx : dx) + (dy < 0 ? -dy : dy);
        span = extent > span ? extent : span;
        // double(-dy * 256) and double(dx * 256), exactly (and +0, not -0,
        // for a zero step, as the integer product gives).
        const F64 step_x = __builtin_convertvector(-dy, F64) * double(kSubpixelOne);
        const F64 step_y = __builtin_convertvector(dx, F64) * double(kSubpixelOne);
        simd::store(out.bary_dx[weight], __builtin_convertvector(step_x * inv_area2, F32));
        simd::store(out.bary_dy[weight], __builtin_convertvector(step_y * inv_area2, F32));
    }
    simd::store(out.span, span);
}

// The pixel bounding box of each lane (setup_kept_triangle's pixel_range),
// and the lanes whose box holds no pixel centre.
void boxes(const I32 x[3], const I32 y[3], const Viewport& viewport, Lanes& out) {
    const int32_t reach = viewport.samples > 1 ? int32_t(kSubpixelOne / 2) : 0;
    const int32_t half = int32_t(kSubpixelOne / 2);
    const auto lowest = [](const I32 v[3]) {
        const I32 m = v[0] < v[1] ? v[0] : v[1];
        return m < v[2] ? m : v[2];
    };
    const auto highest = [](const I32 v[3]) {
        const I32 m = v[0] > v[1] ? v[0] : v[1];
        return m > v[2] ? m : v[2];
    };
    // Coordinates lie within 2^29 sub-pixels (snap), so nothing overflows.
    I32 x0 = (lowest(x) - reach - half + int32_t(kSubpixelOne) - 1) >> kSubpixelBits;
    I32 x1 = (highest(x) + reach - half) >> kSubpixelBits;
    I32 y0 = (lowest(y) - reach - half + int32_t(kSubpixelOne) - 1) >> kSubpixelBits;
    I32 y1 = (highest(y) + reach - half) >> kSubpixelBits;
    x0 = x0 > 0 ? x0 : 0;
    y0 = y0 > 0 ? y0 : 0;
    const int32_t right = viewport.width - 1, bottom = viewport.target_rows() - 1;
    x1 = x1 < right ? x1 : right;
    y1 = y1 < bottom ? y1 : bottom;
    simd::store(out.box[0], x0);
    simd::store(out.box[1], y0);
    simd::store(out.box[2], x1);
    simd::store(out.box[3], y1);
    out.no_pixels = bits((x0 > x1) | (y0 > y1));
}

// The lanes whose box is at most 2x2 pixels and holds no centre the
// triangle covers (misses_small_box): its first centre's edge values,
// exact in 64 bits, and the steps of a pixel across and down.
uint32_t misses_small_boxes(const Lanes& l) {
    const I32 x0 = simd::load<I32>(l.box[0]), y0 = simd::load<I32>(l.box[1]);
    const I32 across = simd::load<I32>(l.box[2]) - x0, down = simd::load<I32>(l.box[3]) - y0;
    const uint32_t small = bits((across <= 1) & (down <= 1));
    if (!small) return 0;
    const int32_t half = int32_t(kSubpixelOne / 2);
    const I64 px = widen(x0 * int32_t(kSubpixelOne) + half);
    const I64 py = widen(y0 * int32_t(kSubpixelOne) + half);
    I64 hit[4] = {I64{} - 1, I64{} - 1, I64{} - 1, I64{} - 1};  // (0, 0), (1, 0), (0, 1), (1, 1)
    for (int k = 0; k < 3; ++k) {
        const I64 dx = widen(simd::load<I32>(l.dx[k])), dy = widen(simd::load<I32>(l.dy[k]));
        const I64 e = multiply(dx, py - widen(simd::load<I32>(l.y[k]))) -
                      multiply(dy, px - widen(simd::load<I32>(l.x[k]))) +
                      widen(simd::load<I32>(l.bias[k]));
        const I64 step_x = -dy * kSubpixelOne, step_y = dx * kSubpixelOne;
        hit[0] &= e >= 0;
        hit[1] &= e + step_x >= 0;
        hit[2] &= e + step_y >= 0;
        hit[3] &= e + step_x + step_y >= 0;
    }
    const I64 right = widen(across >= 1), below = widen(down >= 1);
    const I64 any = hit[0] | (hit[1] & right) | (hit[2] & below) | (hit[3] & right & below);
    return small & ~bits(any) & 0xFFu;
}

// The fate of eight triangles from their corners' outcodes and area, and
// what setup needs of the kept ones.
void classify(const WideAssembly& a, const uint32_t* idx, Lanes& out) {
    I32 x[3], y[3], user[3];
    for (int k = 0; k < 3; ++k) load_corners(a, idx, k, x[k], y[k], user[k]);
    out.no_pixels = 0;
    const I32 any = user[0] | user[1] | user[2];
    out.invalid = bits((any & int32_t(kInvalid)) != 0);
    out.outside = bits((user[0] & user[1] & user[2] & 0xFF) != 0) & ~out.invalid;
    const uint32_t rest = ~(out.invalid | out.outside) & 0xFFu;
    out.clip = bits((any >> 8 & 0xFF) != 0) & rest;
    const uint32_t no_window = bits((any & int32_t(kNoWindow)) != 0) & rest & ~out.clip;
    const uint32_t plain = rest & ~out.clip & ~no_window;
    // window_area2 and facing_result.
    const I64 area2 = multiply(widen(x[1] - x[0]), widen(y[2] - y[0])) -
                      multiply(widen(x[2] - x[0]), widen(y[1] - y[0]));
    const uint32_t negative = bits(area2 < 0), zero = bits(area2 == 0);
    const CullState& cull = a.cull;
    out.front = (cull.front_ccw ? negative : ~negative & ~zero) & 0xFFu;
    const uint32_t culled = (cull.cull_front ? out.front : 0u) | (cull.cull_back ? ~out.front : 0u);
    out.back = plain & ~zero & culled;
    out.kept = plain & ~zero & ~culled;
    out.degenerate = no_window | (plain & zero);
    out.flip = negative;
    if (!out.kept) return;
    edges(x, y, area2, out);
    boxes(x, y, a.viewport, out);
    if (a.viewport.samples == 1) out.no_pixels |= misses_small_boxes(out);
}

// The setup of lane j, triangle idx[3 j..] (setup_kept_triangle).
void write_setup(const WideAssembly& a, const uint32_t* idx, const Lanes& l, int j,
                 TriangleSetup& t) {
    for (int k = 0; k < 3; ++k)
        t.edge[k] = {l.x[k][j], l.y[k][j], l.dx[k][j], l.dy[k][j], l.bias[k][j]};
    t.area2 = l.area2[j];
    t.inv_area2 = l.inv_area2[j];
    for (int k = 0; k < 3; ++k) {
        t.bary_dx[k] = l.bary_dx[k][j];
        t.bary_dy[k] = l.bary_dy[k][j];
    }
    t.x0 = l.box[0][j], t.y0 = l.box[1][j], t.x1 = l.box[2][j], t.y1 = l.box[3][j];
    t.narrow = l.span[j] < kNarrowEdgeSpan;
    t.front_facing = l.front >> j & 1;
    const int second = l.flip >> j & 1 ? 2 : 1;
    const uint32_t* triangle = idx + 3 * j;
    const uint32_t vertex[3] = {triangle[0] - a.first_vertex, triangle[second] - a.first_vertex,
                                triangle[3 - second] - a.first_vertex};
    const WindowVertex* const corner[3] = {&a.window[vertex[0]], &a.window[vertex[1]],
                                           &a.window[vertex[2]]};
    const float* const varyings[3] = {a.varyings + size_t(vertex[0]) * a.vertex_floats,
                                      a.varyings + size_t(vertex[1]) * a.vertex_floats,
                                      a.varyings + size_t(vertex[2]) * a.vertex_floats};
    set_corners(corner, varyings, l.span[j], t);
}

}  // namespace

size_t assemble_triangles(const WideAssembly& a, const uint32_t* idx, size_t count,
                          SetupChunk& chunk) {
    AssemblyCounts n;
    size_t done = 0;
    Lanes lanes;
    for (; done + kLanes <= count; done += kLanes) {
        const uint32_t* first = idx + 3 * done;
        classify(a, first, lanes);
        n.invalid += uint64_t(std::popcount(lanes.invalid));
        n.outside += uint64_t(std::popcount(lanes.outside));
        n.back += uint64_t(std::popcount(lanes.back));
        n.degenerate += uint64_t(std::popcount(lanes.degenerate | (lanes.kept & lanes.no_pixels)));
        // The setups in the order of their triangles.
        for (uint32_t m = (lanes.kept & ~lanes.no_pixels) | lanes.clip; m; m &= m - 1) {
            const int j = std::countr_zero(m);
            if (lanes.clip >> j & 1) {
                a.clip(a.assembler, first + 3 * j, chunk);
                continue;
            }
            write_setup(a, first, lanes, j, chunk.setups.emplace_back());
            ++n.set_up;
        }
    }
    n.in = done;
    n.add_to(chunk.stats);
    return done;
}

#else

size_t assemble_triangles(const WideAssembly&, const uint32_t*, size_t, SetupChunk&) { return 0; }

#endif

}  // namespace facet::FACET_KERNEL_NS
