// A material's `stencil:` (material_yaml.hpp): GL's stencil test and
// operations, with the back faces' own where they differ.
#include "assets/material_yaml.hpp"

#include "facet/error.hpp"

#include <string>

namespace facet {

namespace {

StencilOp stencil_op(const yaml::Context& ctx, const YAML::Node& node) {
    using O = StencilOp;
    return yaml::as_enum<O>(ctx, node,
                            {{"keep", O::keep}, {"zero", O::zero}, {"replace", O::replace},
                             {"increment", O::increment}, {"increment_wrap", O::increment_wrap},
                             {"decrement", O::decrement}, {"decrement_wrap", O::decrement_wrap},
                             {"invert", O::invert}});
}

// A value 0 to 255 (a reference or a mask), decimal or, as masks are
// often written, hexadecimal (0x0F).
uint8_t stencil_byte(const yaml::Context& ctx, const YAML::Node& node, const char* what) {
    const std::string text = node.IsScalar() ? node.Scalar() : std::string();
    int v = 0;
    if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
        const bool hex = text.size() <= 4 && text.find_first_not_of("0123456789abcdefABCDEF", 2) ==
                                                 std::string::npos;
        yaml::ensure(hex, ctx, node, ErrorCode::wrong_type,
                     std::string("a stencil ") + what + " is 0 to 255, or 0x00 to 0xFF");
        v = std::stoi(text.substr(2), nullptr, 16);
    } else {
        v = yaml::as<int>(ctx, node);
    }
    yaml::ensure(v >= 0 && v <= 255, ctx, node, ErrorCode::out_of_range,
                 std::string("a stencil ") + what + " is 0 to 255 (8 bits)");
    return uint8_t(v);
}

// The keys of one facing over `face` (those not given keep its values).
void parse_face(const yaml::Context& ctx, const YAML::Node& node, StencilFace& face) {
    using C = StencilCompare;
    if (const YAML::Node n = node["test"])
        face.compare = yaml::as_enum<C>(
            ctx, n,
            {{"never", C::never}, {"less", C::less}, {"less_equal", C::less_equal},
             {"greater", C::greater}, {"greater_equal", C::greater_equal}, {"equal", C::equal},
             {"not_equal", C::not_equal}, {"always", C::always}});
    if (const YAML::Node n = node["ref"]) face.reference = stencil_byte(ctx, n, "reference");
    if (const YAML::Node n = node["read_mask"]) face.read_mask = stencil_byte(ctx, n, "read mask");
    if (const YAML::Node n = node["write_mask"])
        face.write_mask = stencil_byte(ctx, n, "write mask");
    if (const YAML::Node n = node["fail"]) face.fail = stencil_op(ctx, n);
    if (const YAML::Node n = node["depth_fail"]) face.depth_fail = stencil_op(ctx, n);
    if (const YAML::Node n = node["pass"]) face.pass = stencil_op(ctx, n);
}

}  // namespace

void parse_stencil(const yaml::Context& ctx, const YAML::Node& node, Material& m) {
    yaml::check_map(ctx, node, "stencil",
                    {"test", "ref", "read_mask", "write_mask", "fail", "depth_fail", "pass", "back"});
    StencilState& s = m.stencil;
    s.enabled = true;
    parse_face(ctx, node, s.front);
    s.back = s.front;
    if (const YAML::Node back = node["back"]) {
        yaml::check_map(ctx, back, "stencil's back",
                        {"test", "ref", "read_mask", "write_mask", "fail", "depth_fail", "pass"});
        parse_face(ctx, back, s.back);
    }
}

}  // namespace facet
