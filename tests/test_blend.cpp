// Blending as GL defines it: every factor and equation, colour and alpha
// apart, against a double-precision evaluation of GL's formulas, on every
// path, on float and 8-bit sRGB targets, with and without MSAA; and the
// YAML that names them.
#include "support.hpp"

#include <facet/color.hpp>
#include <facet/error.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace facet;
using namespace facet::test;

namespace {

using glm::dvec4;

// GL's factor f for channel c (3: alpha) of s over d, constant k.
double ref_factor(BlendFactor f, int c, const dvec4& s, const dvec4& d, const dvec4& k) {
    using F = BlendFactor;
    switch (f) {
        case F::zero: return 0;
        case F::one: return 1;
        case F::src_color: return s[c];
        case F::one_minus_src_color: return 1 - s[c];
        case F::dst_color: return d[c];
        case F::one_minus_dst_color: return 1 - d[c];
        case F::src_alpha: return s.a;
        case F::one_minus_src_alpha: return 1 - s.a;
        case F::dst_alpha: return d.a;
        case F::one_minus_dst_alpha: return 1 - d.a;
        case F::constant_color: return k[c];
        case F::one_minus_constant_color: return 1 - k[c];
        case F::constant_alpha: return k.a;
        case F::one_minus_constant_alpha: return 1 - k.a;
        case F::src_alpha_saturate: return c == 3 ? 1 : std::min(s.a, 1 - d.a);
    }
    return 0;
}

double ref_op(BlendOp op, double s, double fs, double d, double fd) {
    switch (op) {
        case BlendOp::add: return s * fs + d * fd;
        case BlendOp::subtract: return s * fs - d * fd;
        case BlendOp::reverse_subtract: return d * fd - s * fs;
        case BlendOp::min: return std::min(s, d);
        case BlendOp::max: return std::max(s, d);
    }
    return 0;
}

// GL's blend, in double; a normalized target clamps s, d and k first.
dvec4 ref_blend(const BlendFunc& f, dvec4 s, dvec4 d, bool normalized) {
    dvec4 k(f.constant[0], f.constant[1], f.constant[2], f.constant[3]);
    if (normalized) {
        s = glm::clamp(s, 0.0, 1.0), d = glm::clamp(d, 0.0, 1.0), k = glm::clamp(k, 0.0, 1.0);
    }
    dvec4 out;
    for (int c = 0; c < 3; ++c)
        out[c] = ref_op(f.color_op, s[c], ref_factor(f.src_color, c, s, d, k), d[c],
                        ref_factor(f.dst_color, c, s, d, k));
    out.a = ref_op(f.alpha_op, s.a, ref_factor(f.src_alpha, 3, s, d, k), d.a,
                   ref_factor(f.dst_alpha, 3, s, d, k));
    return out;
}

Mesh quad(glm::vec4 c) {
    return make_mesh({{-1, -1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}, {-1, 1, 0.5f}},
                     {0, 1, 2, 0, 2, 3}, std::vector<glm::vec4>(4, c));
}

// d drawn opaque, then s blended by f, on a target of `format` with
// `samples`: pixel (3, 3).
glm::vec4 draw_blend(const BlendFunc& f, glm::vec4 s, glm::vec4 d, ColorFormat format,
                     int samples, Isa isa) {
    static const auto shader = plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const Mesh under = quad(d), over = quad(s);
    Framebuffer fb(8, 8, format, samples);
    fb.clear(glm::vec4(0.0f), 0.0f);
    Pipeline pipeline(1, isa);
    FrameStats stats;
    DrawCall call = clip_space_call(under, *shader);
    pipeline.draw(call, fb, stats);
    call.mesh = &over;
    call.state.blend = BlendMode::custom;
    call.state.blend_func = f;
    call.state.depth_compare = DepthCompare::always;
    pipeline.draw(call, fb, stats);
    return samples == 1 ? fb.pixel(3, 3) : fb.sample(3, 3, samples - 1);
}

// The blends to try: each factor as the source's and as the destination's,
// each equation, alpha apart from colour, and a constant.
std::vector<BlendFunc> blends() {
    std::vector<BlendFunc> out;
    for (int i = 0; i <= int(BlendFactor::src_alpha_saturate); ++i) {
        BlendFunc f;
        f.src_color = f.src_alpha = BlendFactor(i);
        f.dst_color = f.dst_alpha = BlendFactor::one_minus_src_alpha;
        f.constant[0] = 0.25f, f.constant[1] = 0.5f, f.constant[2] = 2.0f, f.constant[3] = 0.75f;
        out.push_back(f);
        f.src_color = f.src_alpha = BlendFactor::src_alpha;
        f.dst_color = f.dst_alpha = BlendFactor(i);
        out.push_back(f);
    }
    for (int op = 0; op <= int(BlendOp::max); ++op) {
        BlendFunc f;
        f.src_color = BlendFactor::src_color, f.dst_color = BlendFactor::dst_alpha;
        f.color_op = BlendOp(op);
        f.src_alpha = BlendFactor::one, f.dst_alpha = BlendFactor::one_minus_src_alpha;
        f.alpha_op = BlendOp((op + 1) % 5);
        out.push_back(f);
    }
    return out;
}

}  // namespace

TEST_CASE("blend factors and equations follow GL on every path and target", "[pipeline][blend]") {
    // Source and destination off 0..1 in places, so that a float target's
    // lack of clamping and an 8-bit target's clamping both show.
    const glm::vec4 s(0.9f, 0.3f, 1.6f, 0.6f), d(0.2f, 0.7f, 0.4f, 0.8f);
    int differs = 0;  // blends whose image is not the destination's
    for (const Isa isa : supported_isas())
        for (const ColorFormat format : {ColorFormat::rgba32f, ColorFormat::srgb8})
            for (const int samples : {1, 4})
                for (const BlendFunc& f : blends()) {
                    INFO(isa_name(isa) << ", " << color_format_name(format) << ", " << samples
                                       << " samples, factors " << int(f.src_color) << " "
                                       << int(f.dst_color) << ", ops " << int(f.color_op) << " "
                                       << int(f.alpha_op));
                    const bool normalized = format == ColorFormat::srgb8;
                    // What the target holds of d: 8-bit sRGB keeps a code.
                    glm::vec4 stored = d;
                    if (normalized)
                        for (int c = 0; c < 3; ++c) stored[c] = srgb8_to_linear(linear_to_srgb8(d[c]));
                    const glm::vec4 got = draw_blend(f, s, d, format, samples, isa);
                    const dvec4 want = ref_blend(f, dvec4(s), dvec4(stored), normalized);
                    for (int c = 0; c < 4; ++c) {
                        INFO("channel " << c << ": " << got[c] << ", GL gives " << want[c]);
                        if (normalized && c < 3)  // the code nearest GL's value
                            CHECK(linear_to_srgb8(got[c]) == linear_to_srgb8(float(want[c])));
                        else if (normalized)  // alpha: 8 bits, linear
                            CHECK(std::abs(got[c] - std::clamp(want[c], 0.0, 1.0)) <= 0.5 / 255 + 1e-6);
                        else
                            CHECK(std::abs(got[c] - want[c]) <= 1e-6 * std::max(1.0, std::abs(want[c])));
                    }
                    differs += got != stored;
                }
    CHECK(differs > 0);
}

TEST_CASE("the named blend modes keep their meaning beside GL's factors", "[pipeline][blend]") {
    // premultiplied is over, for a colour already times its alpha; multiply
    // darkens and keeps the destination's alpha.
    SceneDir sd;
    const auto blended = [&](const std::string& blend) {
        const Scene scene = sd.load(
            "camera: {position: [0, 0, 3], target: [0, 0, 0]}\n"
            "render: {size: [16, 16], color_format: rgba32f, clear_color: [0.5, 0.25, 1, 1]}\n"
            "objects:\n"
            "  - mesh: " + std::string(FACET_SOURCE_DIR) + "/assets/plane/plane.obj\n"
            "    rotation: [90, 0, 0]\n"
            "    material: {shader: unlit, blend: " + blend + ", params: {base_color: [0.25, 0.5, 0.125, 0.5]}}\n");
        Framebuffer fb;
        Renderer(1).render(scene, fb);
        return fb.pixel(8, 8);
    };
    CHECK(blended("premultiplied") == glm::vec4(0.5f, 0.625f, 0.625f, 1.0f));
    CHECK(blended("multiply") == glm::vec4(0.125f, 0.125f, 0.125f, 1.0f));
    CHECK(blended("alpha") == blended("{src: src_alpha, dst: one_minus_src_alpha, src_alpha: one}"));
    CHECK(blended("additive") ==
          blended("{src: src_alpha, dst: one, src_alpha: zero, dst_alpha: one}"));
}

TEST_CASE("a bad blend is an error at its line", "[material][blend]") {
    SceneDir sd;
    const auto error = [&](const std::string& blend) {
        return sd.error("objects:\n  - mesh: " + std::string(FACET_SOURCE_DIR) +
                        "/assets/plane/plane.obj\n    material: {shader: unlit, blend: " + blend + "}\n");
    };
    CHECK_THAT(error("mix"), Catch::Contains("'mix' (expected one of: opaque, alpha, additive, "
                                             "premultiplied, multiply)"));
    CHECK_THAT(error("{src: one, dst: half}"), Catch::Contains("'half' (expected one of: zero, one") &&
                                                   Catch::Contains("scene.yaml:3:"));
    CHECK_THAT(error("{src: one, op: average}"), Catch::Contains("'average'"));
    CHECK_THAT(error("{src: one, equation: add}"), Catch::Contains("'equation'"));
    CHECK_THAT(error("{src: one, constant: [1, 2]}"), Catch::Contains("4 numbers"));
}
