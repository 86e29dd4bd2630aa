// The texture sampler's filters, lane by lane (one of the per-ISA kernels,
// kernels.hpp): the steps sampler.cpp (nearest, bilinear, trilinear, cube
// maps) and sampler_anisotropic.cpp share, each inlined into the loops
// that use it. sampler.hpp says what they compute.
#pragma once

#ifndef FACET_KERNEL_NS
#error "texel_filters.hpp belongs to the per-ISA kernel sources (core/CMakeLists.txt)"
#endif

#include "base/simd.hpp"

#include "facet/texture.hpp"

#include <facet/shader_abi.h>

#include <bit>
#include <cstdint>

// The helpers below are inlined into each filter's loop: returned as
// values through memory, their vectors cost more than their work.
#define FACET_INLINE [[gnu::always_inline]] inline

namespace facet::FACET_KERNEL_NS::texel_filters {

constexpr int N = FACET_BLOCK_LANES;
using simd::Float;
using simd::Int;
using simd::kParts;
using simd::kWidth;
using simd::Short;

// The helpers below are inlined into each filter's loop: returned as
// values through memory, their vectors cost more than their work.

// Floats of this size or more have no fraction.
constexpr float kWhole = 8388608.0f;

struct Texels {
    Float r, g, b, a;
};

// A level's numbers, in each lane (levels may differ from lane to lane).
struct Level {
    Int width, height, tile_row, offset;
    Float fwidth, fheight;
};

FACET_INLINE Float splat(float v) { return Float{} + v; }

FACET_INLINE Level with_sizes(const Int& width, const Int& height, const Int& tile_row,
                              const Int& offset) {
    return {width, height, tile_row, offset, simd::to_float(width), simd::to_float(height)};
}

FACET_INLINE Level level_at(const TexelLevels& t, int i) {
    const TexelLevel& l = t.level[size_t(i)];
    return with_sizes(Int{} + l.width, Int{} + l.height, Int{} + l.tile_row, Int{} + l.offset);
}

FACET_INLINE Level level_at(const TexelLevels& t, const Int& i) {
    if (simd::bits(i == i[0]) == simd::kPartMask) return level_at(t, i[0]);  // the usual case
    static_assert(sizeof(TexelLevel) == 16);
    Int n[4];
    simd::gather4(reinterpret_cast<const int32_t*>(t.level.data()), i << 2, n);
    return with_sizes(n[0], n[1], n[2], n[3]);
}

// floor(x) for |x| < 2^31: the truncation, less one where it rounded up.
FACET_INLINE Int floor_int(const Float& x) {
    const Int t = __builtin_convertvector(x, Int);
    return t + (simd::to_float(t) > x);  // a comparison is -1 where it holds
}

// x - floor(x) where |x| < 2^23, else 0 (NaN and infinities too): exact.
// The other lanes are floored as 0, where floor_int would overflow.
FACET_INLINE Float fraction(const Float& x) {
    const Int small = simd::abs(x) < kWhole;
    const Float within = std::bit_cast<Float>(std::bit_cast<Int>(x) & small);
    return std::bit_cast<Float>(std::bit_cast<Int>(within - simd::to_float(floor_int(within))) &
                                small);
}

// A coordinate folded as its wrap repeats it, as the reference's fold()
// (texture.cpp): repeat into [0, 1), mirror into [0, 1], clamp within
// [-1, 2]; NaN as 0. Once a lane, for every level it reads.
template <Wrap W>
FACET_INLINE Float fold(const Float& u) {
    if constexpr (W == Wrap::repeat) {
        return fraction(u);
    } else if constexpr (W == Wrap::mirror) {
        const Float m = fraction(u * 0.5f) * 2.0f;  // [0, 2): exact
        return m > 1.0f ? 2.0f - m : m;
    } else {
        return simd::min(simd::max(u == u ? u : Float{}, splat(-1.0f)), splat(2.0f));
    }
}

// Texel index i, from a folded coordinate (-1 to n), into 0..n-1.
template <Wrap W>
FACET_INLINE Int wrap(const Int& i, const Int& n) {
    if constexpr (W == Wrap::repeat) {
        const Int k = i < 0 ? i + n : i;
        return k < n ? k : k - n;
    } else {
        const Int c = i < 0 ? Int{} : i;
        return c < n ? c : n - 1;
    }
}

// The index of texel (x, y) of level l, in texels (facet/texture.hpp's
// tiles: 20 texels a tile, 5 a row of one).
FACET_INLINE Int texel_index(const Level& l, const Int& x, const Int& y) {
    const Int tile_column = x >> 2, row = y & 3;
    return l.offset + (y >> 2) * l.tile_row + (tile_column << 4) + (tile_column << 2) + (row << 2) +
           row + (x & 3);
}

// The scale of a format's codes: rgba16 holds 14-bit linear codes, and
// rgba8's filtered codes are 8-bit ones times 64 (nearest reads them as
// they are).
constexpr float kScale16 = 1.0f / 16383.0f, kScale8 = 1.0f / 255.0f,
                kScaleFiltered8 = 1.0f / (255.0f * 64.0f);

// A word's two 16-bit codes, the low one first, as floats times k.
FACET_INLINE Float low_code(const Int& w, float k) { return simd::to_float(w & 0xFFFF) * k; }
FACET_INLINE Float high_code(const Int& w, float k) {
    return simd::to_float((w >> 16) & 0xFFFF) * k;
}

// A texel's words, decoded: rgba8's one, or rgba16's two.
template <TexelFormat F>
FACET_INLINE Texels decode(const Int& w0, const Int& w1) {
    if constexpr (F == TexelFormat::rgba8) {
        (void)w1;
        return {simd::to_float(w0 & 0xFF) * kScale8, simd::to_float((w0 >> 8) & 0xFF) * kScale8,
                simd::to_float((w0 >> 16) & 0xFF) * kScale8,
                simd::to_float((w0 >> 24) & 0xFF) * kScale8};
    } else {
        return {low_code(w0, kScale16), high_code(w0, kScale16), low_code(w1, kScale16),
                high_code(w1, kScale16)};
    }
}

FACET_INLINE const int32_t* words(const TexelLevels& t) {
    return reinterpret_cast<const int32_t*>(t.words);
}

// The texel at `index` of the lanes of `active`, decoded: 0 elsewhere.
template <TexelFormat F>
FACET_INLINE Texels fetch(const TexelLevels& t, const Int& index, const Int& active) {
    if constexpr (F == TexelFormat::rgba8) {
        return decode<F>(simd::gather(words(t), index, active), Int{});
    } else {
        const Int at = index + index;
        return decode<F>(simd::gather(words(t), at, active),
                         simd::gather(words(t), at + 1, active));
    }
}

// Filtering works on 16-bit codes, two channels of a lane in each 32-bit
// word: rgba16's (red, green) and (blue, alpha) as stored, rgba8's (red,
// blue) and (green, alpha) times 64. A code is at most 16383, so that a
// difference of two, doubled, is a 16-bit number.
struct Fixed {
    Short p, q;
};

// The two texels a row of a footprint gives each lane, with one load a
// lane: `index` and the texel after it (as repeat wraps it: the row's
// extra texel). Lanes outside `active` read texel 0 of the texture.
template <TexelFormat F>
FACET_INLINE void fetch_pair(const TexelLevels& t, Int index, const Int& active, Fixed& first,
                             Fixed& second) {
    index &= active;
    Int w[4];
    simd::gather4(words(t), F == TexelFormat::rgba16 ? index + index : index, w);
    const auto shorts = [](const Int& v) { return std::bit_cast<Short>(v); };
    if constexpr (F == TexelFormat::rgba8) {
        constexpr int32_t kCodes = 0x00FF00FF << 6;  // two bytes, times 64
        first = {shorts((w[0] << 6) & kCodes), shorts((w[0] >> 2) & kCodes)};
        second = {shorts((w[1] << 6) & kCodes), shorts((w[1] >> 2) & kCodes)};
    } else {
        first = {shorts(w[0]), shorts(w[1])};
        second = {shorts(w[2]), shorts(w[3])};
    }
}

// A weight in [0, 1) as 15-bit fixed point, floor(t 2^15), in both halves
// of each lane's word.
FACET_INLINE Short fixed_weight(const Float& t) {
    Int w = __builtin_convertvector(t * 32768.0f, Int);
    w = w < 32767 ? w : Int{} + 32767;
    return std::bit_cast<Short>(w | w << 16);
}

// a + floor((b - a) w / 2^15), each code.
FACET_INLINE Short lerp(const Short& a, const Short& b, const Short& w) {
    const Short d = b - a;
    return a + simd::mulhi(d + d, w);
}

FACET_INLINE Fixed lerp(const Fixed& a, const Fixed& b, const Short& w) {
    return {lerp(a.p, b.p, w), lerp(a.q, b.q, w)};
}

// Filtered codes back to linear floats.
template <TexelFormat F>
FACET_INLINE Texels unfixed(const Fixed& c) {
    const Int p = std::bit_cast<Int>(c.p), q = std::bit_cast<Int>(c.q);
    if constexpr (F == TexelFormat::rgba8)
        return {low_code(p, kScaleFiltered8), low_code(q, kScaleFiltered8),
                high_code(p, kScaleFiltered8), high_code(q, kScaleFiltered8)};
    else
        return {low_code(p, kScale16), high_code(p, kScale16), low_code(q, kScale16),
                high_code(q, kScale16)};
}

// From folded coordinates; a repeated one just below 1 can round to the
// width, which reads the last texel.
template <TexelFormat F, Wrap W>
FACET_INLINE Texels nearest(const TexelLevels& t, const Level& l, const Float& u, const Float& v,
                            const Int& active) {
    const Int x = wrap<W>(floor_int(u * l.fwidth), l.width),
              y = wrap<W>(floor_int(v * l.fheight), l.height);
    return fetch<F>(
        t, texel_index(l, x < l.width ? x : l.width - 1, y < l.height ? y : l.height - 1), active);
}

// Where in a row a bilinear footprint's pair of texels begins, and the
// second's weight, from x0, the footprint's first column (-1 to n - 1 from
// a folded coordinate): repeated, x0 wrapped, the pair being that texel
// and the next (the row's extra texel past the last); clamped (and
// mirrored, whose folded coordinate clamps), x0 clamped, the second's
// weight 0 where the two clamp to one texel.
struct RowPair {
    Int first;
    Float weight;
};

template <Wrap W>
FACET_INLINE RowPair row_pair(const Level& l, const Int& x0, const Float& fx) {
    if constexpr (W == Wrap::repeat) return {wrap<W>(x0, l.width), fx};
    return {wrap<W>(x0, l.width), x0 >= 0 && x0 < l.width - 1 ? fx : Float{}};
}

// A bilinear footprint of each lane: where its two rows' pairs of texels
// begin, and the weights of the second texel of a pair and of the second
// row.
struct Footprint {
    Int row_a, row_b;
    Short wx, wy;
};

template <Wrap W>
FACET_INLINE Footprint footprint(const Level& l, const Float& u, const Float& v) {
    const Float x = u * l.fwidth - 0.5f, y = v * l.fheight - 0.5f;
    const Int x0 = floor_int(x), y0 = floor_int(y);
    const Float fx = x - simd::to_float(x0), fy = y - simd::to_float(y0);
    const RowPair pair = row_pair<W>(l, x0, fx);
    const Int ya = wrap<W>(y0, l.height), yb = wrap<W>(y0 + 1, l.height);
    return {texel_index(l, pair.first, ya), texel_index(l, pair.first, yb),
            fixed_weight(pair.weight), fixed_weight(fy)};
}

// A footprint's four texels, as fetch_pair() loads them.
struct Quartet {
    Fixed a, b, c, d;
};

template <TexelFormat F>
FACET_INLINE Quartet fetch_footprint(const TexelLevels& t, const Footprint& f,
                                     const Int& active) {
    Quartet q;
    fetch_pair<F>(t, f.row_a, active, q.a, q.b);
    fetch_pair<F>(t, f.row_b, active, q.c, q.d);
    return q;
}

FACET_INLINE Fixed filter(const Quartet& q, const Footprint& f) {
    return lerp(lerp(q.a, q.b, f.wx), lerp(q.c, q.d, f.wx), f.wy);
}

template <TexelFormat F, Wrap W>
FACET_INLINE Fixed bilinear(const TexelLevels& t, const Level& l, const Float& u, const Float& v,
                            const Int& active) {
    const Footprint f = footprint<W>(l, u, v);
    return filter(fetch_footprint<F>(t, f, active), f);
}

// Four floats and four ints: one a 2x2 quad of a block, for the level of
// detail, worked out once a block whatever the path's width.
using Quad = float __attribute__((vector_size(16)));
using QuadInt = int32_t __attribute__((vector_size(16)));

// log2(x) for finite x >= FLT_MIN: x = m 2^e with m in [sqrt(1/2),
// sqrt(2)), and log2 m = log2(1 + s) for s = m - 1 from a polynomial of
// degree 6 fitted by least squares at Chebyshev nodes (error below 2.5e-6).
// Below FLT_MIN it gives about -127. For a quad's floats or a part's.
template <class V>
FACET_INLINE V log2(const V& x) {
    using Bits = decltype(x < x);  // the integer vector of V's shape
    const Bits bits = std::bit_cast<Bits>(x);
    V e = __builtin_convertvector(((bits >> 23) & 0xFF) - 127, V);
    V m = std::bit_cast<V>((bits & 0x7FFFFF) | 0x3F800000);  // [1, 2)
    const Bits high = m > 1.41421356f;
    m = high ? m * 0.5f : m;
    e = high ? e + 1.0f : e;
    const V s = m - 1.0f;
    const V p =
        1.44271577f +
        s * (-0.721122539f +
             s * (0.479324359f + s * (-0.367703982f + s * (0.322085496f + s * -0.205298295f))));
    return e + s * p;
}

// The screen derivatives of u and v, UV units a pixel: du/dx, dv/dx,
// du/dy, dv/dy. Of each 2x2 quad of a block (Quad: quads in the order top
// left, top right, bottom left, bottom right), or of each lane (Float).
template <class V>
struct Derivatives {
    V ux, vx, uy, vy;
};

// Each quad's, from its top-left, top-right and bottom-left lanes' u and v
// (all 16 lanes hold coordinates).
FACET_INLINE Derivatives<Quad> block_derivatives(const float* u, const float* v) {
    const auto corners = [](const float* a, Quad& tl, Quad& tr, Quad& bl) {
        const Quad r0 = simd::load<Quad>(a), r1 = simd::load<Quad>(a + 4);
        const Quad r2 = simd::load<Quad>(a + 8), r3 = simd::load<Quad>(a + 12);
        tl = __builtin_shufflevector(r0, r2, 0, 2, 4, 6);
        tr = __builtin_shufflevector(r0, r2, 1, 3, 5, 7);
        bl = __builtin_shufflevector(r1, r3, 0, 2, 4, 6);
    };
    Quad utl, utr, ubl, vtl, vtr, vbl;
    corners(u, utl, utr, ubl);
    corners(v, vtl, vtr, vbl);
    return {utr - utl, vtr - vtl, ubl - utl, vbl - vtl};
}

// The level of detail of each quad: log2 of the longer axis of its
// footprint in level-0 texels.
FACET_INLINE Quad block_lods(const TexelLevels& t, const Derivatives<Quad>& d) {
    const float w = float(t.level[0].width), h = float(t.level[0].height);
    const Quad xu = d.ux * w, xv = d.vx * h;
    const Quad yu = d.uy * w, yv = d.vy * h;
    // As std::max(x, y) in the reference: x where they are unordered.
    const Quad x2 = xu * xu + xv * xv, y2 = yu * yu + yv * yv;
    const Quad rho2 = y2 > x2 ? y2 : x2;
    return rho2 == rho2 ? log2(rho2) * 0.5f : Quad{};  // NaN: level 0
}

// Each lane of part p with its quad's value.
FACET_INLINE Float per_lane(const Quad& q, int p) {
#if FACET_SIMD_WIDTH == 16
    (void)p;
    return __builtin_shufflevector(q, q, 0, 0, 1, 1, 0, 0, 1, 1, 2, 2, 3, 3, 2, 2, 3, 3);
#elif FACET_SIMD_WIDTH == 8
    return p == 0 ? __builtin_shufflevector(q, q, 0, 0, 1, 1, 0, 0, 1, 1)  // rows 0 and 1
                  : __builtin_shufflevector(q, q, 2, 2, 3, 3, 2, 2, 3, 3);
#else
    return p < 2 ? __builtin_shufflevector(q, q, 0, 0, 1, 1)  // row p
                 : __builtin_shufflevector(q, q, 2, 2, 3, 3);
#endif
}

// The levels of each lane's face (`face` times the levels a face has: 0
// but for a cube) filtered at its level of detail.
template <TexelFormat F, Wrap W>
FACET_INLINE Texels trilinear(const TexelLevels& t, const Float& lod, const Float& u,
                              const Float& v, const Int& active, const Int& face = Int{}) {
    const Float l =
        simd::min(simd::max(lod == lod ? lod : Float{}, Float{}), splat(float(t.levels - 1)));
    const Int lo = __builtin_convertvector(l, Int);  // l >= 0: the floor
    const Float frac = l - simd::to_float(lo);
    const Int second = active & (frac > 0.0f);  // then lo + 1 is a level
    const Footprint fa = footprint<W>(level_at(t, face + lo), u, v);
    if (!simd::bits(second)) return unfixed<F>(filter(fetch_footprint<F>(t, fa, active), fa));
    // Both levels' addresses first, then their loads together, then the
    // arithmetic: the loads of the second level wait on no filtering.
    const Footprint fb = footprint<W>(level_at(t, face + (second ? lo + 1 : lo)), u, v);
    const Quartet qa = fetch_footprint<F>(t, fa, active), qb = fetch_footprint<F>(t, fb, second);
    const Fixed a = filter(qa, fa), b = filter(qb, fb);
    return unfixed<F>(lerp(a, b, fixed_weight(frac)));  // frac 0: a, exactly
}

// x at the lanes of `keep`, 0 at the others.
FACET_INLINE Float kept(const Float& x, const Int& keep) {
    return std::bit_cast<Float>(std::bit_cast<Int>(x) & keep);
}

// Each lane's cube face (0..5, times `levels`) and where its direction
// meets it, (u, v): the reference's cube_face() (texture.cpp), step by step.
FACET_INLINE Int cube_faces(const Float& x, const Float& y, const Float& z, int levels, Float& u,
                            Float& v) {
    const Float ax = simd::abs(x), ay = simd::abs(y), az = simd::abs(z);
    const Int on_x = (ax >= ay) & (ax >= az), on_y = ~on_x & (ay >= az);
    const Int face = on_x ? (x > 0.0f ? Int{} : Int{} + 1)
                          : on_y ? (y > 0.0f ? Int{} + 2 : Int{} + 3)
                                 : (z > 0.0f ? Int{} + 4 : Int{} + 5);
    const Float sc = on_x ? (x > 0.0f ? -z : z) : on_y ? x : (z > 0.0f ? x : -x);
    const Float tc = on_x ? -y : on_y ? (y > 0.0f ? z : -z) : -y;
    const Float ma = on_x ? ax : on_y ? ay : az;
    const Int none = ~(ma > 0.0f);  // no direction (0, or NaN): the face's middle
    u = none ? splat(0.5f) : (sc / ma + 1.0f) * 0.5f;
    v = none ? splat(0.5f) : (tc / ma + 1.0f) * 0.5f;
    return face * levels;
}

// Lanes of a bit mask of part p as all ones or zero.
FACET_INLINE Int active_lanes(uint32_t lanes) {
    Int bit;
    for (int j = 0; j < kWidth; ++j) bit[j] = int32_t(1u << j);
    return ((Int{} + int32_t(lanes)) & bit) != 0;
}

// Part p of the output: c at the lanes of `active`, 0 at the others.
FACET_INLINE void store(float* rgba, int p, const Texels& c, const Int& active) {
    simd::store(rgba + p * kWidth, kept(c.r, active));
    simd::store(rgba + N + p * kWidth, kept(c.g, active));
    simd::store(rgba + 2 * N + p * kWidth, kept(c.b, active));
    simd::store(rgba + 3 * N + p * kWidth, kept(c.a, active));
}

// Where a part's lanes read: their raw coordinates, and their level of
// detail or derivatives as given per lane (null: from the block's quads).
struct Lanes {
    const float *u, *v, *lod, *grads;
};

// The lanes of `mask` of an anisotropic 2D binding (sampler_anisotropic.cpp).
void sample_anisotropic(const TexelLevels& t, const TextureBinding& b, const Lanes& in,
                        uint32_t mask, float* rgba);

}  // namespace facet::FACET_KERNEL_NS::texel_filters
