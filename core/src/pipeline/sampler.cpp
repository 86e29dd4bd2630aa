// The per-path texture sampler (sampler.hpp): a vector of lanes at a time.
#include "pipeline/sampler.hpp"

#include "base/simd.hpp"

#include <facet/shader_abi.h>

#include <algorithm>
#include <bit>

namespace facet::FACET_KERNEL_NS {

namespace {

constexpr int N = FACET_BLOCK_LANES;
using simd::Float;
using simd::Int;
using simd::kParts;
using simd::kWidth;
using simd::Short;

// The helpers below are inlined into each filter's loop: returned as
// values through memory, their vectors cost more than their work.
#define FACET_INLINE [[gnu::always_inline]] inline

// Coordinates are pinned within +-2^23 texels, where a float still has
// whole numbers and a wrap's arithmetic below stays exact.
constexpr float kLimit = 8388608.0f;

struct Texels {
    Float r, g, b, a;
};

// The wrap a binding and a texture's sizes give, resolved once a call.
enum class WrapKind { repeat_pow2, repeat, mirror_pow2, mirror, clamp };

// A level's numbers, in each lane (levels may differ from lane to lane).
struct Level {
    Int width, height, stride, offset;
    Float fwidth, fheight, inv_width, inv_height;
};

FACET_INLINE Float splat(float v) { return Float{} + v; }

FACET_INLINE Level level_at(const TexelLevels& t, int i) {
    const TexelLevel& l = t.level[size_t(i)];
    return {Int{} + l.width, Int{} + l.height, Int{} + l.stride,   Int{} + l.offset,
            splat(l.fwidth), splat(l.fheight), splat(l.inv_width), splat(l.inv_height)};
}

FACET_INLINE Level level_at(const TexelLevels& t, const Int& i) {
    if (simd::bits(i == i[0]) == simd::kPartMask) return level_at(t, i[0]);  // the usual case
    static_assert(sizeof(TexelLevel) == 32);
    const auto* records = reinterpret_cast<const int32_t*>(t.level.data());
    Int n[4], f[4];
    simd::gather4(records, i << 3, n);
    simd::gather4(records + 4, i << 3, f);
    const auto floats = [](const Int& v) { return std::bit_cast<Float>(v); };
    return {n[0], n[1], n[2], n[3], floats(f[0]), floats(f[1]), floats(f[2]), floats(f[3])};
}

// NaN as 0, then within +-kLimit.
FACET_INLINE Float pinned(Float x) {
    x = x == x ? x : Float{};
    return simd::min(simd::max(x, splat(-kLimit)), splat(kLimit));
}

// floor(x) for |x| <= kLimit: the truncation, less one where it rounded up.
FACET_INLINE Int floor_int(const Float& x) {
    const Int t = __builtin_convertvector(x, Int);
    return t + (simd::to_float(t) > x);  // a comparison is -1 where it holds
}

// Texel index i of a level n texels across, wrapped into 0..n-1.
template <WrapKind W>
FACET_INLINE Int wrap(const Int& i, const Int& n, const Float& fn, const Float& inv_n) {
    if constexpr (W == WrapKind::repeat_pow2) {
        return i & (n - 1);
    } else if constexpr (W == WrapKind::mirror_pow2) {
        const Int k = i & (n + n - 1);
        return k < n ? k : n + n - 1 - k;
    } else if constexpr (W == WrapKind::clamp) {
        const Int c = i < 0 ? Int{} : i;
        return c < n ? c : n - 1;
    } else {
        // i modulo the period (n, or 2n mirrored) in floats, exact for
        // |i| <= 2^23: the quotient may come out one off, which the two
        // corrections mend.
        constexpr bool mirror = W == WrapKind::mirror;
        const Float period = mirror ? fn + fn : fn, inv = mirror ? inv_n * 0.5f : inv_n;
        const Float fi = simd::to_float(i);
        Float r = fi - simd::to_float(floor_int(fi * inv)) * period;
        r = r < 0.0f ? r + period : r;
        r = r >= period ? r - period : r;
        const Int k = __builtin_convertvector(r, Int);
        if constexpr (mirror) return k < n ? k : n + n - 1 - k;
        return k;
    }
}

// The index of texel (x, y) of level l, in texels.
FACET_INLINE Int texel_index(const Level& l, const Int& x, const Int& y) {
    return l.offset + y * l.stride + x;
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

template <TexelFormat F, WrapKind W>
FACET_INLINE Texels nearest(const TexelLevels& t, const Level& l, const Float& u, const Float& v,
                            const Int& active) {
    const Int x = wrap<W>(floor_int(pinned(u * l.fwidth)), l.width, l.fwidth, l.inv_width);
    const Int y = wrap<W>(floor_int(pinned(v * l.fheight)), l.height, l.fheight, l.inv_height);
    return fetch<F>(t, texel_index(l, x, y), active);
}

// Where in a row a bilinear footprint's pair of texels begins, and the
// second's weight: texels x0 and x0 + 1 wrapped, k0 and k1, are either
// next to each other (k1 = k0 + 1, or, repeating, k0 the last and k1 the
// first, which the row's extra texel holds), or k1 = k0 - 1 (mirrored:
// the pair from k1, weighted the other way), or the same texel (clamped,
// or where mirroring turns: weight 0).
struct RowPair {
    Int first;
    Float weight;
};

template <WrapKind W>
FACET_INLINE RowPair row_pair(const Level& l, const Int& x0, const Float& fx) {
    if constexpr (W == WrapKind::repeat_pow2 || W == WrapKind::repeat) {
        return {wrap<W>(x0, l.width, l.fwidth, l.inv_width), fx};
    } else if constexpr (W == WrapKind::clamp) {
        const Int k0 = wrap<W>(x0, l.width, l.fwidth, l.inv_width);
        return {k0, x0 >= 0 && x0 < l.width - 1 ? fx : Float{}};
    } else {
        const Int k0 = wrap<W>(x0, l.width, l.fwidth, l.inv_width);
        const Int k1 = wrap<W>(x0 + 1, l.width, l.fwidth, l.inv_width);
        return {k1 < k0 ? k1 : k0, k1 > k0 ? fx : k1 < k0 ? 1.0f - fx : Float{}};
    }
}

template <TexelFormat F, WrapKind W>
FACET_INLINE Fixed bilinear(const TexelLevels& t, const Level& l, const Float& u, const Float& v,
                            const Int& active) {
    const Float x = pinned(u * l.fwidth - 0.5f), y = pinned(v * l.fheight - 0.5f);
    const Int x0 = floor_int(x), y0 = floor_int(y);
    const Float fx = x - simd::to_float(x0), fy = y - simd::to_float(y0);
    const RowPair pair = row_pair<W>(l, x0, fx);
    const Int ya = wrap<W>(y0, l.height, l.fheight, l.inv_height);
    const Int yb = wrap<W>(y0 + 1, l.height, l.fheight, l.inv_height);
    Fixed a, b, c, d;
    fetch_pair<F>(t, texel_index(l, pair.first, ya), active, a, b);
    fetch_pair<F>(t, texel_index(l, pair.first, yb), active, c, d);
    const Short wx = fixed_weight(pair.weight);
    return lerp(lerp(a, b, wx), lerp(c, d, wx), fixed_weight(fy));
}

// log2(x) for finite x >= FLT_MIN: x = m 2^e with m in [sqrt(1/2),
// sqrt(2)), and log2 m = log2(1 + s) for s = m - 1 from a polynomial of
// degree 6 fitted by least squares at Chebyshev nodes (error below 2.5e-6).
// Below FLT_MIN it gives about -127.
FACET_INLINE Float log2(const Float& x) {
    const Int bits = std::bit_cast<Int>(x);
    Float e = simd::to_float(((bits >> 23) & 0xFF) - 127);
    Float m = std::bit_cast<Float>((bits & 0x7FFFFF) | 0x3F800000);  // [1, 2)
    const Int high = m > 1.41421356f;
    m = high ? m * 0.5f : m;
    e = high ? e + 1.0f : e;
    const Float s = m - 1.0f;
    const Float p =
        1.44271577f +
        s * (-0.721122539f +
             s * (0.479324359f + s * (-0.367703982f + s * (0.322085496f + s * -0.205298295f))));
    return e + s * p;
}

// Each lane's quad's top-left, top-right and bottom-left values of a, a
// block's 16 floats, for part p.
struct QuadCorners {
    Float tl, tr, bl;
};

FACET_INLINE QuadCorners quad_corners(const float* a, int p) {
#if FACET_SIMD_WIDTH == 16
    (void)p;
    const Float x = simd::load<Float>(a);
    return {__builtin_shufflevector(x, x, 0, 0, 2, 2, 0, 0, 2, 2, 8, 8, 10, 10, 8, 8, 10, 10),
            __builtin_shufflevector(x, x, 1, 1, 3, 3, 1, 1, 3, 3, 9, 9, 11, 11, 9, 9, 11, 11),
            __builtin_shufflevector(x, x, 4, 4, 6, 6, 4, 4, 6, 6, 12, 12, 14, 14, 12, 12, 14, 14)};
#elif FACET_SIMD_WIDTH == 8
    const Float x = simd::load<Float>(a + 8 * p);  // rows 2p and 2p + 1: whole quads
    return {__builtin_shufflevector(x, x, 0, 0, 2, 2, 0, 0, 2, 2),
            __builtin_shufflevector(x, x, 1, 1, 3, 3, 1, 1, 3, 3),
            __builtin_shufflevector(x, x, 4, 4, 6, 6, 4, 4, 6, 6)};
#else
    const int top_row = p & ~1;  // row p's quads begin on the even row
    const Float top = simd::load<Float>(a + 4 * top_row);
    const Float bottom = simd::load<Float>(a + 4 * (top_row + 1));
    return {__builtin_shufflevector(top, top, 0, 0, 2, 2),
            __builtin_shufflevector(top, top, 1, 1, 3, 3),
            __builtin_shufflevector(bottom, bottom, 0, 0, 2, 2)};
#endif
}

// Level of detail of part p's lanes: log2 of the longer axis of their
// quad's footprint in level-0 texels.
FACET_INLINE Float quad_lod(const TexelLevels& t, const float* u, const float* v, int p) {
    const QuadCorners cu = quad_corners(u, p), cv = quad_corners(v, p);
    const Float w = splat(t.level[0].fwidth), h = splat(t.level[0].fheight);
    const Float xu = (cu.tr - cu.tl) * w, xv = (cv.tr - cv.tl) * h;
    const Float yu = (cu.bl - cu.tl) * w, yv = (cv.bl - cv.tl) * h;
    // As std::max(x, y) in the reference: x where they are unordered.
    const Float x2 = xu * xu + xv * xv, y2 = yu * yu + yv * yv;
    const Float rho2 = simd::max(y2, x2);
    return rho2 == rho2 ? log2(rho2) * 0.5f : Float{};  // NaN: level 0
}

template <TexelFormat F, WrapKind W>
FACET_INLINE Texels trilinear(const TexelLevels& t, const Float& lod, const Float& u,
                              const Float& v, const Int& active) {
    const Float l =
        simd::min(simd::max(lod == lod ? lod : Float{}, Float{}), splat(float(t.levels - 1)));
    const Int lo = __builtin_convertvector(l, Int);  // l >= 0: the floor
    const Float frac = l - simd::to_float(lo);
    const Fixed a = bilinear<F, W>(t, level_at(t, lo), u, v, active);
    const Int second = active & (frac > 0.0f);  // then lo + 1 is a level
    if (!simd::bits(second)) return unfixed<F>(a);
    const Fixed b = bilinear<F, W>(t, level_at(t, second ? lo + 1 : lo), u, v, second);
    return unfixed<F>(lerp(a, b, fixed_weight(frac)));  // frac 0: a, exactly
}

// Lanes of a bit mask of part p as all ones or zero.
FACET_INLINE Int active_lanes(uint32_t lanes) {
    Int bit;
    for (int j = 0; j < kWidth; ++j) bit[j] = int32_t(1u << j);
    return ((Int{} + int32_t(lanes)) & bit) != 0;
}

// Part p of the output: c at the lanes of `active`, 0 at the others.
FACET_INLINE void store(float* rgba, int p, const Texels& c, const Int& active) {
    const auto kept = [&](const Float& x) {
        return std::bit_cast<Float>(std::bit_cast<Int>(x) & active);
    };
    simd::store(rgba + p * kWidth, kept(c.r));
    simd::store(rgba + N + p * kWidth, kept(c.g));
    simd::store(rgba + 2 * N + p * kWidth, kept(c.b));
    simd::store(rgba + 3 * N + p * kWidth, kept(c.a));
}

// Every part with a lane in `mask`, with its levels of detail from `lod`
// or, where that is null, from the quads.
template <TexelFormat F, WrapKind W>
void sample_parts(const TexelLevels& t, Filter filter, const float* u, const float* v,
                  const float* lod, uint32_t mask, float* rgba) {
    for (int p = 0; p < kParts; ++p) {
        const uint32_t lanes = simd::part_mask(mask, p);
        if (!lanes) {
            store(rgba, p, Texels{}, Int{});
            continue;
        }
        const Int active = active_lanes(lanes);
        const Float fu = simd::load<Float>(u + p * kWidth), fv = simd::load<Float>(v + p * kWidth);
        switch (filter) {
            case Filter::nearest:
                store(rgba, p, nearest<F, W>(t, level_at(t, 0), fu, fv, active), active);
                break;
            case Filter::bilinear:
                store(rgba, p, unfixed<F>(bilinear<F, W>(t, level_at(t, 0), fu, fv, active)),
                      active);
                break;
            case Filter::trilinear: {
                const Float l = lod ? simd::load<Float>(lod + p * kWidth) : quad_lod(t, u, v, p);
                store(rgba, p, trilinear<F, W>(t, l, fu, fv, active), active);
                break;
            }
        }
    }
}

WrapKind wrap_kind(Wrap wrap, bool pow2) {
    switch (wrap) {
        case Wrap::clamp:
            return WrapKind::clamp;
        case Wrap::mirror:
            return pow2 ? WrapKind::mirror_pow2 : WrapKind::mirror;
        case Wrap::repeat:
            break;
    }
    return pow2 ? WrapKind::repeat_pow2 : WrapKind::repeat;
}

template <TexelFormat F>
void sample_format(const TexelLevels& t, const TextureBinding& b, const float* u, const float* v,
                   const float* lod, uint32_t mask, float* rgba) {
    switch (wrap_kind(b.wrap, t.pow2)) {
        case WrapKind::repeat_pow2:
            return sample_parts<F, WrapKind::repeat_pow2>(t, b.filter, u, v, lod, mask, rgba);
        case WrapKind::repeat:
            return sample_parts<F, WrapKind::repeat>(t, b.filter, u, v, lod, mask, rgba);
        case WrapKind::mirror_pow2:
            return sample_parts<F, WrapKind::mirror_pow2>(t, b.filter, u, v, lod, mask, rgba);
        case WrapKind::mirror:
            return sample_parts<F, WrapKind::mirror>(t, b.filter, u, v, lod, mask, rgba);
        case WrapKind::clamp:
            return sample_parts<F, WrapKind::clamp>(t, b.filter, u, v, lod, mask, rgba);
    }
}

void sample(const TextureBinding& b, const float* u, const float* v, const float* lod,
            uint32_t mask, float* rgba) {
    const TexelLevels* t = b.texture ? &b.texture->sampled() : nullptr;
    if (!t || t->levels == 0) {  // nothing bound reads as white
        for (int c = 0; c < 4; ++c)
            for (int i = 0; i < N; ++i) rgba[c * N + i] = mask >> i & 1u ? 1.0f : 0.0f;
        return;
    }
    if (t->format == TexelFormat::rgba16)
        sample_format<TexelFormat::rgba16>(*t, b, u, v, lod, mask, rgba);
    else
        sample_format<TexelFormat::rgba8>(*t, b, u, v, lod, mask, rgba);
}

#undef FACET_INLINE

}  // namespace

void sample_block(const TextureBinding& binding, const float* u, const float* v, uint32_t mask,
                  float* rgba) {
    sample(binding, u, v, nullptr, mask, rgba);
}

void sample_lod(const TextureBinding& binding, const float* u, const float* v, const float* lod,
                uint32_t mask, float* rgba) {
    static const float kLevelZero[N] = {};
    sample(binding, u, v, lod ? lod : kLevelZero, mask, rgba);
}

}  // namespace facet::FACET_KERNEL_NS
