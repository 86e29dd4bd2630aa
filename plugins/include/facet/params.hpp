// Parameter schemas for plugins (C++20, header-only): the facet_param_desc
// entries of a shader's or a screen pass's `params` table, made at compile
// time, and varyings for shaders. Included by <facet/shader.hpp> and
// <facet/post.hpp>.
#pragma once

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>

namespace facet::sdk {

constexpr facet_varying_desc varying(const char* name, uint32_t components,
                                     facet_interpolation interp = FACET_INTERP_PERSPECTIVE) {
    return {name, components, static_cast<uint32_t>(interp)};
}

namespace detail {
constexpr float kInf = std::numeric_limits<float>::infinity();

constexpr facet_param_desc param(const char* name, facet_param_type type, size_t offset,
                                 float d0, float d1, float d2, float d3, float lo, float hi,
                                 const char* doc) {
    return {name, static_cast<uint32_t>(type), static_cast<uint32_t>(offset),
            {d0, d1, d2, d3}, lo, hi, 0u, -1, doc};
}
}  // namespace detail

constexpr facet_param_desc float1(const char* name, size_t offset, float def,
                                  float lo = -detail::kInf, float hi = detail::kInf,
                                  const char* doc = nullptr) {
    return detail::param(name, FACET_PARAM_FLOAT, offset, def, 0, 0, 0, lo, hi, doc);
}
constexpr facet_param_desc int1(const char* name, size_t offset, int def, int lo, int hi,
                                const char* doc = nullptr) {
    return detail::param(name, FACET_PARAM_INT, offset, float(def), 0, 0, 0, float(lo),
                         float(hi), doc);
}
constexpr facet_param_desc boolean(const char* name, size_t offset, bool def,
                                   const char* doc = nullptr) {
    return detail::param(name, FACET_PARAM_BOOL, offset, def ? 1.f : 0.f, 0, 0, 0, 0, 1, doc);
}
constexpr facet_param_desc vec3(const char* name, size_t offset, glm::vec3 def,
                                float lo = -detail::kInf, float hi = detail::kInf,
                                const char* doc = nullptr) {
    return detail::param(name, FACET_PARAM_VEC3, offset, def.x, def.y, def.z, 0, lo, hi, doc);
}
constexpr facet_param_desc color3(const char* name, size_t offset, glm::vec3 def,
                                  const char* doc = nullptr) {
    return detail::param(name, FACET_PARAM_COLOR3, offset, def.x, def.y, def.z, 0, 0,
                         detail::kInf, doc);
}
constexpr facet_param_desc color4(const char* name, size_t offset, glm::vec4 def,
                                  const char* doc = nullptr) {
    return detail::param(name, FACET_PARAM_COLOR4, offset, def.x, def.y, def.z, def.w, 0,
                         detail::kInf, doc);
}
// A texture parameter sampled by the host at the UV held in varying
// `uv_varying`. `srgb` marks colour data, decoded to linear on sampling.
constexpr facet_param_desc texture(const char* name, size_t offset, int uv_varying, bool srgb,
                                   const char* doc = nullptr) {
    facet_param_desc p = detail::param(name, FACET_PARAM_TEXTURE, offset, 0, 0, 0, 0, 0, 1, doc);
    p.flags = srgb ? uint32_t(FACET_PARAM_SRGB) : 0u;
    p.uv_varying = uv_varying;
    return p;
}

// One of several names (ABI 1.4): the parameter holds the index of the
// name the YAML gives, among those the plugin's `param_choices` entry for
// it lists ("reinhard|aces"); `def` is the index of the default.
constexpr facet_param_desc choice(const char* name, size_t offset, int def,
                                  const char* doc = nullptr) {
    return detail::param(name, FACET_PARAM_CHOICE, offset, float(def), 0, 0, 0, 0, 0, doc);
}

namespace detail {
// The `param_choices` table of plugin struct S (one entry per parameter:
// the names of a choice, else nullptr), or nullptr when it has none.
template <class S>
constexpr const char* const* choice_table() {
    if constexpr (requires { S::param_choices; }) {
        static_assert(std::size(S::param_choices) == std::size(S::params),
                      "param_choices must have one entry for each parameter");
        return std::data(S::param_choices);
    }
    return nullptr;
}
}  // namespace detail

}  // namespace facet::sdk
