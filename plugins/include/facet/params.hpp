// Parameter schemas for plugins (C++20, header-only): the facet_param_desc
// entries of a shader's or a screen pass's `params` table, made at compile
// time, and varyings for shaders. Included by <facet/shader.hpp> and
// <facet/post.hpp>. The kinds FACET_PARAMS takes (shader.hpp) are at the
// end: namespace facet::sdk::param.
#pragma once

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <type_traits>

namespace facet::sdk {

constexpr facet_varying_desc varying(const char* name, uint32_t components,
                                     facet_interpolation interp = FACET_INTERP_PERSPECTIVE) {
    return {name, components, static_cast<uint32_t>(interp)};
}

// An unbounded end of a parameter's range.
inline constexpr float infinity = std::numeric_limits<float>::infinity();

namespace detail {
constexpr float kInf = infinity;

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

// One of several names: the parameter holds the index of the
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

// ---- the kinds of FACET_PARAMS --------------------------------------------------

// A texture parameter's value in a shader's Params: whether the material
// binds one (Fragment::texture reads it).
struct Texture {
    int32_t bound;
    explicit operator bool() const { return bound != 0; }
};

// Whether a texture holds colour (sRGB-encoded, decoded to linear as it is
// sampled) or data (normals, masks: read as they are).
enum class Encoding { srgb, linear };
inline constexpr Encoding srgb = Encoding::srgb;
inline constexpr Encoding linear = Encoding::linear;

// The parameters with which a material receives the host's shadow maps and
// AO (the `receiving` kind): light_visibility() and ambient_visibility() in
// <facet/lighting.hpp> read them. The host draws shadow maps only for
// visible materials with receive_shadows on, and runs AO only for those
// with ambient_occlusion above 0.
struct Receiving {
    int32_t shadows;   // receive_shadows: filter the lights' shadow maps (bool)
    int32_t kernel;    // shadow_kernel: PCF width in texels, odd
    float bias;        // shadow_bias: constant bias, texels
    float slope_bias;  // shadow_slope_bias: bias per unit of tan(angle to the light)
    float ao;          // ambient_occlusion: ambient light times AO^this (0: none)
};

namespace param {

// What a kind gives the schema: K entries, a CHOICE's names (else null),
// and a TEXTURE's UV varying by name (resolved by the shader's describe()).
template <size_t K>
struct Entries {
    facet_param_desc at[K];
    const char* choices[K];
    const char* uv[K];
};
struct End {};

constexpr Entries<1> one(const facet_param_desc& d, const char* choices = nullptr,
                         const char* uv = nullptr) {
    return {{d}, {choices}, {uv}};
}
constexpr facet_param_desc flagged(facet_param_desc d, uint32_t flags) {
    d.flags |= flags;
    return d;
}

// The kinds, each (kind, name, arguments) in FACET_PARAMS: the member's
// type, and the arguments after the name.
struct float1 {  // (default, lowest, highest, doc)
    using type = float;
    static constexpr Entries<1> describe(const char* n, size_t at, float def,
                                         float lo = -detail::kInf, float hi = detail::kInf,
                                         const char* doc = nullptr) {
        return one(sdk::float1(n, at, def, lo, hi, doc));
    }
};
struct int1 {  // (default, lowest, highest, doc)
    using type = int32_t;
    static constexpr Entries<1> describe(const char* n, size_t at, int def, int lo, int hi,
                                         const char* doc = nullptr) {
        return one(sdk::int1(n, at, def, lo, hi, doc));
    }
};
struct boolean {  // (default, doc): an int32_t, 0 or 1
    using type = int32_t;
    static constexpr Entries<1> describe(const char* n, size_t at, bool def,
                                         const char* doc = nullptr) {
        return one(sdk::boolean(n, at, def, doc));
    }
};
struct vec3 {  // ({x, y, z}, lowest, highest, doc)
    using type = glm::vec3;
    static constexpr Entries<1> describe(const char* n, size_t at, glm::vec3 def,
                                         float lo = -detail::kInf, float hi = detail::kInf,
                                         const char* doc = nullptr) {
        return one(sdk::vec3(n, at, def, lo, hi, doc));
    }
};
struct color3 {  // ({r, g, b}, doc): linear RGB
    using type = glm::vec3;
    static constexpr Entries<1> describe(const char* n, size_t at, glm::vec3 def,
                                         const char* doc = nullptr) {
        return one(sdk::color3(n, at, def, doc));
    }
};
struct color4 {  // ({r, g, b, a}, doc): linear RGBA
    using type = glm::vec4;
    static constexpr Entries<1> describe(const char* n, size_t at, glm::vec4 def,
                                         const char* doc = nullptr) {
        return one(sdk::color4(n, at, def, doc));
    }
};
struct choice {  // (default index, "name|name|...", doc): the index of the name
    using type = int32_t;
    static constexpr Entries<1> describe(const char* n, size_t at, int def, const char* names,
                                         const char* doc = nullptr) {
        return one(sdk::choice(n, at, def, doc), names);
    }
};
struct texture {  // ("uv varying", srgb or linear, doc): sampled by the host there
    using type = Texture;
    static constexpr Entries<1> describe(const char* n, size_t at, const char* uv, Encoding e,
                                         const char* doc = nullptr) {
        return one(sdk::texture(n, at, -1, e == Encoding::srgb, doc), nullptr, uv);
    }
};
struct image {  // (srgb or linear, doc): a 2D texture the shader samples itself (Fragment::sample)
    using type = Texture;
    static constexpr Entries<1> describe(const char* n, size_t at, Encoding e,
                                         const char* doc = nullptr) {
        return one(sdk::texture(n, at, -1, e == Encoding::srgb, doc));
    }
};
struct cube {  // (srgb or linear, doc): a cube map, sampled by direction (Fragment::sample_cube)
    using type = Texture;
    static constexpr Entries<1> describe(const char* n, size_t at, Encoding e,
                                         const char* doc = nullptr) {
        return one(flagged(sdk::texture(n, at, -1, e == Encoding::srgb, doc), FACET_PARAM_CUBE));
    }
};
struct normal_map {  // ("uv varying"): a tangent-space normal map (lighting.hpp)
    using type = Texture;
    static constexpr Entries<1> describe(const char* n, size_t at, const char* uv) {
        return one(sdk::texture(n, at, -1, false,
                                "tangent-space normal map (linear; +Y towards the texture's top)"),
                   nullptr, uv);
    }
};
struct normal_scale {  // (): scales a normal map's X and Y (glTF's normalTexture.scale)
    using type = float;
    static constexpr Entries<1> describe(const char* n, size_t at) {
        return one(sdk::float1(n, at, 1.0f, -16.0f, 16.0f, "scales the normal map's X and Y"));
    }
};
// (): fragments whose alpha is below this are discarded (a cutout: a
// texture's alpha cuts a shape out of a quad). 0, the default, discards
// nothing, and the host then draws the material as fast as one that
// cannot discard. The shader asks for FACET_NEED_DISCARD and calls cut_out().
struct cutoff {
    using type = float;
    static constexpr Entries<1> describe(const char* n, size_t at) {
        return one(flagged(sdk::float1(n, at, 0.0f, 0.0f, 1.0f,
                                       "discard fragments with alpha below this; 0: none"),
                           FACET_PARAM_USES_DISCARD));
    }
};
// (): colour times AO to this power (0: no AO), for a shader with no
// lights; one with lights takes `receiving`.
struct ao_strength {
    using type = float;
    static constexpr Entries<1> describe(const char* n, size_t at) {
        return one(flagged(sdk::float1(n, at, 0.0f, 0.0f, 8.0f,
                                       "colour times AO to this power; 0: no AO"),
                           FACET_PARAM_USES_AO));
    }
};
// (): the five parameters of Receiving, named as the host's passes know them.
struct receiving {
    using type = Receiving;
    static constexpr Entries<5> describe(const char*, size_t at) {
        return {{flagged(sdk::boolean("receive_shadows", at + offsetof(Receiving, shadows), true,
                                      "filter the shadow maps of the lights that cast shadows"),
                         FACET_PARAM_USES_SHADOWS),
                 sdk::int1("shadow_kernel", at + offsetof(Receiving, kernel), 3, 1, 15,
                           "percentage-closer filter width in texels (odd)"),
                 sdk::float1("shadow_bias", at + offsetof(Receiving, bias), 1.0f, 0.0f, 64.0f,
                             "constant shadow bias, texels"),
                 sdk::float1("shadow_slope_bias", at + offsetof(Receiving, slope_bias), 1.5f, 0.0f,
                             64.0f, "shadow bias per unit of tan(angle to the light), texels"),
                 flagged(sdk::float1("ambient_occlusion", at + offsetof(Receiving, ao), 0.0f, 0.0f,
                                     8.0f, "ambient light times AO to this power; 0: no AO"),
                         FACET_PARAM_USES_AO)},
                {},
                {}};
    }
};

}  // namespace param

namespace detail {

// A schema: its entries, each one's CHOICE names and TEXTURE UV varying.
template <size_t N>
struct Schema {
    std::array<facet_param_desc, N> at{};
    std::array<const char*, N> choices{};
    std::array<const char*, N> uv{};
    uint32_t count = 0;
    bool has_choices = false;
};

template <class E>
constexpr size_t entries_in() {
    if constexpr (std::is_same_v<E, param::End>) return 0;
    else return sizeof(E::at) / sizeof(E::at[0]);
}

// The schema of every kind's entries in order (the last argument is End).
template <class... E>
constexpr auto schema(const E&... e) {
    constexpr size_t n = (entries_in<E>() + ... + 0);
    Schema<(n > 0 ? n : 1)> s;
    const auto add = [&](const auto& entries) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(entries)>, param::End>)
            for (size_t k = 0; k < entries_in<std::decay_t<decltype(entries)>>(); ++k) {
                s.at[s.count] = entries.at[k];
                s.choices[s.count] = entries.choices[k];
                s.uv[s.count] = entries.uv[k];
                s.has_choices |= entries.choices[k] != nullptr;
                ++s.count;
            }
    };
    (add(e), ...);
    return s;
}

}  // namespace detail

}  // namespace facet::sdk
