// The fixed-function modes a material or a scene chooses and the pipeline
// applies (PipelineState, facet/pipeline.hpp): face culling, blending and
// the depth and stencil tests. Plain types, so that assets name them without depending
// on the pipeline.
#pragma once

#include <cstdint>

namespace facet {

enum class CullMode { none, back, front };

// What a draw's mesh is drawn as: its triangles; its triangles' edges,
// each once, as lines; or its vertices as points. A line of width w is the
// rectangle w pixels across centred on it, ending at its end points, and a
// point of size s the square of side s centred on it (Vulkan's rectangular
// lines and its points), each covering what a triangle would: the same
// sample positions, the top-left rule on the edges.
enum class Topology { triangles, lines, points };

// opaque, alpha and additive are facet's named modes (a material's `blend:
// alpha`); custom blends by BlendFunc, as GL does.
enum class BlendMode { opaque, alpha, additive, custom };

// GL's blend factors (glBlendFuncSeparate), for the source s (the shader's
// colour), the destination d (the target's) and the constant c. On the
// colour channels: zero, one, s, 1 - s, d, 1 - d, s.a, 1 - s.a, d.a,
// 1 - d.a, c, 1 - c, c.a, 1 - c.a, min(s.a, 1 - d.a); on alpha a colour
// factor takes its alpha, and src_alpha_saturate is 1.
enum class BlendFactor {
    zero, one, src_color, one_minus_src_color, dst_color, one_minus_dst_color,
    src_alpha, one_minus_src_alpha, dst_alpha, one_minus_dst_alpha,
    constant_color, one_minus_constant_color, constant_alpha, one_minus_constant_alpha,
    src_alpha_saturate
};

// GL's blend equations (glBlendEquationSeparate): s * S + d * D, s * S -
// d * D, d * D - s * S, and min and max of s and d (which take no factors).
enum class BlendOp { add, subtract, reverse_subtract, min, max };

// A blend as GL writes it, colour and alpha apart. On a target of 8 bits a
// channel (srgb8) the source, the destination (decoded to linear) and the
// constant are clamped to 0..1 first, as GL clamps for a normalized
// target; a float target takes them as they are.
struct BlendFunc {
    BlendFactor src_color = BlendFactor::one, dst_color = BlendFactor::zero;
    BlendOp color_op = BlendOp::add;
    BlendFactor src_alpha = BlendFactor::one, dst_alpha = BlendFactor::zero;
    BlendOp alpha_op = BlendOp::add;
    float constant[4] = {0.0f, 0.0f, 0.0f, 0.0f};  // linear RGBA
};

enum class DepthCompare { never, less, less_equal, greater, greater_equal, equal, always };

// GL's stencil test (glStencilFuncSeparate): a fragment passes where
// (reference & read_mask) compares so with (stored & read_mask); `less`
// passes where the masked reference is less than the masked stored value.
enum class StencilCompare {
    never, less, less_equal, greater, greater_equal, equal, not_equal, always
};

// GL's stencil operations (glStencilOpSeparate): keep, 0, the reference,
// +1 clamped at 255, +1 wrapping, -1 clamped at 0, -1 wrapping, bitwise
// not. Only the bits of the write mask change.
enum class StencilOp {
    keep, zero, replace, increment, increment_wrap, decrement, decrement_wrap, invert
};

// One facing's stencil state: its test, and the operation where the
// stencil test fails, where it passes and the depth test fails, and where
// both pass.
struct StencilFace {
    StencilCompare compare = StencilCompare::always;
    uint8_t reference = 0, read_mask = 0xFF, write_mask = 0xFF;
    StencilOp fail = StencilOp::keep, depth_fail = StencilOp::keep, pass = StencilOp::keep;
    bool operator==(const StencilFace&) const = default;
};

// The 8-bit stencil test and operations of a draw, front- and back-facing
// triangles apart, as GL has them. Off, the stencil buffer is neither
// tested nor written.
struct StencilState {
    bool enabled = false;
    StencilFace front, back;
    bool operator==(const StencilState&) const = default;
};

}  // namespace facet
