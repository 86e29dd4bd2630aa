// facet shader authoring layer: vector math for fragment shaders (C++20,
// header-only; GCC or Clang).
//
// A fragment shader may give, beside its scalar `fragment`, a
// `fragment_wide` that shades several lanes of a block at once with the
// types below. It reads like the scalar one - Vec3 for glm::vec3, select()
// for a branch - and each value is one vector register, where the scalar
// loop runs lane after lane. When a shader has both, facet::sdk uses the
// wide one; define FACET_SDK_SCALAR before including <facet/shader.hpp> to
// use the scalar one (tests compare them).
//
// Float holds kLanes floats, as many as the widest register of the target
// the code is compiled for: 16 with AVX-512, 8 with AVX2, 4 with SSE2 or
// NEON. facet_add_shader() compiles a plugin once for each x86-64 path, so
// the same fragment_wide runs 4, 8 or 16 lanes at a time and never holds
// more values than the registers can; the batch loop calls it once per
// kLanes lanes of the 16-fragment batch and skips lanes with no fragment.
// Write it for any kLanes: a batch may hold pixels of several blocks and
// triangles (shader.hpp), and WideFragment::coord gives each lane's pixel.
//
// Arithmetic and comparisons work lane by lane, mixed freely with plain
// floats; a comparison gives a Mask (all ones or zero per lane). The
// functions here are as accurate as their scalar counterparts within a few
// units in the last place, except pow (see there).
#pragma once

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#elif defined(__ARM_NEON) && defined(__aarch64__)
#include <arm_neon.h>
#endif

#if defined(__AVX512F__)
#define FACET_WIDE_LANES 16
#define FACET_WIDE_NAMESPACE lanes16
#elif defined(__AVX__)
#define FACET_WIDE_LANES 8
#define FACET_WIDE_NAMESPACE lanes8
#else
#define FACET_WIDE_LANES 4
#define FACET_WIDE_NAMESPACE lanes4
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
#if defined(__AVX512F__)
    const __m512 x = std::bit_cast<__m512>(b), y = std::bit_cast<__m512>(a);
    return std::bit_cast<Float>(_mm512_mask_min_ps(x, 0xFFFF, x, y));  // GCC 12 warns of the plain form
#elif defined(__AVX__)
    return std::bit_cast<Float>(_mm256_min_ps(std::bit_cast<__m256>(b), std::bit_cast<__m256>(a)));
#elif defined(__SSE2__)
    return std::bit_cast<Float>(_mm_min_ps(std::bit_cast<__m128>(b), std::bit_cast<__m128>(a)));
#else
    return b < a ? b : a;
#endif
}
inline Float max(const Float& a, const Float& b) {
#if defined(__AVX512F__)
    const __m512 x = std::bit_cast<__m512>(b), y = std::bit_cast<__m512>(a);
    return std::bit_cast<Float>(_mm512_mask_max_ps(x, 0xFFFF, x, y));  // GCC 12 warns of the plain form
#elif defined(__AVX__)
    return std::bit_cast<Float>(_mm256_max_ps(std::bit_cast<__m256>(b), std::bit_cast<__m256>(a)));
#elif defined(__SSE2__)
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
#if defined(__AVX512F__)
    return std::bit_cast<Float>(_mm512_maskz_sqrt_ps(0xFFFF, std::bit_cast<__m512>(x)));
#elif defined(__AVX__)
    return std::bit_cast<Float>(_mm256_sqrt_ps(std::bit_cast<__m256>(x)));
#elif defined(__SSE2__)
    return std::bit_cast<Float>(_mm_sqrt_ps(std::bit_cast<__m128>(x)));
#elif defined(__ARM_NEON) && defined(__aarch64__)
    return std::bit_cast<Float>(vsqrtq_f32(std::bit_cast<float32x4_t>(x)));
#else
    Float r;
    for (int i = 0; i < kLanes; ++i) r[i] = std::sqrt(x[i]);
    return r;
#endif
}

// As std::floor and std::ceil, but a zero result is always +0 (they may
// give -0), so that every path gives the same bits. Floats of magnitude
// 2^23 or more are whole already and stay as they are, as do NaN and
// infinities. One rounding instruction where the path has one.
inline Float floor(const Float& x) {
#if defined(__AVX512F__)
    const __m512 v = std::bit_cast<__m512>(x);  // masked: GCC 12 warns of the plain form
    return std::bit_cast<Float>(_mm512_mask_roundscale_ps(v, 0xFFFF, v, 0x09)) + 0.0f;
#elif defined(__AVX__)
    return std::bit_cast<Float>(_mm256_round_ps(std::bit_cast<__m256>(x), 0x09)) + 0.0f;
#else
    const Mask small = x < 8388608.0f && x > -8388608.0f;  // false for NaN
    const Float t = __builtin_convertvector(
        __builtin_convertvector(select(small, x, splat(0.0f)), Mask), Float);  // truncated
    return select(small, select(t > x, t - 1.0f, t), x);
#endif
}
inline Float ceil(const Float& x) {
#if defined(__AVX512F__)
    const __m512 v = std::bit_cast<__m512>(x);  // masked: GCC 12 warns of the plain form
    return std::bit_cast<Float>(_mm512_mask_roundscale_ps(v, 0xFFFF, v, 0x0A)) + 0.0f;
#elif defined(__AVX__)
    return std::bit_cast<Float>(_mm256_round_ps(std::bit_cast<__m256>(x), 0x0A)) + 0.0f;
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
#if defined(__AVX512F__)
    return std::bit_cast<Float>(_mm512_mask_i32gather_ps(
        _mm512_set1_ps(otherwise), _mm512_cmplt_epi32_mask(std::bit_cast<__m512i>(m),
                                                           _mm512_setzero_si512()),
        std::bit_cast<__m512i>(index), base, 4));
#elif defined(__AVX2__)
    return std::bit_cast<Float>(_mm256_mask_i32gather_ps(
        _mm256_set1_ps(otherwise), base, std::bit_cast<__m256i>(index),
        std::bit_cast<__m256>(m), 4));
#else
    Float r;
    for (int i = 0; i < kLanes; ++i) r[i] = m[i] ? base[index[i]] : otherwise;
    return r;
#endif
}

// The four floats base[index[i]] .. base[index[i] + 3] of every lane i:
// out[k][i] = base[index[i] + k], for records of four floats (every index
// and the three after it must be inside the array). One 16-byte load per
// lane and a 4x4 transpose in each 128-bit part, where four gathers would
// fetch each float on its own.
inline void gather4(const float* base, const Mask& index, Float out[4]) {
#if defined(__AVX512F__)
    __m512 r[4];  // part j of r[k]: lane 4j + k's record
    for (int k = 0; k < 4; ++k) {
        const auto part = [&](int j) { return _mm_loadu_ps(base + index[4 * j + k]); };
        r[k] = _mm512_insertf32x4(_mm512_castps128_ps512(part(0)), part(1), 1);
        r[k] = _mm512_insertf32x4(r[k], part(2), 2);
        r[k] = _mm512_insertf32x4(r[k], part(3), 3);
    }
    // Masked unpacks: GCC 12 warns that the plain ones' source is undefined.
    const auto lo = [](__m512 a, __m512 b) { return _mm512_mask_unpacklo_ps(a, 0xFFFF, a, b); };
    const auto hi = [](__m512 a, __m512 b) { return _mm512_mask_unpackhi_ps(a, 0xFFFF, a, b); };
    const __m512 t0 = lo(r[0], r[1]), t1 = hi(r[0], r[1]), t2 = lo(r[2], r[3]), t3 = hi(r[2], r[3]);
    out[0] = std::bit_cast<Float>(_mm512_shuffle_ps(t0, t2, 0x44));
    out[1] = std::bit_cast<Float>(_mm512_shuffle_ps(t0, t2, 0xEE));
    out[2] = std::bit_cast<Float>(_mm512_shuffle_ps(t1, t3, 0x44));
    out[3] = std::bit_cast<Float>(_mm512_shuffle_ps(t1, t3, 0xEE));
#elif defined(__AVX__)
    __m256 r[4];  // r[k]: lane k's record, then lane k + 4's
    for (int k = 0; k < 4; ++k)
        r[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(base + index[k])),
                                    _mm_loadu_ps(base + index[k + 4]), 1);
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    out[0] = std::bit_cast<Float>(_mm256_shuffle_ps(t0, t2, 0x44));
    out[1] = std::bit_cast<Float>(_mm256_shuffle_ps(t0, t2, 0xEE));
    out[2] = std::bit_cast<Float>(_mm256_shuffle_ps(t1, t3, 0x44));
    out[3] = std::bit_cast<Float>(_mm256_shuffle_ps(t1, t3, 0xEE));
#elif defined(__SSE2__)
    __m128 r[4];
    for (int k = 0; k < 4; ++k) r[k] = _mm_loadu_ps(base + index[k]);
    const __m128 t0 = _mm_unpacklo_ps(r[0], r[1]), t1 = _mm_unpackhi_ps(r[0], r[1]);
    const __m128 t2 = _mm_unpacklo_ps(r[2], r[3]), t3 = _mm_unpackhi_ps(r[2], r[3]);
    out[0] = std::bit_cast<Float>(_mm_movelh_ps(t0, t2));
    out[1] = std::bit_cast<Float>(_mm_movehl_ps(t2, t0));
    out[2] = std::bit_cast<Float>(_mm_movelh_ps(t1, t3));
    out[3] = std::bit_cast<Float>(_mm_movehl_ps(t3, t1));
#else
    for (int i = 0; i < kLanes; ++i)
        for (int k = 0; k < 4; ++k) out[k][i] = base[index[i] + k];
#endif
}

// For kLanes / 2 lanes, as many 64-bit lanes: the four 16-bit values
// base[index[i]] .. base[index[i] + 3] of each, the first in the lowest
// bits; every index and the three after it must be inside the array.
using Quads = uint64_t __attribute__((vector_size(4 * kLanes)));
using HalfIndex = int32_t __attribute__((vector_size(2 * kLanes)));
inline Quads gather_quads(const uint16_t* base, const HalfIndex& index) {
#if defined(__AVX512F__)
    // The masked form: GCC 12 warns that the plain one's source is undefined.
    return std::bit_cast<Quads>(_mm512_mask_i32gather_epi64(
        _mm512_setzero_si512(), 0xFF, std::bit_cast<__m256i>(index), base, 2));
#elif defined(__AVX2__)
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
    const Float r = exp2(y * log2(max(x, splat(1.17549435e-38f))));
    const Float zero = select(y == 0.0f, splat(1.0f), splat(0.0f));
    return select(x != x, x, select(x < 1.17549435e-38f, zero, r));  // NaN stays NaN
}
inline Float pow(const Float& x, float y) { return pow(x, splat(y)); }

struct Vec2 {
    Float x, y;
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
    Vec4(const Float& x_, const Float& y_, const Float& z_, const Float& w_)
        : x(x_), y(y_), z(z_), w(w_) {}
    explicit Vec4(const glm::vec4& v) : x(splat(v.x)), y(splat(v.y)), z(splat(v.z)), w(splat(v.w)) {}
};

// Vec3 arithmetic, lane by lane, with Vec3, Float or float operands.
inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(const Vec3& a, const Float& s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(const Float& s, const Vec3& a) { return a * s; }
// One division, three multiplies (within an ulp or two of three divisions).
inline Vec3 operator/(const Vec3& a, const Float& s) {
    const Float r = 1.0f / s;
    return {a.x * r, a.y * r, a.z * r};
}
inline Vec3 operator+(const Vec3& a, const glm::vec3& b) { return a + Vec3(b); }
inline Vec3 operator+(const glm::vec3& a, const Vec3& b) { return Vec3(a) + b; }
inline Vec3 operator-(const glm::vec3& a, const Vec3& b) { return Vec3(a) - b; }
inline Vec3 operator*(const Vec3& a, const glm::vec3& b) { return a * Vec3(b); }
inline Vec3 operator*(const glm::vec3& a, const Vec3& b) { return Vec3(a) * b; }
inline Vec3 operator*(const glm::vec3& a, const Float& s) { return Vec3(a) * s; }
inline Vec3 operator*(const Float& s, const glm::vec3& a) { return Vec3(a) * s; }
inline Vec3& operator+=(Vec3& a, const Vec3& b) { return a = a + b; }

inline Vec4 operator+(const Vec4& a, const Vec4& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w};
}
inline Vec4 operator*(const Vec4& a, const Vec4& b) {
    return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w};
}
inline Vec4 operator*(const Vec4& a, const glm::vec4& b) { return a * Vec4(b); }

inline Vec3 select(const Mask& m, const Vec3& a, const Vec3& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}

inline Float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Float length(const Vec3& v) { return sqrt(dot(v, v)); }
// As glm::normalize: v times 1 / |v|.
inline Vec3 normalize(const Vec3& v) { return v * (1.0f / sqrt(dot(v, v))); }
// As glm::reflect: i - 2 dot(n, i) n.
inline Vec3 reflect(const Vec3& i, const Vec3& n) { return i - n * (2.0f * dot(n, i)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The lanes of a call as a bit mask (bit i for lane i), from a Mask.
inline uint32_t bits(const Mask& m) {
#if defined(__AVX512F__)
    return _mm512_cmplt_epi32_mask(std::bit_cast<__m512i>(m), _mm512_setzero_si512());
#elif defined(__AVX__)
    return uint32_t(_mm256_movemask_ps(std::bit_cast<__m256>(m)));
#elif defined(__SSE2__)
    return uint32_t(_mm_movemask_ps(std::bit_cast<__m128>(m)));
#else
    uint32_t r = 0;
    for (int i = 0; i < kLanes; ++i) r |= uint32_t(m[i] != 0) << i;
    return r;
#endif
}

// Whether any lane of `m` is set: to skip work no lane needs, as a GPU
// shader branches when a whole warp agrees.
inline bool any(const Mask& m) { return bits(m) != 0; }

}  // namespace FACET_WIDE_NAMESPACE
}  // namespace facet::sdk::wide
