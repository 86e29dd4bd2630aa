// 16-lane vectors for the 4x4 blocks the raster and fragment stages work on.
//
// The arithmetic is written once, with GCC/Clang vector extensions, and the
// compiler maps it to whatever the target has: one AVX-512 register per
// 16 floats, two AVX2 registers, or four SSE ones (the portable fallback).
// Only turning a lane-wise comparison into a bit mask differs by instruction
// set, so that alone is written per target below.
//
// Lane i of a block is pixel (x + i % 4, y + i / 4), as in the plugin ABI.
#pragma once

#include <cstdint>
#include <cstring>

#if defined(__AVX512F__) || defined(__AVX2__)
#include <immintrin.h>
#endif

namespace facet::simd {

using f32x16 = float __attribute__((vector_size(64)));
using i32x16 = int32_t __attribute__((vector_size(64)));
using i64x8 = int64_t __attribute__((vector_size(64)));
using f64x8 = double __attribute__((vector_size(64)));
using f32x8 = float __attribute__((vector_size(32)));
using f32x4 = float __attribute__((vector_size(16)));

// Loads and stores of unaligned memory.
template <class V>
inline V load(const void* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <class V>
inline void store(void* p, const V& v) {
    std::memcpy(p, &v, sizeof v);
}

// Bit i set where lane i of a comparison result (all ones or zero) is set.
inline uint32_t bits(const i32x16& m) {
#if defined(__AVX512F__)
    return _mm512_cmpneq_epi32_mask(__m512i(m), _mm512_setzero_si512());
#elif defined(__AVX2__)
    const __m256i* h = reinterpret_cast<const __m256i*>(&m);
    return uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(h[0]))) |
           uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(h[1]))) << 8;
#else
    uint32_t r = 0;
    for (int i = 0; i < 16; ++i) r |= uint32_t(m[i] != 0) << i;
    return r;
#endif
}

inline uint32_t bits(const i64x8& m) {
#if defined(__AVX512F__)
    return _mm512_cmpneq_epi64_mask(__m512i(m), _mm512_setzero_si512());
#elif defined(__AVX2__)
    const __m256i* h = reinterpret_cast<const __m256i*>(&m);
    return uint32_t(_mm256_movemask_pd(_mm256_castsi256_pd(h[0]))) |
           uint32_t(_mm256_movemask_pd(_mm256_castsi256_pd(h[1]))) << 4;
#else
    uint32_t r = 0;
    for (int i = 0; i < 8; ++i) r |= uint32_t(m[i] != 0) << i;
    return r;
#endif
}

// The 16 lanes of a 4x4 block of a row-major float image whose rows are
// `stride` floats apart, and back (only the lanes in `mask`).
// Built in registers: a 16-lane load of four 4-lane stores through memory
// would miss store-to-load forwarding and stall.
inline f32x16 load_block(const float* p, size_t stride) {
    const f32x4 r0 = load<f32x4>(p), r1 = load<f32x4>(p + stride);
    const f32x4 r2 = load<f32x4>(p + 2 * stride), r3 = load<f32x4>(p + 3 * stride);
    const f32x8 top = __builtin_shufflevector(r0, r1, 0, 1, 2, 3, 4, 5, 6, 7);
    const f32x8 bottom = __builtin_shufflevector(r2, r3, 0, 1, 2, 3, 4, 5, 6, 7);
    return __builtin_shufflevector(top, bottom, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13,
                                   14, 15);
}

inline void store_block(float* p, size_t stride, const f32x16& v, uint32_t mask) {
    const float* lanes = reinterpret_cast<const float*>(&v);
    for (int r = 0; r < 4; ++r) {
        const uint32_t row = mask >> (4 * r) & 0xFu;
        if (!row) continue;  // rows past the image's bottom are never addressed
        float* out = p + size_t(r) * stride;
        if (row == 0xFu) {
            std::memcpy(out, lanes + 4 * r, 16);
            continue;
        }
        for (uint32_t m = row; m; m &= m - 1) out[__builtin_ctz(m)] = lanes[4 * r + __builtin_ctz(m)];
    }
}

// Row r (lanes 4r..4r+3) of a block held as four channel vectors, as four
// interleaved RGBA pixels.
struct Rows {
    f32x16 row[4];
};

inline Rows interleave_rgba(const f32x16& r, const f32x16& g, const f32x16& b, const f32x16& a) {
    // rg_lo = r0 g0 r1 g1 .. r7 g7, rg_hi the same for lanes 8..15; ba alike.
    const f32x16 rg_lo = __builtin_shufflevector(r, g, 0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
    const f32x16 rg_hi = __builtin_shufflevector(r, g, 8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31);
    const f32x16 ba_lo = __builtin_shufflevector(b, a, 0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
    const f32x16 ba_hi = __builtin_shufflevector(b, a, 8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31);
    return {{__builtin_shufflevector(rg_lo, ba_lo, 0, 1, 16, 17, 2, 3, 18, 19, 4, 5, 20, 21, 6, 7, 22, 23),
             __builtin_shufflevector(rg_lo, ba_lo, 8, 9, 24, 25, 10, 11, 26, 27, 12, 13, 28, 29, 14, 15, 30, 31),
             __builtin_shufflevector(rg_hi, ba_hi, 0, 1, 16, 17, 2, 3, 18, 19, 4, 5, 20, 21, 6, 7, 22, 23),
             __builtin_shufflevector(rg_hi, ba_hi, 8, 9, 24, 25, 10, 11, 26, 27, 12, 13, 28, 29, 14, 15, 30, 31)}};
}

}  // namespace facet::simd
