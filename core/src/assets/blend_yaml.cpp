// A material's `blend:` (material_yaml.hpp): a named mode, or GL's factors
// and equations.
#include "assets/material_yaml.hpp"

#include "facet/error.hpp"

#include <cmath>

namespace facet {

namespace {

BlendFactor factor(const yaml::Context& ctx, const YAML::Node& node) {
    using F = BlendFactor;
    return yaml::as_enum<F>(
        ctx, node,
        {{"zero", F::zero}, {"one", F::one}, {"src_color", F::src_color},
         {"one_minus_src_color", F::one_minus_src_color}, {"dst_color", F::dst_color},
         {"one_minus_dst_color", F::one_minus_dst_color}, {"src_alpha", F::src_alpha},
         {"one_minus_src_alpha", F::one_minus_src_alpha}, {"dst_alpha", F::dst_alpha},
         {"one_minus_dst_alpha", F::one_minus_dst_alpha}, {"constant_color", F::constant_color},
         {"one_minus_constant_color", F::one_minus_constant_color},
         {"constant_alpha", F::constant_alpha},
         {"one_minus_constant_alpha", F::one_minus_constant_alpha},
         {"src_alpha_saturate", F::src_alpha_saturate}});
}

BlendOp op(const yaml::Context& ctx, const YAML::Node& node) {
    return yaml::as_enum<BlendOp>(ctx, node,
                                  {{"add", BlendOp::add},
                                   {"subtract", BlendOp::subtract},
                                   {"reverse_subtract", BlendOp::reverse_subtract},
                                   {"min", BlendOp::min},
                                   {"max", BlendOp::max}});
}

// The same factors and equation for colour and alpha.
BlendFunc same(BlendFactor src, BlendFactor dst) {
    BlendFunc f;
    f.src_color = f.src_alpha = src;
    f.dst_color = f.dst_alpha = dst;
    return f;
}

// {src, dst, op, src_alpha, dst_alpha, op_alpha, constant}: alpha's take
// colour's unless given (glBlendFunc, then glBlendFuncSeparate).
BlendFunc parse_factors(const yaml::Context& ctx, const YAML::Node& node) {
    yaml::check_map(ctx, node, "blend",
                    {"src", "dst", "op", "src_alpha", "dst_alpha", "op_alpha", "constant"});
    BlendFunc f;
    if (const YAML::Node n = node["src"]) f.src_color = f.src_alpha = factor(ctx, n);
    if (const YAML::Node n = node["dst"]) f.dst_color = f.dst_alpha = factor(ctx, n);
    if (const YAML::Node n = node["op"]) f.color_op = f.alpha_op = op(ctx, n);
    if (const YAML::Node n = node["src_alpha"]) f.src_alpha = factor(ctx, n);
    if (const YAML::Node n = node["dst_alpha"]) f.dst_alpha = factor(ctx, n);
    if (const YAML::Node n = node["op_alpha"]) f.alpha_op = op(ctx, n);
    if (const YAML::Node n = node["constant"]) {
        const glm::vec4 c = yaml::as<glm::vec4>(ctx, n);
        for (int i = 0; i < 4; ++i) f.constant[i] = c[i];
    }
    return f;
}

}  // namespace

void parse_blend(const yaml::Context& ctx, const YAML::Node& node, Material& m) {
    if (node.IsMap()) {
        m.blend = BlendMode::custom;
        m.blend_func = parse_factors(ctx, node);
        return;
    }
    enum class Named { opaque, alpha, additive, premultiplied, multiply };
    const Named named = yaml::as_enum<Named>(ctx, node,
                                             {{"opaque", Named::opaque},
                                              {"alpha", Named::alpha},
                                              {"additive", Named::additive},
                                              {"premultiplied", Named::premultiplied},
                                              {"multiply", Named::multiply}});
    switch (named) {
        case Named::opaque: m.blend = BlendMode::opaque; return;
        case Named::alpha: m.blend = BlendMode::alpha; return;
        case Named::additive: m.blend = BlendMode::additive; return;
        case Named::premultiplied:  // colour already times alpha: over, as GL composites it
            m.blend = BlendMode::custom;
            m.blend_func = same(BlendFactor::one, BlendFactor::one_minus_src_alpha);
            return;
        case Named::multiply:  // the colour darkens what is there; its alpha stays
            m.blend = BlendMode::custom;
            m.blend_func = same(BlendFactor::dst_color, BlendFactor::zero);
            m.blend_func.src_alpha = BlendFactor::zero;
            m.blend_func.dst_alpha = BlendFactor::one;
            return;
    }
}

}  // namespace facet
