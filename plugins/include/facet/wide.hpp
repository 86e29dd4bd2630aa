// facet shader authoring layer: the shading language's vector maths (C++20,
// header-only; GCC or Clang).
//
// A shader's vertex and fragment functions are written once, over the
// types here, and run on kLanes vertices or fragments at a time: each
// value is one vector register. Float holds kLanes floats, Vec2, Vec3
// and Vec4 hold as many vectors, a comparison gives a Mask (all ones or
// zero per lane). It reads like GLSL: dot, normalize, mix, clamp, pow,
// reflect, select() for a branch that differs between lanes, any() to skip
// work no lane needs. Uniform values (a material's parameters, a light)
// are plain floats and glm vectors, and mix freely with the lane types.
//
// facet_add_shader() compiles a shader once for each path, and each build
// gets its own kLanes: 16 with AVX-512, 8 with AVX2, 4 with SSE2 or NEON.
// FACET_SDK_REFERENCE builds the reference the tests hold every path to:
// plain per-lane code with the C library's functions (std::sqrt, std::pow,
// ...), four lanes at a time, so that a 2x2 quad's derivatives work as on
// the paths. Write a shader for any kLanes.
//
// The functions here are as accurate as their std:: counterparts within a
// few units in the last place, except pow (see there).
#pragma once

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <bit>
#include <type_traits>
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#elif defined(__ARM_NEON) && defined(__aarch64__)
#include <arm_neon.h>
#endif

// The build's lane count, and which intrinsics it uses: none in the
// reference build (FACET_WIDE_GENERIC), else the target's.
#if defined(FACET_SDK_REFERENCE)
#define FACET_WIDE_LANES 4
#define FACET_WIDE_NAMESPACE reference
#define FACET_WIDE_GENERIC 1
#elif defined(__AVX512F__)
#define FACET_WIDE_LANES 16
#define FACET_WIDE_NAMESPACE lanes16
#elif defined(__AVX__)
#define FACET_WIDE_LANES 8
#define FACET_WIDE_NAMESPACE lanes8
#else
#define FACET_WIDE_LANES 4
#define FACET_WIDE_NAMESPACE lanes4
#endif
#ifndef FACET_WIDE_GENERIC
#define FACET_WIDE_GENERIC 0
#endif
// Each 1 where this build takes that target's intrinsics.
#if !FACET_WIDE_GENERIC && defined(__AVX512F__)
#define FACET_WIDE_AVX512 1
#else
#define FACET_WIDE_AVX512 0
#endif
#if !FACET_WIDE_GENERIC && defined(__AVX__)
#define FACET_WIDE_AVX 1
#else
#define FACET_WIDE_AVX 0
#endif
#if !FACET_WIDE_GENERIC && defined(__AVX2__)
#define FACET_WIDE_AVX2 1
#else
#define FACET_WIDE_AVX2 0
#endif
#if !FACET_WIDE_GENERIC && defined(__SSE2__)
#define FACET_WIDE_SSE2 1
#else
#define FACET_WIDE_SSE2 0
#endif
#if !FACET_WIDE_GENERIC && defined(__ARM_NEON) && defined(__aarch64__)
#define FACET_WIDE_NEON 1
#else
#define FACET_WIDE_NEON 0
#endif

namespace facet::sdk::wide {
// Each lane count in a namespace of its own, so that these functions have a
// name per width. Code that only uses them (shader.hpp's WideFragment and
// batch loop) can still share a name across widths: facet_add_shader keeps
// the builds apart by making every symbol of a path's build local
// (facet_isa_objects in FacetShader.cmake), so build them that way.
inline namespace FACET_WIDE_NAMESPACE {

static_assert(FACET_BLOCK_LANES % FACET_WIDE_LANES == 0);
constexpr int kLanes = FACET_WIDE_LANES;
using Float = float __attribute__((vector_size(4 * kLanes)));
using Mask = int32_t __attribute__((vector_size(4 * kLanes)));

// v in every lane, as it is (v - 0 is v, -0 included: one broadcast, where
// 0 + v would be an addition too, which makes -0 +0).
inline Float splat(float v) { return v - Float{}; }
inline Float select(const Mask& m, const Float& a, const Float& b) { return m ? a : b; }
inline Mask select(const Mask& m, const Mask& a, const Mask& b) { return m ? a : b; }
// As std::min and std::max: a when the two are unordered (a NaN a stays).
// x86's minimum and maximum instructions are exactly these with the operands
// swapped (their second operand where the comparison fails); GCC does not
// make them of the comparisons, which take two instructions.
inline Float min(const Float& a, const Float& b) {
#if FACET_WIDE_AVX512
    const __m512 x = std::bit_cast<__m512>(b), y = std::bit_cast<__m512>(a);
    return std::bit_cast<Float>(_mm512_mask_min_ps(x, 0xFFFF, x, y));  // GCC 12 warns of the plain form
#elif FACET_WIDE_AVX
    return std::bit_cast<Float>(_mm256_min_ps(std::bit_cast<__m256>(b), std::bit_cast<__m256>(a)));
#elif FACET_WIDE_SSE2
    return std::bit_cast<Float>(_mm_min_ps(std::bit_cast<__m128>(b), std::bit_cast<__m128>(a)));
#else
    return b < a ? b : a;
#endif
}
inline Float max(const Float& a, const Float& b) {
#if FACET_WIDE_AVX512
    const __m512 x = std::bit_cast<__m512>(b), y = std::bit_cast<__m512>(a);
    return std::bit_cast<Float>(_mm512_mask_max_ps(x, 0xFFFF, x, y));  // GCC 12 warns of the plain form
#elif FACET_WIDE_AVX
    return std::bit_cast<Float>(_mm256_max_ps(std::bit_cast<__m256>(b), std::bit_cast<__m256>(a)));
#elif FACET_WIDE_SSE2
    return std::bit_cast<Float>(_mm_max_ps(std::bit_cast<__m128>(b), std::bit_cast<__m128>(a)));
#else
    return a < b ? b : a;
#endif
}
inline Float clamp(const Float& x, float lo, float hi) { return min(max(x, splat(lo)), splat(hi)); }
// |x|, as std::abs: the sign bit cleared.
inline Float abs(const Float& x) {
    return std::bit_cast<Float>(std::bit_cast<Mask>(x) & 0x7FFFFFFF);
}

// Correctly rounded, as std::sqrt.
inline Float sqrt(const Float& x) {
#if FACET_WIDE_AVX512
    return std::bit_cast<Float>(_mm512_maskz_sqrt_ps(0xFFFF, std::bit_cast<__m512>(x)));
#elif FACET_WIDE_AVX
    return std::bit_cast<Float>(_mm256_sqrt_ps(std::bit_cast<__m256>(x)));
#elif FACET_WIDE_SSE2
    return std::bit_cast<Float>(_mm_sqrt_ps(std::bit_cast<__m128>(x)));
#elif FACET_WIDE_NEON
    return std::bit_cast<Float>(vsqrtq_f32(std::bit_cast<float32x4_t>(x)));
#else
    Float r{};
    for (int i = 0; i < kLanes; ++i) r[i] = std::sqrt(x[i]);
    return r;
#endif
}

// As std::floor and std::ceil, but a zero result is always +0 (they may
// give -0), so that every path gives the same bits. Floats of magnitude
// 2^23 or more are whole already and stay as they are, as do NaN and
// infinities. One rounding instruction where the path has one.
inline Float floor(const Float& x) {
#if FACET_WIDE_AVX512
    const __m512 v = std::bit_cast<__m512>(x);  // masked: GCC 12 warns of the plain form
    return std::bit_cast<Float>(_mm512_mask_roundscale_ps(v, 0xFFFF, v, 0x09)) + 0.0f;
#elif FACET_WIDE_AVX
    return std::bit_cast<Float>(_mm256_round_ps(std::bit_cast<__m256>(x), 0x09)) + 0.0f;
#elif FACET_WIDE_GENERIC
    Float r{};
    for (int i = 0; i < kLanes; ++i) r[i] = std::floor(x[i]) + 0.0f;
    return r;
#else
    const Mask small = x < 8388608.0f && x > -8388608.0f;  // false for NaN
    const Float t = __builtin_convertvector(
        __builtin_convertvector(select(small, x, splat(0.0f)), Mask), Float);  // truncated
    return select(small, select(t > x, t - 1.0f, t), x);
#endif
}
inline Float ceil(const Float& x) {
#if FACET_WIDE_AVX512
    const __m512 v = std::bit_cast<__m512>(x);  // masked: GCC 12 warns of the plain form
    return std::bit_cast<Float>(_mm512_mask_roundscale_ps(v, 0xFFFF, v, 0x0A)) + 0.0f;
#elif FACET_WIDE_AVX
    return std::bit_cast<Float>(_mm256_round_ps(std::bit_cast<__m256>(x), 0x0A)) + 0.0f;
#elif FACET_WIDE_GENERIC
    Float r{};
    for (int i = 0; i < kLanes; ++i) r[i] = std::ceil(x[i]) + 0.0f;
    return r;
#else
    const Mask small = x < 8388608.0f && x > -8388608.0f;
    const Float t = __builtin_convertvector(
        __builtin_convertvector(select(small, x, splat(0.0f)), Mask), Float);
    return select(small, select(t < x, t + 1.0f, t), x);
#endif
}

// base[index[i]] for each lane of `m`, `otherwise` for the others (whose
// index is not read).
inline Float gather(const float* base, const Mask& index, const Mask& m, float otherwise) {
#if FACET_WIDE_AVX512
    return std::bit_cast<Float>(_mm512_mask_i32gather_ps(
        _mm512_set1_ps(otherwise), _mm512_cmplt_epi32_mask(std::bit_cast<__m512i>(m),
                                                           _mm512_setzero_si512()),
        std::bit_cast<__m512i>(index), base, 4));
#elif FACET_WIDE_AVX2
    return std::bit_cast<Float>(_mm256_mask_i32gather_ps(
        _mm256_set1_ps(otherwise), base, std::bit_cast<__m256i>(index),
        std::bit_cast<__m256>(m), 4));
#else
    Float r{};
    for (int i = 0; i < kLanes; ++i) r[i] = m[i] ? base[index[i]] : otherwise;
    return r;
#endif
}

#if FACET_WIDE_SSE2  // the x86 paths (AVX and AVX-512 builds have SSE2 too)
namespace impl {
// Lane i's record of four floats in r[i], turned into the four
// components' lanes: out[k][i] = r[i][k] (a 4x4 transpose in each 128-bit
// part).
inline void transpose_records(const __m128 (&r)[kLanes], Float out[4]) {
#if FACET_WIDE_AVX512
    __m512 q[4];  // part j of q[k]: lane 4j + k's record
    for (int k = 0; k < 4; ++k) {
        q[k] = _mm512_insertf32x4(_mm512_castps128_ps512(r[k]), r[k + 4], 1);
        q[k] = _mm512_insertf32x4(q[k], r[k + 8], 2);
        q[k] = _mm512_insertf32x4(q[k], r[k + 12], 3);
    }
    // Masked unpacks: GCC 12 warns that the plain ones' source is undefined.
    const auto lo = [](__m512 a, __m512 b) { return _mm512_mask_unpacklo_ps(a, 0xFFFF, a, b); };
    const auto hi = [](__m512 a, __m512 b) { return _mm512_mask_unpackhi_ps(a, 0xFFFF, a, b); };
    const __m512 t0 = lo(q[0], q[1]), t1 = hi(q[0], q[1]), t2 = lo(q[2], q[3]), t3 = hi(q[2], q[3]);
    out[0] = std::bit_cast<Float>(_mm512_shuffle_ps(t0, t2, 0x44));
    out[1] = std::bit_cast<Float>(_mm512_shuffle_ps(t0, t2, 0xEE));
    out[2] = std::bit_cast<Float>(_mm512_shuffle_ps(t1, t3, 0x44));
    out[3] = std::bit_cast<Float>(_mm512_shuffle_ps(t1, t3, 0xEE));
#elif FACET_WIDE_AVX
    __m256 q[4];  // q[k]: lane k's record, then lane k + 4's
    for (int k = 0; k < 4; ++k)
        q[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(r[k]), r[k + 4], 1);
    const __m256 t0 = _mm256_unpacklo_ps(q[0], q[1]), t1 = _mm256_unpackhi_ps(q[0], q[1]);
    const __m256 t2 = _mm256_unpacklo_ps(q[2], q[3]), t3 = _mm256_unpackhi_ps(q[2], q[3]);
    out[0] = std::bit_cast<Float>(_mm256_shuffle_ps(t0, t2, 0x44));
    out[1] = std::bit_cast<Float>(_mm256_shuffle_ps(t0, t2, 0xEE));
    out[2] = std::bit_cast<Float>(_mm256_shuffle_ps(t1, t3, 0x44));
    out[3] = std::bit_cast<Float>(_mm256_shuffle_ps(t1, t3, 0xEE));
#else
    const __m128 t0 = _mm_unpacklo_ps(r[0], r[1]), t1 = _mm_unpackhi_ps(r[0], r[1]);
    const __m128 t2 = _mm_unpacklo_ps(r[2], r[3]), t3 = _mm_unpackhi_ps(r[2], r[3]);
    out[0] = std::bit_cast<Float>(_mm_movelh_ps(t0, t2));
    out[1] = std::bit_cast<Float>(_mm_movehl_ps(t2, t0));
    out[2] = std::bit_cast<Float>(_mm_movelh_ps(t1, t3));
    out[3] = std::bit_cast<Float>(_mm_movehl_ps(t3, t1));
#endif
}

// a + (b - a) t in each of four floats: mix, with t one number.
inline __m128 mix4(__m128 a, __m128 b, float t) {
    return _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), _mm_set1_ps(t)));
}
}  // namespace impl
#endif

// The four floats base[index[i]] .. base[index[i] + 3] of every lane i:
// out[k][i] = base[index[i] + k], for records of four floats (every index
// and the three after it must be inside the array). One 16-byte load per
// lane and a transpose, where four gathers would fetch each float on its
// own.
inline void gather4(const float* base, const Mask& index, Float out[4]) {
#if !FACET_WIDE_SSE2
    for (int k = 0; k < 4; ++k) {
        Float v{};
        for (int i = 0; i < kLanes; ++i) v[i] = base[index[i] + k];
        out[k] = v;
    }
#else
    __m128 r[kLanes];
    for (int i = 0; i < kLanes; ++i) r[i] = _mm_loadu_ps(base + index[i]);
    impl::transpose_records(r, out);
#endif
}

// A bilinear lookup in records of four floats (RGBA texels): for each lane
// i, the records at base + top[i] and the one after it, and at base +
// bottom[i] and the one after it, mixed across by fx and then down by fy:
// out[k] = mix(mix(a, b, fx), mix(c, d, fx), fy) for component k, with the
// same roundings as that in lanes. Each lane's four records are mixed where
// they lie (two 32-byte loads with AVX) and transposed once, where four
// gather4 calls would transpose each.
inline void bilinear4(const float* base, const Mask& top, const Mask& bottom, const Float& fx,
                      const Float& fy, Float out[4]) {
#if !FACET_WIDE_SSE2
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < kLanes; ++i) {
            const float* a = base + top[i] + k;
            const float* c = base + bottom[i] + k;
            const float upper = a[0] + (a[4] - a[0]) * fx[i], lower = c[0] + (c[4] - c[0]) * fx[i];
            out[k][i] = upper + (lower - upper) * fy[i];
        }
#else
    __m128 r[kLanes];
    for (int i = 0; i < kLanes; ++i) {
#if FACET_WIDE_AVX
        const __m256 a = _mm256_loadu_ps(base + top[i]), c = _mm256_loadu_ps(base + bottom[i]);
        const __m256 left = _mm256_permute2f128_ps(a, c, 0x20);   // upper left, lower left
        const __m256 right = _mm256_permute2f128_ps(a, c, 0x31);  // upper right, lower right
        const __m256 across = _mm256_add_ps(
            left, _mm256_mul_ps(_mm256_sub_ps(right, left), _mm256_set1_ps(fx[i])));
        r[i] = impl::mix4(_mm256_castps256_ps128(across), _mm256_extractf128_ps(across, 1), fy[i]);
#else
        const float *a = base + top[i], *c = base + bottom[i];
        const __m128 upper = impl::mix4(_mm_loadu_ps(a), _mm_loadu_ps(a + 4), fx[i]);
        const __m128 lower = impl::mix4(_mm_loadu_ps(c), _mm_loadu_ps(c + 4), fx[i]);
        r[i] = impl::mix4(upper, lower, fy[i]);
#endif
    }
    impl::transpose_records(r, out);
#endif
}

// For kLanes / 2 lanes, as many 64-bit lanes: the four 16-bit values
// base[index[i]] .. base[index[i] + 3] of each, the first in the lowest
// bits; every index and the three after it must be inside the array.
using Quads = uint64_t __attribute__((vector_size(4 * kLanes)));
using HalfIndex = int32_t __attribute__((vector_size(2 * kLanes)));
inline Quads gather_quads(const uint16_t* base, const HalfIndex& index) {
#if FACET_WIDE_AVX512
    // The masked form: GCC 12 warns that the plain one's source is undefined.
    return std::bit_cast<Quads>(_mm512_mask_i32gather_epi64(
        _mm512_setzero_si512(), 0xFF, std::bit_cast<__m256i>(index), base, 2));
#elif FACET_WIDE_AVX2
    return std::bit_cast<Quads>(_mm256_i32gather_epi64(reinterpret_cast<const long long*>(base),
                                                       std::bit_cast<__m128i>(index), 2));
#else
    static_assert(std::endian::native == std::endian::little);  // the first value lowest
    Quads r;
    for (int i = 0; i < kLanes / 2; ++i) {
        uint64_t q;
        std::memcpy(&q, base + index[i], 8);
        r[i] = q;
    }
    return r;
#endif
}

// log2(x) for finite x >= FLT_MIN (other x give meaningless values; pow
// handles them): x = m 2^e with m in [sqrt(1/2), sqrt(2)), and ln m =
// 2 atanh(t), t = (m - 1) / (m + 1), from its series to t^9 (|t| < 0.172, so
// the first term left out, t^10 / 11 of the sum, is below 2^-29).
inline Float log2(const Float& x) {
#if FACET_WIDE_GENERIC
    Float generic{};
    for (int i = 0; i < kLanes; ++i) generic[i] = std::log2(x[i]);
    return generic;
#endif
    const Mask bits = std::bit_cast<Mask>(x);
    Float e = __builtin_convertvector(((bits >> 23) & 0xFF) - 127, Float);
    Float m = std::bit_cast<Float>((bits & 0x7FFFFF) | 0x3F800000);  // [1, 2)
    const Mask high = m > 1.41421356f;
    m = select(high, m * 0.5f, m);
    e = select(high, e + 1.0f, e);
    const Float t = (m - 1.0f) / (m + 1.0f), t2 = t * t;
    const Float series = 1.0f + t2 * (1.0f / 3 + t2 * (1.0f / 5 + t2 * (1.0f / 7 + t2 * (1.0f / 9))));
    return e + (2.0f * 1.44269504f) * t * series;  // 1 / ln 2
}

// 2^y: y = n + f with n an integer and |f| <= 1/2, and 2^f from the Taylor
// series of e^(f ln 2) to the 7th power (error below 2^-27), scaled by 2^n
// in two normal factors, so the result rounds to subnormals and 0 below
// 2^-126 and overflows to infinity above FLT_MAX as a float would. NaN
// stays NaN.
inline Float exp2(const Float& y) {
#if FACET_WIDE_GENERIC
    Float generic{};
    for (int i = 0; i < kLanes; ++i) generic[i] = std::exp2(y[i]);
    return generic;
#endif
    const Float c = clamp(select(y != y, splat(0.0f), y), -160.0f, 160.0f);  // NaN: any number
    Float n = __builtin_convertvector(__builtin_convertvector(c, Mask), Float);  // truncated
    n = select(n > c, n - 1.0f, n);                                              // floored
    n = select(c - n > 0.5f, n + 1.0f, n);                                       // nearest
    const Float x = (c - n) * 0.693147181f;
    const Float p =
        1.0f + x * (1.0f + x * (1.0f / 2 + x * (1.0f / 6 + x * (1.0f / 24 + x * (1.0f / 120 +
                                                          x * (1.0f / 720 + x * (1.0f / 5040)))))));
    const Mask ni = __builtin_convertvector(n, Mask), half = ni >> 1;  // both in [-80, 80]
    const Float r = p * std::bit_cast<Float>((half + 127) << 23) *
                    std::bit_cast<Float>((ni - half + 127) << 23);
    return select(y != y, y, r);
}

// x^y for x >= 0, as exp2(y log2 x). The product's rounding dominates the
// error, a relative error of a few |y log2 x| 2^-24: below 4e-6 wherever the
// result is above 1e-7, against std::pow (tests/test_wide.cpp). x below
// FLT_MIN counts as 0: 0^y is 0, and 1 for y = 0. NaN stays NaN.
inline Float pow(const Float& x, const Float& y) {
#if FACET_WIDE_GENERIC
    Float generic{};
    for (int i = 0; i < kLanes; ++i) generic[i] = std::pow(x[i], y[i]);
    return generic;
#endif
    const Float r = exp2(y * log2(max(x, splat(1.17549435e-38f))));
    const Float zero = select(y == 0.0f, splat(1.0f), splat(0.0f));
    return select(x != x, x, select(x < 1.17549435e-38f, zero, r));  // NaN stays NaN
}
inline Float pow(const Float& x, float y) { return pow(x, splat(y)); }

// ---- vectors -------------------------------------------------------------------

struct Vec2 {
    Float x, y;
    Vec2() = default;
    Vec2(const Float& x_, const Float& y_) : x(x_), y(y_) {}
    explicit Vec2(const glm::vec2& v) : x(splat(v.x)), y(splat(v.y)) {}
    explicit Vec2(const Float& s) : x(s), y(s) {}
};

struct Vec3 {
    Float x, y, z;
    Vec3() = default;
    Vec3(const Float& x_, const Float& y_, const Float& z_) : x(x_), y(y_), z(z_) {}
    explicit Vec3(const glm::vec3& v) : x(splat(v.x)), y(splat(v.y)), z(splat(v.z)) {}
    explicit Vec3(const Float& s) : x(s), y(s), z(s) {}
};

struct Vec4 {
    Float x, y, z, w;
    Vec4() = default;
    Vec4(const Vec3& v, const Float& w_) : x(v.x), y(v.y), z(v.z), w(w_) {}
    Vec4(const Vec3& v, float w_) : x(v.x), y(v.y), z(v.z), w(splat(w_)) {}
    Vec4(const Float& x_, const Float& y_, const Float& z_, const Float& w_)
        : x(x_), y(y_), z(z_), w(w_) {}
    explicit Vec4(const glm::vec4& v) : x(splat(v.x)), y(splat(v.y)), z(splat(v.z)), w(splat(v.w)) {}
    explicit Vec4(const Float& s) : x(s), y(s), z(s), w(s) {}
};

// The first three components, as GLSL's v.xyz (and a colour's rgb).
inline Vec3 xyz(const Vec4& v) { return {v.x, v.y, v.z}; }
inline Vec3 rgb(const Vec4& v) { return {v.x, v.y, v.z}; }

// Lane-by-lane arithmetic of Vec2, Vec3 and Vec4 with each other, with
// Float and float, and with glm's vectors of the same size (uniforms).
namespace vec {
template <class V>
constexpr int size() {
    if constexpr (sizeof(V) == 2 * sizeof(Float)) return 2;
    else if constexpr (sizeof(V) == 3 * sizeof(Float)) return 3;
    else return 4;
}
template <class V>
concept Lanes = std::is_same_v<V, Vec2> || std::is_same_v<V, Vec3> || std::is_same_v<V, Vec4>;
// f of each component (of a and b). Spelt out rather than a loop over the
// components through a pointer, which GCC keeps in memory.
template <Lanes V, class F>
[[gnu::always_inline]] inline V each(const V& a, const V& b, F f) {
    if constexpr (size<V>() == 2) return {f(a.x, b.x), f(a.y, b.y)};
    else if constexpr (size<V>() == 3) return {f(a.x, b.x), f(a.y, b.y), f(a.z, b.z)};
    else return {f(a.x, b.x), f(a.y, b.y), f(a.z, b.z), f(a.w, b.w)};
}
template <Lanes V, class F>
[[gnu::always_inline]] inline V each(const V& a, F f) {
    if constexpr (size<V>() == 2) return {f(a.x), f(a.y)};
    else if constexpr (size<V>() == 3) return {f(a.x), f(a.y), f(a.z)};
    else return {f(a.x), f(a.y), f(a.z), f(a.w)};
}
// glm's vector of V's size, broadcast.
template <Lanes V>
using Uniform = glm::vec<size<V>(), float>;
}  // namespace vec

#define FACET_WIDE_OPERATOR(op)                                                             \
    template <vec::Lanes V>                                                              \
    inline V operator op(const V& a, const V& b) {                                          \
        return vec::each(a, b, [](const Float& x, const Float& y) { return x op y; });  \
    }                                                                                       \
    template <vec::Lanes V>                                                              \
    inline V operator op(const V& a, const Float& s) {                                      \
        return vec::each(a, [&](const Float& x) { return x op s; });                     \
    }                                                                                       \
    template <vec::Lanes V>                                                              \
    inline V operator op(const Float& s, const V& a) {                                      \
        return vec::each(a, [&](const Float& x) { return s op x; });                     \
    }                                                                                       \
    template <vec::Lanes V>                                                              \
    inline V operator op(const V& a, float s) { return a op splat(s); }                     \
    template <vec::Lanes V>                                                              \
    inline V operator op(float s, const V& a) { return splat(s) op a; }                     \
    template <vec::Lanes V>                                                              \
    inline V operator op(const V& a, const vec::Uniform<V>& b) { return a op V(b); }     \
    template <vec::Lanes V>                                                              \
    inline V operator op(const vec::Uniform<V>& a, const V& b) { return V(a) op b; }     \
    template <vec::Lanes V, class T>                                                     \
    inline V& operator op##=(V& a, const T& b) { return a = a op b; }
FACET_WIDE_OPERATOR(+)
FACET_WIDE_OPERATOR(-)
FACET_WIDE_OPERATOR(*)
#undef FACET_WIDE_OPERATOR

// A uniform vector times a Float (a colour times a lane's weight).
inline Vec2 operator*(const glm::vec2& a, const Float& s) { return Vec2(a) * s; }
inline Vec3 operator*(const glm::vec3& a, const Float& s) { return Vec3(a) * s; }
inline Vec4 operator*(const glm::vec4& a, const Float& s) { return Vec4(a) * s; }
inline Vec2 operator*(const Float& s, const glm::vec2& a) { return Vec2(a) * s; }
inline Vec3 operator*(const Float& s, const glm::vec3& a) { return Vec3(a) * s; }
inline Vec4 operator*(const Float& s, const glm::vec4& a) { return Vec4(a) * s; }

template <vec::Lanes V>
inline V operator-(const V& a) {
    return vec::each(a, [](const Float& x) { return -x; });
}
// Division by a Float: one division, then multiplies (within an ulp or two
// of dividing each component).
template <vec::Lanes V>
inline V operator/(const V& a, const Float& s) {
    const Float r = 1.0f / s;
    return a * r;
}
template <vec::Lanes V>
inline V operator/(const V& a, float s) { return a * (1.0f / s); }
template <vec::Lanes V>
inline V operator/(const V& a, const V& b) {
    return vec::each(a, b, [](const Float& x, const Float& y) { return x / y; });
}

template <vec::Lanes V>
inline V select(const Mask& m, const V& a, const V& b) {
    return vec::each(a, b, [&](const Float& x, const Float& y) { return select(m, x, y); });
}
template <vec::Lanes V>
inline V min(const V& a, const V& b) {
    return vec::each(a, b, [](const Float& x, const Float& y) { return min(x, y); });
}
template <vec::Lanes V>
inline V max(const V& a, const V& b) {
    return vec::each(a, b, [](const Float& x, const Float& y) { return max(x, y); });
}
template <vec::Lanes V>
inline V clamp(const V& v, float lo, float hi) {
    return vec::each(v, [&](const Float& x) { return clamp(x, lo, hi); });
}
template <vec::Lanes V>
inline V abs(const V& v) {
    return vec::each(v, [](const Float& x) { return abs(x); });
}

// ---- GLSL's functions ------------------------------------------------------------

inline Float min(const Float& a, float b) { return min(a, splat(b)); }
inline Float max(const Float& a, float b) { return max(a, splat(b)); }
inline Float clamp(const Float& x, const Float& lo, const Float& hi) { return min(max(x, lo), hi); }
inline Float fract(const Float& x) { return x - floor(x); }
// 1 where x >= edge, else 0.
inline Float step(float edge, const Float& x) { return select(x >= edge, splat(1.0f), splat(0.0f)); }
// a + (b - a) t, as GLSL's mix.
inline Float mix(const Float& a, const Float& b, const Float& t) { return a + (b - a) * t; }
template <vec::Lanes V>
inline V mix(const V& a, const V& b, const Float& t) { return a + (b - a) * t; }
template <vec::Lanes V>
inline V mix(const V& a, const V& b, float t) { return a + (b - a) * t; }
// 0 below lo, 1 above hi, and 3t^2 - 2t^3 of t = (x - lo) / (hi - lo)
// between (hi > lo); a step at lo when they are equal.
inline Float smoothstep(float lo, float hi, const Float& x) {
    if (!(hi > lo)) return step(lo, x);
    const Float t = clamp((x - lo) * (1.0f / (hi - lo)), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

inline Float dot(const Vec2& a, const Vec2& b) { return a.x * b.x + a.y * b.y; }
inline Float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Float dot(const Vec4& a, const Vec4& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
}
inline Float dot(const Vec3& a, const glm::vec3& b) { return dot(a, Vec3(b)); }
template <vec::Lanes V>
inline Float length(const V& v) { return sqrt(dot(v, v)); }
template <vec::Lanes V>
inline Float distance(const V& a, const V& b) { return length(a - b); }
// As glm::normalize: v times 1 / |v|.
template <vec::Lanes V>
inline V normalize(const V& v) { return v * (1.0f / sqrt(dot(v, v))); }
// As glm::reflect: i - 2 dot(n, i) n.
inline Vec3 reflect(const Vec3& i, const Vec3& n) { return i - n * (2.0f * dot(n, i)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// A uniform matrix times lane vectors (glm's column-major layout).
inline Vec4 operator*(const glm::mat4& m, const Vec4& v) {
    const auto row = [&](int r) {
        return (m[0][r] * v.x + m[1][r] * v.y) + (m[2][r] * v.z + m[3][r] * v.w);
    };
    return {row(0), row(1), row(2), row(3)};
}
inline Vec3 operator*(const glm::mat3& m, const Vec3& v) {
    const auto row = [&](int r) { return m[0][r] * v.x + m[1][r] * v.y + m[2][r] * v.z; };
    return {row(0), row(1), row(2)};
}

// ---- masks ---------------------------------------------------------------------

// The lanes of a call as a bit mask (bit i for lane i), from a Mask.
inline uint32_t bits(const Mask& m) {
#if FACET_WIDE_AVX512
    return _mm512_cmplt_epi32_mask(std::bit_cast<__m512i>(m), _mm512_setzero_si512());
#elif FACET_WIDE_AVX
    return uint32_t(_mm256_movemask_ps(std::bit_cast<__m256>(m)));
#elif FACET_WIDE_SSE2
    return uint32_t(_mm_movemask_ps(std::bit_cast<__m128>(m)));
#else
    uint32_t r = 0;
    for (int i = 0; i < kLanes; ++i) r |= uint32_t(m[i] != 0) << i;
    return r;
#endif
}

// Whether any lane of `m` is set: to skip work no lane needs, as a GPU
// shader branches when a whole warp agrees. all(): every lane.
inline bool any(const Mask& m) { return bits(m) != 0; }
inline bool all(const Mask& m) { return bits(m) == (1u << kLanes) - 1u; }

// ---- 2x2 quads -------------------------------------------------------------------

// A fragment call's lanes are whole 2x2 quads of pixels (<facet/shader.hpp>
// arranges it): in each quad of four lanes, the top-left, top-right,
// bottom-left and bottom-right pixel are lanes q, q + 1, q + kQuadRow,
// q + kQuadRow + 1. With four lanes, the call is one quad; wider, it is
// rows of the 4x4 block.
constexpr int kQuadRow = kLanes == 4 ? 2 : 4;

// Each lane's quad's top-left, top-right and bottom-left values.
struct QuadCorners {
    Float tl, tr, bl;
};
inline QuadCorners quad_corners(const Float& v) {
#if FACET_WIDE_LANES == 16
    return {__builtin_shufflevector(v, v, 0, 0, 2, 2, 0, 0, 2, 2, 8, 8, 10, 10, 8, 8, 10, 10),
            __builtin_shufflevector(v, v, 1, 1, 3, 3, 1, 1, 3, 3, 9, 9, 11, 11, 9, 9, 11, 11),
            __builtin_shufflevector(v, v, 4, 4, 6, 6, 4, 4, 6, 6, 12, 12, 14, 14, 12, 12, 14, 14)};
#elif FACET_WIDE_LANES == 8
    return {__builtin_shufflevector(v, v, 0, 0, 2, 2, 0, 0, 2, 2),
            __builtin_shufflevector(v, v, 1, 1, 3, 3, 1, 1, 3, 3),
            __builtin_shufflevector(v, v, 4, 4, 6, 6, 4, 4, 6, 6)};
#else
    return {__builtin_shufflevector(v, v, 0, 0, 0, 0), __builtin_shufflevector(v, v, 1, 1, 1, 1),
            __builtin_shufflevector(v, v, 2, 2, 2, 2)};
#endif
}

// Screen-space derivatives, as GLSL's dFdx and dFdy (coarse: one a quad,
// from its top row and its left column). Meaningful only in shaders that
// ask for FACET_NEED_DERIVATIVES, whose fragments are never packed.
inline Float dFdx(const Float& v) {
    const QuadCorners c = quad_corners(v);
    return c.tr - c.tl;
}
inline Float dFdy(const Float& v) {
    const QuadCorners c = quad_corners(v);
    return c.bl - c.tl;
}
template <vec::Lanes V>
inline V dFdx(const V& v) {
    return vec::each(v, [](const Float& x) { return dFdx(x); });
}
template <vec::Lanes V>
inline V dFdy(const V& v) {
    return vec::each(v, [](const Float& x) { return dFdy(x); });
}

}  // namespace FACET_WIDE_NAMESPACE
}  // namespace facet::sdk::wide
