// facet shader declarations (C++20, header-only): each varying and each
// parameter named in one place. Included by <facet/shader.hpp>.
//
//     FACET_VARYINGS((Vec3, normal), (Vec2, uv), (Float, fog, linear))
//     FACET_PARAMS((color4, base_color, {1, 1, 1, 1}, "linear RGBA"),
//                  (texture, base_texture, "uv", srgb, "multiplies base_color"))
//
// FACET_VARYINGS makes struct Varyings (its members in that order, each a
// wide type of <facet/wide.hpp>) and the descriptor's varyings table;
// FACET_PARAMS makes struct Params (what a draw's parameter block holds)
// and the schema YAML materials are checked against, the kinds and their
// arguments being those of <facet/params.hpp>. A preprocessor list rather
// than reflection over one struct: C++20 has none, and a list reads like
// the GLSL declarations it stands for and costs the compiler little.
#pragma once

#include <facet/params.hpp>
#include <facet/shader_abi.h>
#include <facet/wide.hpp>

#include <cstddef>
#include <cstdint>

namespace facet::sdk {

using namespace wide;

namespace detail {
// The floats of a varying's type.
template <class T>
constexpr uint32_t components() {
    return uint32_t(sizeof(T) / sizeof(Float));
}
// The end of a varyings table.
inline constexpr facet_varying_desc kNoVarying{nullptr, 0, 0};
}  // namespace detail

}  // namespace facet::sdk

// FACET_SDK_FOR_EACH(m, a, b, ...) is m(a) m(b) ...: a macro's rescans,
// 256 of them, each taking the next argument (C++20's __VA_OPT__ stops it).
#define FACET_SDK_PARENS ()
#define FACET_SDK_EXPAND(...) FACET_SDK_EXPAND4(FACET_SDK_EXPAND4(FACET_SDK_EXPAND4(__VA_ARGS__)))
#define FACET_SDK_EXPAND4(...) FACET_SDK_EXPAND3(FACET_SDK_EXPAND3(FACET_SDK_EXPAND3(__VA_ARGS__)))
#define FACET_SDK_EXPAND3(...) FACET_SDK_EXPAND2(FACET_SDK_EXPAND2(FACET_SDK_EXPAND2(__VA_ARGS__)))
#define FACET_SDK_EXPAND2(...) FACET_SDK_EXPAND1(FACET_SDK_EXPAND1(FACET_SDK_EXPAND1(__VA_ARGS__)))
#define FACET_SDK_EXPAND1(...) __VA_ARGS__
#define FACET_SDK_FOR_EACH(m, ...) \
    __VA_OPT__(FACET_SDK_EXPAND(FACET_SDK_FOR_EACH_NEXT(m, __VA_ARGS__)))
#define FACET_SDK_FOR_EACH_NEXT(m, a, ...) \
    m(a) __VA_OPT__(FACET_SDK_FOR_EACH_AGAIN FACET_SDK_PARENS(m, __VA_ARGS__))
#define FACET_SDK_FOR_EACH_AGAIN() FACET_SDK_FOR_EACH_NEXT

// (type, name[, interpolation]) as a member, and as a table entry.
#define FACET_SDK_VARYING_FIELD(v) FACET_SDK_VARYING_FIELD_ v
#define FACET_SDK_VARYING_FIELD_(type, name, ...) type name;
#define FACET_SDK_VARYING_DESC(v) FACET_SDK_VARYING_DESC_ v
#define FACET_SDK_VARYING_DESC_(type, name, ...)                    \
    ::facet::sdk::varying(#name, ::facet::sdk::detail::components<type>(), \
                          FACET_SDK_INTERP(__VA_ARGS__ __VA_OPT__(, ) perspective)),
#define FACET_SDK_INTERP(first, ...) FACET_SDK_INTERP_##first
#define FACET_SDK_INTERP_perspective FACET_INTERP_PERSPECTIVE
#define FACET_SDK_INTERP_linear FACET_INTERP_LINEAR
#define FACET_SDK_INTERP_flat FACET_INTERP_FLAT

// struct Varyings and the `varyings` table, from (type, name[, how]) entries.
#define FACET_VARYINGS(...)                                                          \
    struct Varyings {                                                                \
        FACET_SDK_FOR_EACH(FACET_SDK_VARYING_FIELD, __VA_ARGS__)                     \
    };                                                                               \
    static constexpr facet_varying_desc varyings[] = {                               \
        FACET_SDK_FOR_EACH(FACET_SDK_VARYING_DESC, __VA_ARGS__)::facet::sdk::detail::kNoVarying};

// (kind, name, arguments...) as a member, and as schema entries (params.hpp).
#define FACET_SDK_PARAM_FIELD(p) FACET_SDK_PARAM_FIELD_ p
#define FACET_SDK_PARAM_FIELD_(kind, name, ...) ::facet::sdk::param::kind::type name;
#define FACET_SDK_PARAM_DESC(p) FACET_SDK_PARAM_DESC_ p
#define FACET_SDK_PARAM_DESC_(kind, name, ...) \
    ::facet::sdk::param::kind::describe(#name, offsetof(Params, name) __VA_OPT__(, ) __VA_ARGS__),

// struct Params and the `params` schema, from (kind, name, ...) entries.
#define FACET_PARAMS(...)                                                         \
    struct Params {                                                               \
        FACET_SDK_FOR_EACH(FACET_SDK_PARAM_FIELD, __VA_ARGS__)                    \
    };                                                                            \
    static constexpr auto params = ::facet::sdk::detail::schema(                  \
        FACET_SDK_FOR_EACH(FACET_SDK_PARAM_DESC, __VA_ARGS__)::facet::sdk::param::End{});
