// Blending: a fragment's colour s over the target's d, by the draw's
// PipelineState (one of the per-ISA kernel headers: wide for a part of a
// block, scalar for one MSAA sample; the two give the same floats).
//
// The named modes (the factor a is the source alpha clamped to 0..1):
//   alpha:    colour s * a + d * (1 - a),  alpha a + d.a * (1 - a)
//   additive: colour s * a + d,            alpha d.a
// custom follows GL (BlendFunc, render_state.hpp): op(s * S, d * D) on
// colour and on alpha with their own factors; on a normalized target
// (srgb8) s, d and the constant are clamped to 0..1 first.
#pragma once

#ifndef FACET_KERNEL_NS
#error "blend.hpp belongs to the per-ISA kernel sources (core/CMakeLists.txt)"
#endif

#include "pipeline/pixels.hpp"

#include "facet/pipeline.hpp"

#include <algorithm>
#include <type_traits>

#include <glm/glm.hpp>

namespace facet::FACET_KERNEL_NS {

namespace blending {

// One channel or lane type: Float (wide) or float (a sample).
template <class T>
T clamp01(const T& x) {
    if constexpr (std::is_same_v<T, float>) return std::clamp(x, 0.0f, 1.0f);
    else return x < 0.0f ? T{} : x > 1.0f ? T{} + 1.0f : x;
}

template <class T>
T lesser(const T& a, const T& b) {
    if constexpr (std::is_same_v<T, float>) return a < b ? a : b;
    else return simd::min(a, b);
}

template <class T>
T greater(const T& a, const T& b) {
    if constexpr (std::is_same_v<T, float>) return a > b ? a : b;
    else return simd::max(a, b);
}

// Factor f for channel c (0..3, 3 alpha) of s over d, constant k.
template <class T>
T factor(BlendFactor f, int c, const T* s, const T* d, const T* k) {
    using F = BlendFactor;
    const T one = T{} + 1.0f;
    switch (f) {
        case F::zero: return T{};
        case F::one: return one;
        case F::src_color: return s[c];
        case F::one_minus_src_color: return one - s[c];
        case F::dst_color: return d[c];
        case F::one_minus_dst_color: return one - d[c];
        case F::src_alpha: return s[3];
        case F::one_minus_src_alpha: return one - s[3];
        case F::dst_alpha: return d[3];
        case F::one_minus_dst_alpha: return one - d[3];
        case F::constant_color: return k[c];
        case F::one_minus_constant_color: return one - k[c];
        case F::constant_alpha: return k[3];
        case F::one_minus_constant_alpha: return one - k[3];
        case F::src_alpha_saturate: return c == 3 ? one : lesser(s[3], one - d[3]);
    }
    return T{};
}

template <class T>
T apply(BlendOp op, const T& s, const T& fs, const T& d, const T& fd) {
    switch (op) {
        case BlendOp::add: return s * fs + d * fd;
        case BlendOp::subtract: return s * fs - d * fd;
        case BlendOp::reverse_subtract: return d * fd - s * fs;
        case BlendOp::min: return lesser(s, d);
        case BlendOp::max: return greater(s, d);
    }
    return s;
}

// GL's blend of channels s over d (four each), into out.
template <class T>
void custom(const BlendFunc& f, bool normalized, const T* src, const T* dst, T* out) {
    T s[4], d[4], k[4];
    for (int c = 0; c < 4; ++c) {
        s[c] = normalized ? clamp01(src[c]) : src[c];
        d[c] = normalized ? clamp01(dst[c]) : dst[c];
        const T constant = T{} + f.constant[c];
        k[c] = normalized ? clamp01(constant) : constant;
    }
    for (int c = 0; c < 3; ++c)
        out[c] = apply(f.color_op, s[c], factor(f.src_color, c, s, d, k), d[c],
                       factor(f.dst_color, c, s, d, k));
    out[3] = apply(f.alpha_op, s[3], factor(f.src_alpha, 3, s, d, k), d[3],
                   factor(f.dst_alpha, 3, s, d, k));
}

}  // namespace blending

// src over dst on a target of `format`: C is Rgba (a part of a block,
// wide) or glm::vec4 (one sample); the two give the same floats.
template <class C>
C blend(const PipelineState& state, ColorFormat format, const C& src, const C& dst) {
    using T = std::remove_cv_t<std::remove_reference_t<decltype(src.r)>>;
    const T a = blending::clamp01(src.a);
    switch (state.blend) {
        case BlendMode::opaque: return src;
        case BlendMode::alpha: {
            const T keep = 1.0f - a;
            return {src.r * a + dst.r * keep, src.g * a + dst.g * keep, src.b * a + dst.b * keep,
                    a + dst.a * keep};
        }
        case BlendMode::additive:
            return {dst.r + src.r * a, dst.g + src.g * a, dst.b + src.b * a, dst.a};
        case BlendMode::custom: {
            const T s[4] = {src.r, src.g, src.b, src.a}, d[4] = {dst.r, dst.g, dst.b, dst.a};
            T out[4];
            blending::custom(state.blend_func, format == ColorFormat::srgb8, s, d, out);
            return {out[0], out[1], out[2], out[3]};
        }
    }
    return src;
}

}  // namespace facet::FACET_KERNEL_NS
