// Output: colour formats, a part of a block at a time (one of the per-ISA
// kernels, kernels.hpp): exact encoding to and decoding from srgb8, rgba16f
// and rgba32f, and the parts of 4x4 blocks the fragment stage reads and
// writes. The scalar codecs of framebuffer.hpp define the results; tests
// hold these to them on every path.
//
// Takes: a block's colours (linear float lanes) and a target's format.
// Gives: the target's stored bits for them, and back.
#pragma once

#include "base/srgb8_tables.hpp"
#include "base/simd.hpp"

#include "facet/framebuffer.hpp"

#include <bit>

namespace facet::FACET_KERNEL_NS {

using simd::Float;
using simd::Int;
using simd::kWidth;

// Linear RGBA of kWidth pixels, a channel per vector.
struct Rgba {
    Float r, g, b, a;
};

// linear_to_srgb8 of each lane (base/srgb8_tables.hpp).
inline Int srgb8_encode(const Float& x) {
    const Float c = x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f;  // NaN fails: 0
    const Int bits = std::bit_cast<Int>(c);
    Int b = (bits >> 16) - Srgb8Tables::kFirstBucket;  // 1.0 is the last bucket
    b = b < 0 ? 0 : b;  // below 2^-13: the first bucket, which holds no threshold
    const Int entry = simd::gather(kSrgb8.bucket, b);
    return (entry >> 17) - ((bits & 0xFFFF) >= (entry & 0x1FFFF));
}

inline Float srgb8_decode(const Int& code) { return simd::gather(kSrgb8.decode, code); }

// unorm8: round(255 v) with halves away from zero, v clamped to 0..1.
inline Int unorm8_encode(const Float& v) {
    const Float c = v > 1.0f ? 1.0f : v > 0.0f ? v : 0.0f;  // NaN: 0
    const Float p = c * 255.0f;
    const Float even = (p + 8388608.0f) - 8388608.0f;  // nearest, ties to even (p < 2^23)
    return __builtin_convertvector(p - even == 0.5f ? even + 1.0f : even, Int);
}

// float_to_half of each lane, in the low 16 bits.
inline Int half_encode(const Float& x) {
#if defined(__AVX512F__)
    using Halves = uint16_t __attribute__((vector_size(2 * kWidth)));
    return __builtin_convertvector(std::bit_cast<Halves>(_mm512_maskz_cvtps_ph(
                                       0xFFFF, std::bit_cast<__m512>(x), _MM_FROUND_TO_NEAREST_INT)),
                                   Int);
#elif defined(__F16C__) && defined(__AVX2__)
    using Halves = uint16_t __attribute__((vector_size(2 * kWidth)));
    return __builtin_convertvector(
        std::bit_cast<Halves>(_mm256_cvtps_ph(std::bit_cast<__m256>(x), _MM_FROUND_TO_NEAREST_INT)),
        Int);
#else
    const Int u = std::bit_cast<Int>(x);
    const Int sign = (u >> 16) & 0x8000;
    const Int a = u & 0x7FFFFFFF;
    const Int nan = sign | 0x7E00 | ((a >> 13) & 0x3FF);
    const Int normal = sign | ((a - 0x38000000 + 0xFFF + ((a >> 13) & 1)) >> 13);
    // 2^24: subnormal halves as integers (the other lanes, which may be NaN or
    // too large to convert, as 0).
    const Float scaled = std::bit_cast<Float>(a < 0x38800000 ? a : 0) * 16777216.0f;
    const Int subnormal = sign | __builtin_convertvector((scaled + 8388608.0f) - 8388608.0f, Int);
    return a > 0x7F800000 ? nan
           : a >= 0x477FF000 ? (sign | 0x7C00)
           : a >= 0x38800000 ? normal
                             : subnormal;
#endif
}

// half_to_float of the low 16 bits of each lane.
inline Float half_decode(const Int& h) {
    const Int sign = (h & 0x8000) << 16;
    const Int exponent = (h >> 10) & 0x1F, mantissa = h & 0x3FF;
    const Int sub = std::bit_cast<Int>(simd::to_float(mantissa) * 5.9604645e-8f);  // 2^-24
    const Int bits = exponent == 0    ? sub
                     : exponent == 31 ? (0x7F800000 | mantissa << 13)
                                      : ((exponent + 112) << 23 | mantissa << 13);
    return std::bit_cast<Float>(sign | bits);
}

// kWidth pixels packed in lane order, as the format stores them.
struct Packed {
    alignas(64) uint8_t bytes[16 * kWidth];
};

// Interleaves the lanes of a and b: a0 b0 a1 b1 ... into lo, then hi.
template <class V>
inline void interleave(const V& a, const V& b, V& lo, V& hi) {
    constexpr int n = sizeof(V) / sizeof(a[0]);
    if constexpr (n == 2) {
        lo = __builtin_shufflevector(a, b, 0, 2);
        hi = __builtin_shufflevector(a, b, 1, 3);
    } else if constexpr (n == 4) {
        lo = __builtin_shufflevector(a, b, 0, 4, 1, 5);
        hi = __builtin_shufflevector(a, b, 2, 6, 3, 7);
    } else if constexpr (n == 8) {
        lo = __builtin_shufflevector(a, b, 0, 8, 1, 9, 2, 10, 3, 11);
        hi = __builtin_shufflevector(a, b, 4, 12, 5, 13, 6, 14, 7, 15);
    } else {
        static_assert(n == 16);
        lo = __builtin_shufflevector(a, b, 0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
        hi = __builtin_shufflevector(a, b, 8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30,
                                     15, 31);
    }
}

// The opposite: the even lanes of a then of b into even, the odd ones into odd.
template <class V>
inline void deinterleave(const V& a, const V& b, V& even, V& odd) {
    constexpr int n = sizeof(V) / sizeof(a[0]);
    if constexpr (n == 2) {
        even = __builtin_shufflevector(a, b, 0, 2);
        odd = __builtin_shufflevector(a, b, 1, 3);
    } else if constexpr (n == 4) {
        even = __builtin_shufflevector(a, b, 0, 2, 4, 6);
        odd = __builtin_shufflevector(a, b, 1, 3, 5, 7);
    } else if constexpr (n == 8) {
        even = __builtin_shufflevector(a, b, 0, 2, 4, 6, 8, 10, 12, 14);
        odd = __builtin_shufflevector(a, b, 1, 3, 5, 7, 9, 11, 13, 15);
    } else {
        static_assert(n == 16);
        even = __builtin_shufflevector(a, b, 0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
        odd = __builtin_shufflevector(a, b, 1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
    }
}

// Two floats as one lane, to move r-g and b-a pairs together.
using Pairs = double __attribute__((vector_size(4 * kWidth)));

// kWidth pixels encoded in `format`, written to `out` in lane order; and
// read back. `out` and `in` may be anywhere (an image's row, a Packed).
inline void pack(ColorFormat format, const Rgba& c, uint8_t* out) {
    switch (format) {
        case ColorFormat::srgb8:
            simd::store(out, srgb8_encode(c.r) | srgb8_encode(c.g) << 8 |
                                 srgb8_encode(c.b) << 16 | unorm8_encode(c.a) << 24);
            return;
        case ColorFormat::rgba16f: {
            Int p[2];
            interleave(half_encode(c.r) | half_encode(c.g) << 16,
                       half_encode(c.b) | half_encode(c.a) << 16, p[0], p[1]);
            simd::store(out, p[0]);
            simd::store(out + sizeof p[0], p[1]);
            return;
        }
        case ColorFormat::rgba32f: {
            Float rg[2], ba[2];
            interleave(c.r, c.g, rg[0], rg[1]);  // r0 g0 r1 g1 ..
            interleave(c.b, c.a, ba[0], ba[1]);
            Pairs p[4];  // r0 g0 b0 a0 r1 ..
            interleave(std::bit_cast<Pairs>(rg[0]), std::bit_cast<Pairs>(ba[0]), p[0], p[1]);
            interleave(std::bit_cast<Pairs>(rg[1]), std::bit_cast<Pairs>(ba[1]), p[2], p[3]);
            for (int i = 0; i < 4; ++i) simd::store(out + i * sizeof p[0], p[i]);
            return;
        }
        case ColorFormat::none: return;
    }
}

inline Rgba unpack(ColorFormat format, const uint8_t* in) {
    switch (format) {
        case ColorFormat::srgb8: {
            const Int p = simd::load<Int>(in);
            return {srgb8_decode(p & 0xFF), srgb8_decode((p >> 8) & 0xFF),
                    srgb8_decode((p >> 16) & 0xFF),
                    simd::to_float((p >> 24) & 0xFF) / 255.0f};
        }
        case ColorFormat::rgba16f: {
            const Int p[2] = {simd::load<Int>(in), simd::load<Int>(in + sizeof(Int))};
            Int rg, ba;
            deinterleave(p[0], p[1], rg, ba);
            return {half_decode(rg & 0xFFFF), half_decode((rg >> 16) & 0xFFFF),
                    half_decode(ba & 0xFFFF), half_decode((ba >> 16) & 0xFFFF)};
        }
        case ColorFormat::rgba32f: {
            Pairs p[4], rg[2], ba[2];
            for (int i = 0; i < 4; ++i) p[i] = simd::load<Pairs>(in + i * sizeof(Pairs));
            deinterleave(p[0], p[1], rg[0], ba[0]);
            deinterleave(p[2], p[3], rg[1], ba[1]);
            Rgba c;
            deinterleave(std::bit_cast<Float>(rg[0]), std::bit_cast<Float>(rg[1]), c.r, c.g);
            deinterleave(std::bit_cast<Float>(ba[0]), std::bit_cast<Float>(ba[1]), c.b, c.a);
            return c;
        }
        case ColorFormat::none: break;
    }
    return {Float{}, Float{}, Float{}, Float{}};
}

// Part p of the 4x4 block at `block` of an image of `format` whose rows are
// `row_bytes` apart, in linear light; and writing the lanes of `mask` (the
// part's kWidth bits) back.
inline Rgba load_color(ColorFormat format, const uint8_t* block, size_t row_bytes, int part) {
    Packed packed;
    switch (format) {
        case ColorFormat::srgb8:
            simd::load_part<4>(block, row_bytes, part, packed.bytes);
            return unpack(ColorFormat::srgb8, packed.bytes);
        case ColorFormat::rgba16f:
            simd::load_part<8>(block, row_bytes, part, packed.bytes);
            return unpack(ColorFormat::rgba16f, packed.bytes);
        case ColorFormat::rgba32f:
            simd::load_part<16>(block, row_bytes, part, packed.bytes);
            return unpack(ColorFormat::rgba32f, packed.bytes);
        case ColorFormat::none: break;
    }
    return {Float{}, Float{}, Float{}, Float{}};
}

inline void store_packed(ColorFormat format, uint8_t* block, size_t row_bytes, int part,
                         const Packed& packed, uint32_t mask) {
    switch (bytes_per_pixel(format)) {
        case 4: simd::store_part<4>(block, row_bytes, part, packed.bytes, mask); return;
        case 8: simd::store_part<8>(block, row_bytes, part, packed.bytes, mask); return;
        case 16: simd::store_part<16>(block, row_bytes, part, packed.bytes, mask); return;
        default: return;
    }
}

// The row kernels and bulk codecs of the Kernels table (pixels.cpp).
void clear_rect(Framebuffer& fb, int x0, int y0, int x1, int y1, const glm::vec4& color,
                float depth, uint8_t stencil, bool stream);
void resolve_rows(Framebuffer& fb, int first, int count);
void srgb8_rows(const Framebuffer& fb, int first, int count, uint8_t* out);
void encode_pixels(ColorFormat format, const glm::vec4* linear, size_t count, uint8_t* out);
void decode_pixels(ColorFormat format, const uint8_t* in, size_t count, glm::vec4* linear);

}  // namespace facet::FACET_KERNEL_NS
