// Vectors of the path's register width, for the 4x4 blocks the kernels
// work on (kernels.hpp).
//
// Included only by the kernel sources, which are compiled once per
// instruction-set path, each into its own namespace FACET_KERNEL_NS. A
// Float holds kWidth lanes, as many as one register of the path: 16 with
// AVX-512, 8 with AVX2, 4 with SSE2 or NEON. A block's 16 lanes are then
// kParts parts of kWidth lanes each (whole rows: part p is lanes
// p * kWidth ..), which the kernels visit in turn, skipping parts with no
// covered lane. Nothing is wider than a register, so nothing is split into
// pieces behind the code's back, and little is live at a time: even SSE's
// 16 registers hold it without spills.
//
// The arithmetic is written once with GCC/Clang vector extensions. The few
// operations they cannot say (a comparison to a bit mask, a table gather,
// a half-float conversion) or say slowly (min and max, a multiply of 16-bit
// values on SSE2) use the path's intrinsics where it has them (SSE2 among
// them) and plain code otherwise, so the portable path builds for AArch64
// too.
//
// Lane i of a block is pixel (x + i % 4, y + i / 4), as in the plugin ABI.
#pragma once

#ifndef FACET_KERNEL_NS
#error "simd.hpp belongs to the per-ISA kernel sources (core/CMakeLists.txt)"
#endif

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace facet::FACET_KERNEL_NS::simd {

#if defined(__AVX512F__)
#define FACET_SIMD_WIDTH 16
#elif defined(__AVX2__)
#define FACET_SIMD_WIDTH 8
#else
#define FACET_SIMD_WIDTH 4
#endif
constexpr int kWidth = FACET_SIMD_WIDTH;
constexpr int kParts = 16 / kWidth;
constexpr int kRowsPerPart = kWidth / 4;
constexpr uint32_t kPartMask = (1u << kWidth) - 1u;

using Float = float __attribute__((vector_size(4 * kWidth)));
using Int = int32_t __attribute__((vector_size(4 * kWidth)));
using Long = int64_t __attribute__((vector_size(4 * kWidth)));  // kWidth / 2 lanes
using Row = float __attribute__((vector_size(16)));             // 4 floats
using Short = int16_t __attribute__((vector_size(4 * kWidth)));  // 2 kWidth lanes

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

inline Float to_float(const Int& v) { return __builtin_convertvector(v, Float); }

// The column (i % 4) and the row (i / 4) in the block of each lane of part p.
inline Int column() {
    Int c;
    for (int j = 0; j < kWidth; ++j) c[j] = j % 4;
    return c;
}
inline Int row(int part) {
    Int r;
    for (int j = 0; j < kWidth; ++j) r[j] = part * kRowsPerPart + j / 4;
    return r;
}

// The bits set in v: one instruction where the path has it; the baseline
// x86-64 path has none, and there the compiler's builtin is a call into
// libgcc, once per block or batch, so it adds them up in place.
inline int popcount(uint32_t v) {
#if defined(__POPCNT__) || defined(__aarch64__)
    return __builtin_popcount(v);
#else
    v = v - ((v >> 1) & 0x55555555u);
    v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
    v = (v + (v >> 4)) & 0x0F0F0F0Fu;
    return int((v * 0x01010101u) >> 24);
#endif
}

// The lanes of part p in a 16-bit block mask, and back.
inline uint32_t part_mask(uint32_t mask, int part) { return mask >> (part * kWidth) & kPartMask; }

// The lanes of part p in a 16-bit block mask as a vector: all ones where set.
inline Int part_lanes(uint32_t mask, int part) {
    Int bit;
    for (int j = 0; j < kWidth; ++j) bit[j] = 1 << j;
    return (bit & int(part_mask(mask, part))) != 0;
}

// Bit i set where lane i of a comparison result (all ones or zero) is set.
inline uint32_t bits(const Int& m) {
#if defined(__AVX512F__)
    __m512i v;
    std::memcpy(&v, &m, sizeof v);
    return _mm512_movepi32_mask(v);
#elif defined(__AVX2__)
    __m256 v;
    std::memcpy(&v, &m, sizeof v);
    return uint32_t(_mm256_movemask_ps(v));
#elif defined(__SSE2__)
    __m128 v;
    std::memcpy(&v, &m, sizeof v);
    return uint32_t(_mm_movemask_ps(v));
#else
    uint32_t r = 0;
    for (int i = 0; i < kWidth; ++i) r |= uint32_t(m[i] != 0) << i;
    return r;
#endif
}

inline uint32_t bits(const Long& m) {
#if defined(__AVX512F__)
    __m512i v;
    std::memcpy(&v, &m, sizeof v);
    return _mm512_movepi64_mask(v);
#elif defined(__AVX2__)
    __m256d v;
    std::memcpy(&v, &m, sizeof v);
    return uint32_t(_mm256_movemask_pd(v));
#elif defined(__SSE2__)
    __m128d v;
    std::memcpy(&v, &m, sizeof v);
    return uint32_t(_mm_movemask_pd(v));
#else
    uint32_t r = 0;
    for (int i = 0; i < kWidth / 2; ++i) r |= uint32_t(m[i] != 0) << i;
    return r;
#endif
}

// Correctly rounded square roots, as std::sqrt.
inline Float sqrt(const Float& x) {
#if defined(__AVX512F__)
    return std::bit_cast<Float>(_mm512_maskz_sqrt_ps(0xFFFF, std::bit_cast<__m512>(x)));
#elif defined(__AVX2__)
    return std::bit_cast<Float>(_mm256_sqrt_ps(std::bit_cast<__m256>(x)));
#elif defined(__SSE2__)
    return std::bit_cast<Float>(_mm_sqrt_ps(std::bit_cast<__m128>(x)));
#else
    Float r;
    for (int k = 0; k < kWidth; ++k) r[k] = __builtin_sqrtf(x[k]);
    return r;
#endif
}

// a > b ? a : b in each lane (b where they are unordered or equal): x86's
// maximum instruction, which is exactly that; GCC leaves the comparison and
// the blend as two.
inline Float max(const Float& a, const Float& b) {
#if defined(__AVX512F__)
    const __m512 x = std::bit_cast<__m512>(a), y = std::bit_cast<__m512>(b);
    return std::bit_cast<Float>(_mm512_mask_max_ps(x, 0xFFFF, x, y));  // GCC 12 warns of the plain form
#elif defined(__AVX2__)
    return std::bit_cast<Float>(_mm256_max_ps(std::bit_cast<__m256>(a), std::bit_cast<__m256>(b)));
#elif defined(__SSE2__)
    return std::bit_cast<Float>(_mm_max_ps(std::bit_cast<__m128>(a), std::bit_cast<__m128>(b)));
#else
    return a > b ? a : b;
#endif
}

// a < b ? a : b in each lane (b where they are unordered or equal), as max.
inline Float min(const Float& a, const Float& b) {
#if defined(__AVX512F__)
    const __m512 x = std::bit_cast<__m512>(a), y = std::bit_cast<__m512>(b);
    return std::bit_cast<Float>(_mm512_mask_min_ps(x, 0xFFFF, x, y));  // GCC 12 warns of the plain form
#elif defined(__AVX2__)
    return std::bit_cast<Float>(_mm256_min_ps(std::bit_cast<__m256>(a), std::bit_cast<__m256>(b)));
#elif defined(__SSE2__)
    return std::bit_cast<Float>(_mm_min_ps(std::bit_cast<__m128>(a), std::bit_cast<__m128>(b)));
#else
    return a < b ? a : b;
#endif
}

// |a| in each lane: the sign bit cleared.
inline Float abs(const Float& a) {
    return std::bit_cast<Float>(std::bit_cast<Int>(a) & 0x7FFFFFFF);
}

// table[index[i]] for each lane; every index must lie inside the table.
inline Float gather(const float* table, const Int& index) {
#if defined(__AVX512F__)
    __m512i i;
    std::memcpy(&i, &index, sizeof i);
    // The masked form: GCC 12 warns that the plain one's source is undefined.
    const __m512 r = _mm512_mask_i32gather_ps(_mm512_setzero_ps(), 0xFFFF, i, table, 4);
    return std::bit_cast<Float>(r);
#elif defined(__AVX2__)
    __m256i i;
    std::memcpy(&i, &index, sizeof i);
    return std::bit_cast<Float>(_mm256_i32gather_ps(table, i, 4));
#elif defined(__SSE2__)
    // No gather: the indices through memory, which costs less than taking
    // each out of the register.
    alignas(16) int32_t i[4];
    store(i, index);
    return std::bit_cast<Float>(_mm_setr_ps(table[i[0]], table[i[1]], table[i[2]], table[i[3]]));
#else
    Float out;
    for (int k = 0; k < kWidth; ++k) out[k] = table[index[k]];
    return out;
#endif
}

inline Int gather(const int32_t* table, const Int& index) {
#if defined(__AVX512F__)
    __m512i i;
    std::memcpy(&i, &index, sizeof i);
    const __m512i r = _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), 0xFFFF, i, table, 4);
    return std::bit_cast<Int>(r);
#elif defined(__AVX2__)
    __m256i i;
    std::memcpy(&i, &index, sizeof i);
    return std::bit_cast<Int>(_mm256_i32gather_epi32(table, i, 4));
#elif defined(__SSE2__)
    alignas(16) int32_t i[4];  // as gather(const float*, ...)
    store(i, index);
    return std::bit_cast<Int>(_mm_setr_epi32(table[i[0]], table[i[1]], table[i[2]], table[i[3]]));
#else
    Int out;
    for (int k = 0; k < kWidth; ++k) out[k] = table[index[k]];
    return out;
#endif
}

// table[index[i]] for each lane where `active` is set (all ones), 0 at the
// others, which read nothing (SSE2 reads table[0] for them, which must
// exist, and drops it).
inline Int gather(const int32_t* table, const Int& index, const Int& active) {
#if defined(__AVX512F__)
    const __mmask16 k = _mm512_movepi32_mask(std::bit_cast<__m512i>(active));
    return std::bit_cast<Int>(_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), k,
                                                          std::bit_cast<__m512i>(index), table, 4));
#elif defined(__AVX2__)
    return std::bit_cast<Int>(_mm256_mask_i32gather_epi32(
        _mm256_setzero_si256(), table, std::bit_cast<__m256i>(index),
        std::bit_cast<__m256i>(active), 4));
#else
    return gather(table, index & active) & active;
#endif
}

// The four words base[index[i]] .. base[index[i] + 3] of every lane i:
// out[k][i] = base[index[i] + k] (every index and the three words after it
// must be inside the array). One 16-byte load a lane and a 4x4 transpose
// in each 128-bit part, where four gathers would fetch each word alone.
inline void gather4(const int32_t* base, const Int& index, Int out[4]) {
#if defined(__AVX512F__)
    // The indices through memory: a store and scalar loads cost less than
    // taking each out of the register.
    alignas(64) int32_t at[16];
    store(at, index);
    __asm__("" : "+m"(at));  // else GCC takes them out of the register after all
    __m512i r[4];  // part j of r[k]: lane 4j + k's words
    for (int k = 0; k < 4; ++k) {
        const auto part = [&](int j) {
            return _mm_loadu_si128(reinterpret_cast<const __m128i*>(base + at[4 * j + k]));
        };
        r[k] = _mm512_inserti32x4(_mm512_castsi128_si512(part(0)), part(1), 1);
        r[k] = _mm512_inserti32x4(r[k], part(2), 2);
        r[k] = _mm512_inserti32x4(r[k], part(3), 3);
    }
    // Masked unpacks: GCC 12 warns that the plain ones' source is undefined.
    using V = __m512i;
    const auto lo = [](V a, V b) { return _mm512_mask_unpacklo_epi32(a, 0xFFFF, a, b); };
    const auto hi = [](V a, V b) { return _mm512_mask_unpackhi_epi32(a, 0xFFFF, a, b); };
    const auto lo64 = [](V a, V b) { return _mm512_mask_unpacklo_epi64(a, 0xFF, a, b); };
    const auto hi64 = [](V a, V b) { return _mm512_mask_unpackhi_epi64(a, 0xFF, a, b); };
    const V t0 = lo(r[0], r[1]), t1 = hi(r[0], r[1]), t2 = lo(r[2], r[3]), t3 = hi(r[2], r[3]);
    out[0] = std::bit_cast<Int>(lo64(t0, t2));
    out[1] = std::bit_cast<Int>(hi64(t0, t2));
    out[2] = std::bit_cast<Int>(lo64(t1, t3));
    out[3] = std::bit_cast<Int>(hi64(t1, t3));
#elif defined(__AVX2__)
    alignas(32) int32_t at[8];  // the indices through memory, as for AVX-512
    store(at, index);
    __asm__("" : "+m"(at));
    __m256i r[4];  // r[k]: lane k's words, then lane k + 4's
    for (int k = 0; k < 4; ++k)
        r[k] = _mm256_inserti128_si256(
            _mm256_castsi128_si256(
                _mm_loadu_si128(reinterpret_cast<const __m128i*>(base + at[k]))),
            _mm_loadu_si128(reinterpret_cast<const __m128i*>(base + at[k + 4])), 1);
    const __m256i t0 = _mm256_unpacklo_epi32(r[0], r[1]), t1 = _mm256_unpackhi_epi32(r[0], r[1]);
    const __m256i t2 = _mm256_unpacklo_epi32(r[2], r[3]), t3 = _mm256_unpackhi_epi32(r[2], r[3]);
    out[0] = std::bit_cast<Int>(_mm256_unpacklo_epi64(t0, t2));
    out[1] = std::bit_cast<Int>(_mm256_unpackhi_epi64(t0, t2));
    out[2] = std::bit_cast<Int>(_mm256_unpacklo_epi64(t1, t3));
    out[3] = std::bit_cast<Int>(_mm256_unpackhi_epi64(t1, t3));
#elif defined(__SSE2__)
    alignas(16) int32_t at[4];  // the indices through memory, as gather() takes them
    store(at, index);
    __m128i r[4];
    for (int k = 0; k < 4; ++k)
        r[k] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(base + at[k]));
    const __m128i t0 = _mm_unpacklo_epi32(r[0], r[1]), t1 = _mm_unpackhi_epi32(r[0], r[1]);
    const __m128i t2 = _mm_unpacklo_epi32(r[2], r[3]), t3 = _mm_unpackhi_epi32(r[2], r[3]);
    out[0] = std::bit_cast<Int>(_mm_unpacklo_epi64(t0, t2));
    out[1] = std::bit_cast<Int>(_mm_unpackhi_epi64(t0, t2));
    out[2] = std::bit_cast<Int>(_mm_unpacklo_epi64(t1, t3));
    out[3] = std::bit_cast<Int>(_mm_unpackhi_epi64(t1, t3));
#else
    for (int i = 0; i < kWidth; ++i)
        for (int k = 0; k < 4; ++k) out[k][i] = base[index[i] + k];
#endif
}

// The high 16 bits of each lane's 32-bit product a * b: floor(a b / 2^16).
// One instruction on every x86 path.
inline Short mulhi(const Short& a, const Short& b) {
#if defined(__AVX512BW__)
    using V = __m512i;
    return std::bit_cast<Short>(_mm512_mulhi_epi16(std::bit_cast<V>(a), std::bit_cast<V>(b)));
#elif defined(__AVX2__)
    using V = __m256i;
    return std::bit_cast<Short>(_mm256_mulhi_epi16(std::bit_cast<V>(a), std::bit_cast<V>(b)));
#elif defined(__SSE2__)
    using V = __m128i;
    return std::bit_cast<Short>(_mm_mulhi_epi16(std::bit_cast<V>(a), std::bit_cast<V>(b)));
#else
    Short r;
    for (int i = 0; i < 2 * kWidth; ++i) r[i] = int16_t((int32_t(a[i]) * int32_t(b[i])) >> 16);
    return r;
#endif
}

// a * b in each lane, for a in -32768..32767 and b in 0..32767. SSE2 has
// no 32-bit multiply (GCC makes one of two 64-bit ones and shuffles); its
// multiply-add of 16-bit halves gives a's low half times b's plus a's high
// half times b's high half, 0: a * b exactly, for such a and b.
inline Int mul_short(const Int& a, int b) {
#if FACET_SIMD_WIDTH == 4 && defined(__SSE2__)
    return std::bit_cast<Int>(_mm_madd_epi16(std::bit_cast<__m128i>(a), _mm_set1_epi32(b)));
#else
    return a * b;
#endif
}

#if FACET_SIMD_WIDTH == 8
// For each 8-bit mask, the lanes it selects, first to last (then zeros):
// the permutation that packs them at the front of an AVX2 register.
struct CompressTable {
    alignas(32) int32_t index[256][8];
    constexpr CompressTable() : index{} {
        for (int m = 0; m < 256; ++m)
            for (int lane = 0, n = 0; lane < 8; ++lane)
                if (m >> lane & 1) index[m][n++] = lane;
    }
};
inline constexpr CompressTable kCompress{};
#endif

// Moves the lanes of a 16-bit mask to the front of any number of rows of
// 16 32-bit values (floats or ints), in lane order; worked out once per
// mask. A row written to dst needs room for 16 values: what lies past the
// packed values may be overwritten.
class Compressor {
public:
    explicit Compressor(uint32_t mask) : count_(popcount(mask)) {
#if FACET_SIMD_WIDTH == 16
        mask_ = __mmask16(mask);
#elif FACET_SIMD_WIDTH == 8
        std::memcpy(&index_[0], kCompress.index[mask & 0xFFu], sizeof index_[0]);
        std::memcpy(&index_[1], kCompress.index[mask >> 8], sizeof index_[1]);
        first_ = popcount(mask & 0xFFu);
#else
        for (uint32_t m = mask, n = 0; m; m &= m - 1) lane_[n++] = uint8_t(__builtin_ctz(m));
#endif
    }

    int count() const { return count_; }

    void operator()(const void* src, void* dst) const {
#if FACET_SIMD_WIDTH == 16
        // The register form, then a store: Zen 4 runs the memory form slowly.
        const __m512i v = _mm512_maskz_compress_epi32(mask_, _mm512_loadu_si512(src));
        _mm512_storeu_si512(dst, v);
#elif FACET_SIMD_WIDTH == 8
        const auto* in = static_cast<const __m256i*>(src);
        auto* out = static_cast<uint32_t*>(dst);
        const __m256i lo = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(in), index_[0]);
        const __m256i hi = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(in + 1), index_[1]);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), lo);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + first_), hi);
#else
        // A whole block (as most are, inside a triangle) moves as it is.
        if (count_ == 16) return static_cast<void>(std::memcpy(dst, src, 16 * sizeof(uint32_t)));
        const auto* in = static_cast<const uint32_t*>(src);
        auto* out = static_cast<uint32_t*>(dst);
        for (int n = 0; n < count_; ++n) out[n] = in[lane_[n]];
#endif
    }

private:
    int count_;
#if FACET_SIMD_WIDTH == 16
    __mmask16 mask_;
#elif FACET_SIMD_WIDTH == 8
    __m256i index_[2];
    int first_;
#else
    uint8_t lane_[16];
#endif
};

// Part p of a 4x4 block of a row-major float image whose rows are `stride`
// floats apart: its rows, one after the other.
inline Float load_part(const float* p, size_t stride, int part) {
    const float* first = p + size_t(part * kRowsPerPart) * stride;
#if FACET_SIMD_WIDTH == 4
    (void)stride;
    return load<Float>(first);
#elif FACET_SIMD_WIDTH == 8
    const Row r0 = load<Row>(first), r1 = load<Row>(first + stride);
    return __builtin_shufflevector(r0, r1, 0, 1, 2, 3, 4, 5, 6, 7);
#else
    using Half = float __attribute__((vector_size(32)));
    const Row r0 = load<Row>(first), r1 = load<Row>(first + stride);
    const Row r2 = load<Row>(first + 2 * stride), r3 = load<Row>(first + 3 * stride);
    const Half top = __builtin_shufflevector(r0, r1, 0, 1, 2, 3, 4, 5, 6, 7);
    const Half bottom = __builtin_shufflevector(r2, r3, 0, 1, 2, 3, 4, 5, 6, 7);
    return __builtin_shufflevector(top, bottom, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
                                   15);
#endif
}

// Writes v as part p of a 4x4 block of a row-major float image whose rows
// are `stride` floats apart (load_part's inverse): whole rows of 4.
inline void store_part(float* p, size_t stride, int part, const Float& v) {
    float* first = p + size_t(part * kRowsPerPart) * stride;
    for (int r = 0; r < kRowsPerPart; ++r) {
        Row row;
        std::memcpy(&row, reinterpret_cast<const float*>(&v) + 4 * r, sizeof row);
        store(first + size_t(r) * stride, row);
    }
}

// The row of 4 pixels of 4 bytes at `out`, with the pixels of `row` (4
// bits) replaced by those of `in`: one store, and no read where all four
// change.
inline void store_row(uint8_t* out, const uint8_t* in, uint32_t row) {
    using Row32 = int32_t __attribute__((vector_size(16)));
    Row32 v = load<Row32>(in);
#if defined(__AVX512VL__)
    if (row != 0xFu) {
        _mm_mask_storeu_epi32(out, __mmask8(row), std::bit_cast<__m128i>(v));
        return;
    }
#else
    if (row != 0xFu) {
        const Row32 lanes = ((Row32{} + int32_t(row)) & Row32{1, 2, 4, 8}) != 0;
        v = lanes ? v : load<Row32>(out);
    }
#endif
    store(out, v);
}

// Copies the pixels of `mask` (kWidth bits) from part p of a block, packed
// in lane order (lane j at packed + j * Bytes), to an image whose rows are
// `row_bytes` apart and whose block starts at `p`. Rows without a lane are
// not touched.
template <size_t Bytes>
inline void store_part(uint8_t* p, size_t row_bytes, int part, const void* packed, uint32_t mask) {
    const auto* src = static_cast<const uint8_t*>(packed);
    for (int r = 0; r < kRowsPerPart; ++r) {
        const uint32_t row = mask >> (4 * r) & 0xFu;
        if (!row) continue;
        uint8_t* out = p + size_t(part * kRowsPerPart + r) * row_bytes;
        const uint8_t* in = src + 4 * r * Bytes;
        if constexpr (Bytes == 4) {
            store_row(out, in, row);
        } else if (row == 0xFu) {
            std::memcpy(out, in, 4 * Bytes);
        } else {
            for (uint32_t m = row; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                std::memcpy(out + i * Bytes, in + i * Bytes, Bytes);
            }
        }
    }
}

// The pixels of part p of the block at `p`, packed in lane order.
template <size_t Bytes>
inline void load_part(const uint8_t* p, size_t row_bytes, int part, void* packed) {
    auto* dst = static_cast<uint8_t*>(packed);
    for (int r = 0; r < kRowsPerPart; ++r)
        std::memcpy(dst + 4 * r * Bytes, p + size_t(part * kRowsPerPart + r) * row_bytes, 4 * Bytes);
}

}  // namespace facet::FACET_KERNEL_NS::simd
