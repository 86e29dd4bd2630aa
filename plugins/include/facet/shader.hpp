// facet shader authoring layer (C++20, header-only).
//
// Write a shader as a struct with plain per-vertex and per-fragment functions;
// FACET_SHADER(YourShader) generates the batch loops and the C descriptor of
// <facet/shader_abi.h> inside your plugin, so your functions inline into the
// loops. The fragment loop visits a batch's covered pixels one at a time; a
// shader that also gives fragment_wide (facet/wide.hpp) shades them kLanes
// at a time instead. A batch is 16 fragments: a 4x4 block, or, for shaders
// that may be packed (the default), covered pixels of any blocks and
// triangles of one draw. A whole shader:
//
//     struct Tint {
//         struct Params { glm::vec4 color; };
//         struct Varyings { glm::vec3 normal; };
//         static constexpr const char* name = "tint";
//         static constexpr const char* version = "1.0";
//         static constexpr uint32_t needs = FACET_NEED_NORMALS;
//         static constexpr facet_varying_desc varyings[] = {
//             facet::sdk::varying("normal", 3)};
//         static constexpr facet_param_desc params[] = {
//             facet::sdk::color4("color", offsetof(Params, color), {1, 1, 1, 1})};
//
//         static Varyings vertex(const facet::sdk::VertexIn& in, const facet::sdk::Draw& d,
//                                const Params&, glm::vec4& clip) {
//             clip = d.model_view_projection() * glm::vec4(in.position, 1.0f);
//             return {d.normal_matrix() * in.normal};
//         }
//         static glm::vec4 fragment(const Varyings& v, facet::sdk::Fragment&,
//                                   const facet::sdk::Draw&, const Params& p) {
//             return p.color * (0.5f + 0.5f * glm::normalize(v.normal).y);
//         }
//     };
//     FACET_SHADER(Tint)
//
// Rules: Varyings holds only floats (glm vectors of float), declared in the
// same order and sizes as `varyings`; Params is a standard-layout struct whose
// fields the `params` schema points at with offsetof. Shaders are called from
// several threads at once and must keep no mutable state. fragment() runs
// only for the covered lanes of a block (those that passed the depth test).
//
// Varyings read only under a parameter (ABI 1.5): a shader whose last
// varyings serve only, say, its normal map declares
//     static constexpr uint32_t conditional_varyings = 1;      // the last one
//     static constexpr const char* varyings_condition = "normal_texture";
// and the host interpolates them only for materials with that parameter
// set; for the others, their members of Varyings are left unset: read them
// only under the condition.
#pragma once

#include <facet/params.hpp>
#include <facet/shader_abi.h>
#if defined(__GNUC__) || defined(__clang__)  // vector extensions: fragment_wide
#include <facet/wide.hpp>
#define FACET_SDK_WIDE 1
#endif

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace facet::sdk {

// ---- lights ----------------------------------------------------------------------

// Light from `l` arriving at world point `p`.
struct Incident {
    glm::vec3 to_light;  // unit vector from p towards the light
    glm::vec3 radiance;  // colour * intensity * attenuation * spot cone; 0 past range
    float distance;      // to the light; infinite for directional lights
};

// How much of a spot light's cone reaches a point at `cos_angle` from its
// axis: smoothstep(cos outer, cos inner, cos angle), or a hard edge when the
// two cones are equal.
inline float spot_cone(const facet_light& l, float cos_angle) {
    if (l.spot_cos_inner <= l.spot_cos_outer) return cos_angle >= l.spot_cos_outer ? 1.0f : 0.0f;
    return glm::smoothstep(l.spot_cos_outer, l.spot_cos_inner, cos_angle);
}

// Directional lights shine along `direction` (the host normalises it).
// Point and spot lights fall off as 1 / (c + l d + q d^2) with attenuation =
// {c, l, q}, give nothing past `range` (if not 0) or at their own position,
// and a spot light is limited to its cone (spot_cone).
inline Incident incident_light(const facet_light& l, glm::vec3 p) {
    const glm::vec3 color = glm::make_vec3(l.color) * l.intensity;
    const glm::vec3 direction = glm::make_vec3(l.direction);
    if (l.type == FACET_LIGHT_DIRECTIONAL)
        return {-direction, color, std::numeric_limits<float>::infinity()};
    const glm::vec3 offset = glm::make_vec3(l.position) - p;
    const float d = glm::length(offset);
    if (d <= 0.0f || (l.range > 0.0f && d > l.range)) return {glm::vec3(0.0f), glm::vec3(0.0f), d};
    const glm::vec3 to_light = offset / d;
    float scale = 1.0f / (l.attenuation[0] + l.attenuation[1] * d + l.attenuation[2] * d * d);
    if (l.type == FACET_LIGHT_SPOT) scale *= spot_cone(l, glm::dot(-to_light, direction));
    return {to_light, color * scale, d};
}

#if FACET_SDK_WIDE
// The same for wide::kLanes points at once (fragment_wide).
struct WideIncident {
    wide::Vec3 to_light;
    wide::Vec3 radiance;
    wide::Float distance;
};

inline wide::Float spot_cone(const facet_light& l, const wide::Float& cos_angle) {
    using namespace wide;
    if (l.spot_cos_inner <= l.spot_cos_outer)
        return select(cos_angle >= l.spot_cos_outer, splat(1.0f), splat(0.0f));
    // A multiply by the reciprocal, where the scalar form divides: within an
    // ulp or two, and no division per lane.
    const Float t = clamp((cos_angle - l.spot_cos_outer) *
                              (1.0f / (l.spot_cos_inner - l.spot_cos_outer)),
                          0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

inline WideIncident incident_light(const facet_light& l, const wide::Vec3& p) {
    using namespace wide;
    const glm::vec3 color = glm::make_vec3(l.color) * l.intensity;
    const glm::vec3 direction = glm::make_vec3(l.direction);
    if (l.type == FACET_LIGHT_DIRECTIONAL)
        return {Vec3(-direction), Vec3(color), splat(std::numeric_limits<float>::infinity())};
    const Vec3 offset = glm::make_vec3(l.position) - p;
    const Float d = length(offset);
    Mask dark = d <= 0.0f;
    if (l.range > 0.0f) dark |= d > l.range;
    const Vec3 to_light = offset / d;
    Float scale = 1.0f / (l.attenuation[0] + l.attenuation[1] * d + l.attenuation[2] * d * d);
    if (l.type == FACET_LIGHT_SPOT) scale *= spot_cone(l, dot(-to_light, Vec3(direction)));
    return {select(dark, Vec3(splat(0.0f)), to_light), Vec3(color) * select(dark, splat(0.0f), scale),
            d};
}
#endif

// ---- shadow maps (ABI 1.1) ----------------------------------------------------

// Distance from the light (along its axis) of window depth z in `sm`, and
// back: the window depth of distance d.
inline float shadow_distance(const facet_shadow_map& sm, float z) {
    const float n = sm.near_plane, f = sm.far_plane;
    if (sm.projection == FACET_SHADOW_ORTHOGRAPHIC) return n + z * (f - n);
    return n * f / (f - z * (f - n));
}
// (A perspective map's distances below its near plane, where the formula
// turns back, all give depth 0: nearer than anything the map holds.)
inline float shadow_depth(const facet_shadow_map& sm, float d) {
    const float n = sm.near_plane, f = sm.far_plane;
    if (sm.projection == FACET_SHADOW_ORTHOGRAPHIC) return (d - n) * (1.0f / (f - n));
    d = glm::max(d, n);
    return f * (d - n) / (d * (f - n));
}

// Fraction of a kernel x kernel block of shadow-map texels (percentage-closer
// filtering) around world point `p` that sees the light. The receiver is
// moved toward the light by (bias + slope_bias * tan(theta)) texels, theta
// being the angle between the surface normal and the light (n_dot_l is its
// cosine): a slope-scaled bias, which keeps surfaces from shadowing
// themselves ("acne") at any angle. A tap k texels from the centre sees the
// tilted receiver k * tan(theta) texels deeper, so its bias grows by that
// much too. A tap is lit where the map's depth is at least the tap's depth
// (the comparison is made in window depth, where the map stores it, so a
// tap costs no conversion of the texel). Points outside the map are lit;
// kernel is clamped to 1..15.
inline float shadow_visibility(const facet_shadow_map& sm, glm::vec3 p, float n_dot_l,
                               int kernel, float bias, float slope_bias) {
    const glm::vec4 c = glm::make_mat4(sm.view_projection) * glm::vec4(p, 1.0f);
    if (!(c.w > 0.0f)) return 1.0f;
    const glm::vec3 ndc = glm::vec3(c) / c.w;
    if (ndc.z > 1.0f) return 1.0f;
    const float distance = shadow_distance(sm, glm::max(ndc.z, 0.0f));
    const float texel = sm.projection == FACET_SHADOW_PERSPECTIVE ? sm.texel_size * distance
                                                                  : sm.texel_size;
    const float cos_t = glm::clamp(n_dot_l, 0.1f, 1.0f);
    const float tan_t = glm::sqrt(1.0f - cos_t * cos_t) / cos_t;
    const float receiver = distance - texel * (bias + slope_bias * tan_t);
    // The centre texel, kept within reach of the map (a kernel reaches 7
    // texels) so that it converts to an int; NaN reads as off the map.
    const auto texel_of = [](float t, float size) {
        const float c = t == t ? glm::floor(t * size) : -16.0f;
        return int(glm::clamp(c, -16.0f, size + 16.0f));
    };
    const int cx = texel_of(ndc.x * 0.5f + 0.5f, float(sm.width));
    const int cy = texel_of(0.5f - ndc.y * 0.5f, float(sm.height));
    const int r = std::clamp(kernel, 1, 15) / 2;
    int lit = 0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const int x = cx + dx, y = cy + dy;
            if (x < 0 || y < 0 || x >= int(sm.width) || y >= int(sm.height)) {
                ++lit;
                continue;
            }
            const float tap = receiver - texel * tan_t * glm::sqrt(float(dx * dx + dy * dy));
            lit += shadow_depth(sm, tap) <= sm.depth[size_t(y) * sm.width + size_t(x)];
        }
    return float(lit) / float((2 * r + 1) * (2 * r + 1));
}

#if FACET_SDK_WIDE
// The same for wide::kLanes points at once (fragment_wide), in the same
// arithmetic: each tap's texels gathered, and the depth of each distance
// from the centre worked out once, not per tap.
inline wide::Float shadow_distance(const facet_shadow_map& sm, const wide::Float& z) {
    const float n = sm.near_plane, f = sm.far_plane;
    if (sm.projection == FACET_SHADOW_ORTHOGRAPHIC) return n + z * (f - n);
    return n * f / (f - z * (f - n));
}
inline wide::Float shadow_depth(const facet_shadow_map& sm, const wide::Float& distance) {
    const float n = sm.near_plane, f = sm.far_plane;
    if (sm.projection == FACET_SHADOW_ORTHOGRAPHIC) return (distance - n) * (1.0f / (f - n));
    const wide::Float d = wide::max(distance, wide::splat(n));
    return f * (d - n) / (d * (f - n));
}

// The taps of a (2R + 1)^2 kernel around texels (cx, cy) of a map: how many
// see the light, per lane. A tap off the map counts as lit; Inside says
// that every kernel of a lane in `seen` lies on the map, so that no tap
// needs the test.
namespace detail {
struct Taps {
    const float* map;
    int width, height;
    wide::Mask cx, cy, seen;

    template <int R, bool Inside>
    wide::Mask lit(const wide::Float (&depth)[8][8]) const {
        using namespace wide;
        const Mask centre = cy * width + cx;
        Mask count{};
        for (int dy = -R; dy <= R; ++dy)
            for (int dx = -R; dx <= R; ++dx) {
                const int i = std::max(std::abs(dx), std::abs(dy));
                const int j = std::min(std::abs(dx), std::abs(dy));
                if constexpr (Inside) {
                    const Float stored = gather(map, centre + (dy * width + dx), seen, 0.0f);
                    count -= depth[i][j] <= stored;  // a comparison is 0 or -1
                } else {
                    const Mask x = cx + dx, y = cy + dy;
                    const Mask on_map = seen & (x >= 0) & (y >= 0) & (x < width) & (y < height);
                    const Float stored = gather(map, centre + (dy * width + dx), on_map, 0.0f);
                    count -= !on_map || depth[i][j] <= stored;
                }
            }
        return count;
    }
};
}  // namespace detail

inline wide::Float shadow_visibility(const facet_shadow_map& sm, const wide::Vec3& p,
                                     const wide::Float& n_dot_l, int kernel, float bias,
                                     float slope_bias) {
    using namespace wide;
    const float* m = sm.view_projection;  // column-major, as glm::make_mat4 reads it
    const auto row = [&](int r) {
        return (m[r] * p.x + m[4 + r] * p.y) + (m[8 + r] * p.z + splat(m[12 + r]));
    };
    // An orthographic map's w is 1: no division (x / 1 is x, as in the scalar code).
    const bool ortho = sm.projection == FACET_SHADOW_ORTHOGRAPHIC;
    const Float cw = ortho ? splat(1.0f) : row(3);
    const Float ndc_x = ortho ? row(0) : row(0) / cw, ndc_y = ortho ? row(1) : row(1) / cw,
                ndc_z = ortho ? row(2) : row(2) / cw;
    const Mask seen = cw > 0.0f && !(ndc_z > 1.0f);  // others are lit
    if (!any(seen)) return splat(1.0f);
    const Float distance = shadow_distance(sm, max(ndc_z, splat(0.0f)));
    const Float texel = sm.projection == FACET_SHADOW_PERSPECTIVE ? sm.texel_size * distance
                                                                  : splat(sm.texel_size);
    const Float cos_t = clamp(n_dot_l, 0.1f, 1.0f);
    const Float tan_t = sqrt(1.0f - cos_t * cos_t) / cos_t;
    const Float receiver = distance - texel * (bias + slope_bias * tan_t);
    // The centre texel, kept within reach of the map (a kernel reaches 7
    // texels) so that it converts to an integer; NaN reads as off the map.
    const float w = float(sm.width), h = float(sm.height);
    const auto texel_of = [](const Float& t, float size) {
        const Float c = select(t == t, floor(t * size), splat(-16.0f));
        return __builtin_convertvector(clamp(c, -16.0f, size + 16.0f), Mask);
    };
    const Mask cx = texel_of(ndc_x * 0.5f + 0.5f, w), cy = texel_of(0.5f - ndc_y * 0.5f, h);
    const int r = std::clamp(kernel, 1, 15) / 2;
    // The tap's depth at |dx| = i, |dy| = j, for j <= i.
    Float depth[8][8];
    for (int i = 0; i <= r; ++i)
        for (int j = 0; j <= i; ++j)
            depth[i][j] = shadow_depth(sm, receiver - texel * tan_t *
                                                          std::sqrt(float(i * i + j * j)));
    // Where every lane's kernel lies on the map, no tap needs a bounds test.
    const int width = int(sm.width), height = int(sm.height);
    const Mask inside = !seen || ((cx >= r) & (cy >= r) & (cx < width - r) & (cy < height - r));
    const bool all_inside = bits(inside) == (1u << kLanes) - 1u;
    const detail::Taps taps{sm.depth, width, height, cx, cy, seen};
    Mask lit;
    switch (r) {  // each kernel's loops unrolled
        case 0: lit = all_inside ? taps.lit<0, true>(depth) : taps.lit<0, false>(depth); break;
        case 1: lit = all_inside ? taps.lit<1, true>(depth) : taps.lit<1, false>(depth); break;
        case 2: lit = all_inside ? taps.lit<2, true>(depth) : taps.lit<2, false>(depth); break;
        case 3: lit = all_inside ? taps.lit<3, true>(depth) : taps.lit<3, false>(depth); break;
        case 4: lit = all_inside ? taps.lit<4, true>(depth) : taps.lit<4, false>(depth); break;
        case 5: lit = all_inside ? taps.lit<5, true>(depth) : taps.lit<5, false>(depth); break;
        case 6: lit = all_inside ? taps.lit<6, true>(depth) : taps.lit<6, false>(depth); break;
        default: lit = all_inside ? taps.lit<7, true>(depth) : taps.lit<7, false>(depth); break;
    }
    return select(seen, __builtin_convertvector(lit, Float) / float((2 * r + 1) * (2 * r + 1)),
                  splat(1.0f));
}
#endif

// ---- shadow maps as distances (ABI 1.3) ----------------------------------------

// A light's shadow map as the host gives it (Draw::shadow): the map, and,
// from a host of ABI 1.3, the same map as 16-bit distances from the light
// (facet_shadow_distances), which the filters below read when it is there:
// half the bytes of a float map, read four texels a gather, no conversion per
// tap, and no bounds test (the map's border reads as lit). From a host of
// ABI 1.6 also the planes that bound the distances tile by tile
// (facet_shadow_planes), from which the filters settle most receivers
// without reading a texel.
struct ShadowMap {
    const facet_shadow_map* map = nullptr;
    const facet_shadow_distances* distances = nullptr;  // null: filter `map`
    const facet_shadow_planes* planes = nullptr;        // null: read the taps
    explicit operator bool() const { return map != nullptr; }
};

// A point light's cube map (Draw::cube_shadow, ABI 1.3): six faces of 90
// degrees, +X, -X, +Y, -Y, +Z, -Z of the direction from the light, each
// with its distances.
struct CubeShadow {
    const facet_shadow_map* faces = nullptr;
    const facet_shadow_distances* distances = nullptr;
    glm::vec3 light{0.0f};  // the light's position
    const facet_shadow_planes* planes = nullptr;  // six, or null
    explicit operator bool() const { return faces != nullptr; }
    ShadowMap face(int f) const {
        return {faces + f, distances + f, planes && planes[f].tiles ? planes + f : nullptr};
    }
};

// The face of a cube map that holds direction d: its largest component's
// axis and sign (x before y before z where they are equal).
inline int cube_face(glm::vec3 d) {
    const float ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    if (ax >= ay && ax >= az) return d.x > 0.0f ? 0 : 1;
    if (ay >= az) return d.y > 0.0f ? 2 : 3;
    return d.z > 0.0f ? 4 : 5;
}

namespace detail {
// sqrt(i * i + j * j), the distance in texels of the taps at |dx| = i and
// |dy| = j from a kernel's centre, rounded to float (tests hold the table
// to std::sqrt): constants for the filters below, each of which makes the
// table a local constexpr (a namespace-scope one would be a symbol shared
// by the per-path builds, which facet_isa_objects cannot make local).
struct TapDistances {
    float at[8][8];
    constexpr TapDistances() : at{} {
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j) {
                const double n = double(i * i + j * j);
                double r = n > 1.0 ? n / 2.0 : n;
                for (int k = 0; k < 64 && r > 0.0; ++k) r = 0.5 * (r + n / r);
                at[i][j] = float(r);
            }
    }
};

// A tap is lit where the stored distance is at least its threshold: the
// tap's distance (in the map's units of 1/65535 of near..far) rounded up,
// within 0..65535 (in front of the near plane everything is lit; at or
// past the far plane, and for NaN, only where nothing was drawn).
inline int32_t tap_threshold(float q) {
    if (!(q == q)) return 65535;
    return int32_t(std::ceil(std::clamp(q, 0.0f, 65535.0f)));
}

// The tap's distance q within 0..65535 (65535 for NaN), unrounded: a
// stored distance (a whole number) at least this is at least the tap's
// threshold, and one below it below the threshold, so that bounds on the
// stored distances are compared with it as they are.
inline float tap_bound(float q) { return q == q ? std::clamp(q, 0.0f, 65535.0f) : 65535.0f; }

// The lowest and the highest distance a kernel of radius r <=
// FACET_SHADOW_REACH around texel (cx, cy) can read, from the planes of the
// tile that holds (cx, cy): the planes at (cx, cy), moved apart by the most
// they rise or fall r texels away on each axis, and by a quarter unit more
// than float rounding can move them (the ABI bounds the slopes by 2048
// units a texel and the planes by 2^17, so no sum here reaches 2^18, below
// which each rounding is within 1/64).
static_assert(FACET_SHADOW_TILE == 8, "a texel's tile is its coordinates >> 3");
struct Slab {
    float low, high;
};
inline Slab slab(const facet_shadow_planes& g, int cx, int cy, int r) {
    const float* t = g.tiles + 4 * (ptrdiff_t(cy >> 3) * ptrdiff_t(g.stride) + (cx >> 3));
    const float nearest = t[0] + t[1] * float(cx & 7) + t[2] * float(cy & 7);
    const float spread = (std::abs(t[1]) + std::abs(t[2])) * float(r);
    return {nearest - spread - 0.25f, nearest + t[3] + spread + 0.25f};
}
}  // namespace detail

// Percentage-closer filtering as shadow_visibility(facet_shadow_map) does,
// over a map's distances (ABI 1.3) when the host gives them, else over its
// window depths. In distance units the receiver and its taps are straight
// lines in the bias, so each class of tap (by its distance from the centre)
// costs one subtraction, and a perspective map's point needs one division.
// A point whose centre texel is off the map is lit; taps past the map's edge
// read its border, which is lit.
inline float shadow_visibility(const ShadowMap& m, glm::vec3 p, float n_dot_l, int kernel,
                               float bias, float slope_bias) {
    if (!m.distances) return shadow_visibility(*m.map, p, n_dot_l, kernel, bias, slope_bias);
    const facet_shadow_map& sm = *m.map;
    const float* v = sm.view_projection;  // column-major
    const auto row = [&](int r) {
        return (v[r] * p.x + v[4 + r] * p.y) + (v[8 + r] * p.z + v[12 + r]);
    };
    const float scale = 65535.0f / (sm.far_plane - sm.near_plane);
    float x = row(0), y = row(1), q, texel;  // texel: a texel's world size, in map units
    if (sm.projection == FACET_SHADOW_ORTHOGRAPHIC) {
        q = row(2) * 65535.0f;  // window depth is the distance, 0..1
        texel = sm.texel_size * scale;
    } else {
        const float w = row(3);  // the distance along the light's axis
        if (!(w > 0.0f)) return 1.0f;
        const float inv_w = 1.0f / w;
        x = x * inv_w;
        y = y * inv_w;
        q = (w - sm.near_plane) * scale;
        texel = (sm.texel_size * scale) * w;
    }
    if (!(q <= 65535.0f)) return 1.0f;  // past the far plane
    const float fx = std::floor((x * 0.5f + 0.5f) * float(sm.width));
    const float fy = std::floor((0.5f - y * 0.5f) * float(sm.height));
    if (!(fx >= 0.0f && fx < float(sm.width) && fy >= 0.0f && fy < float(sm.height))) return 1.0f;
    const float cos_t = glm::clamp(n_dot_l, 0.1f, 1.0f);
    const float tan_t = std::sqrt(1.0f - cos_t * cos_t) / cos_t;
    const float receiver = q - texel * (bias + slope_bias * tan_t);
    const float step = texel * tan_t;  // a tap k texels away sees the receiver k * step deeper
    const int r = std::clamp(kernel, 1, 15) / 2;
    constexpr detail::TapDistances kTaps{};
    if (m.planes && r <= FACET_SHADOW_REACH) {
        // The centre's threshold is the highest and the corners' the lowest:
        // at or above the one every tap is lit; below the other, none is.
        const detail::Slab s = detail::slab(*m.planes, int(fx), int(fy), r);
        if (s.low >= detail::tap_bound(receiver - step * kTaps.at[0][0])) return 1.0f;
        if (s.high < detail::tap_bound(receiver - step * kTaps.at[r][r])) return 0.0f;
    }
    const ptrdiff_t stride = m.distances->stride;
    const uint16_t* centre = m.distances->texels + ptrdiff_t(fy) * stride + ptrdiff_t(fx);
    int lit = 0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const int i = std::max(std::abs(dx), std::abs(dy));
            const int j = std::min(std::abs(dx), std::abs(dy));
            const int32_t threshold = detail::tap_threshold(receiver - step * kTaps.at[i][j]);
            lit += int32_t(centre[dy * stride + dx]) >= threshold;
        }
    return float(lit) / float((2 * r + 1) * (2 * r + 1));
}

// The same over a point light's cube map: the face that holds the
// direction from the light to p.
inline float shadow_visibility(const CubeShadow& c, glm::vec3 p, float n_dot_l, int kernel,
                               float bias, float slope_bias) {
    return shadow_visibility(c.face(cube_face(p - c.light)), p, n_dot_l, kernel, bias,
                             slope_bias);
}

#if FACET_SDK_WIDE
namespace detail {
// tap_threshold for each lane.
inline wide::Mask tap_threshold(const wide::Float& q) {
    using namespace wide;
    const Float c = clamp(q, 0.0f, 65535.0f);
#if defined(__AVX__)
    const Float up = ceil(c);
#else
    // No rounding instruction before SSE4.1: the ceiling of a float in
    // 0..65535 is its truncation, plus one where that fell below it.
    const Float t = __builtin_convertvector(__builtin_convertvector(c, Mask), Float);
    const Float up = select(t < c, t + 1.0f, t);
#endif
    return __builtin_convertvector(select(q == q, up, splat(65535.0f)), Mask);
}

// tap_bound for each lane.
inline wide::Float tap_bound(const wide::Float& q) {
    using namespace wide;
    return select(q == q, clamp(q, 0.0f, 65535.0f), splat(65535.0f));
}

// kTaps.at[r][r] of TapDistances, sqrt(2 r^2), for r in 0..7: a constant
// for each r (the whole table, a local, would be stored on the stack at
// every call).
inline float diagonal_tap(int r) {
    constexpr TapDistances kTaps{};
    switch (r) {
        case 0: return kTaps.at[0][0];
        case 1: return kTaps.at[1][1];
        case 2: return kTaps.at[2][2];
        case 3: return kTaps.at[3][3];
        case 4: return kTaps.at[4][4];
        case 5: return kTaps.at[5][5];
        case 6: return kTaps.at[6][6];
        default: return kTaps.at[7][7];
    }
}

// Four 16-bit values in each 64-bit lane, half a call's lanes at a time:
// half 0 holds lanes 0, 1, 4, 5, 8, 9, ... and half 1 lanes 2, 3, 6, 7, ...,
// the order in which x86 interleaves two registers within each 128 bits, so
// that moving lanes between the layouts costs one instruction.
using Quad16 = uint16_t __attribute__((vector_size(4 * wide::kLanes)));
using QuadCounts = int16_t __attribute__((vector_size(4 * wide::kLanes)));

// The lanes of `half` of (lo, hi) as 64-bit lanes lo | hi << 32.
inline wide::Quads interleave(const wide::Mask& lo, const wide::Mask& hi, int half) {
    using wide::Mask;
#if FACET_WIDE_LANES == 16
    const Mask v = half ? __builtin_shufflevector(lo, hi, 2, 18, 3, 19, 6, 22, 7, 23, 10, 26, 11,
                                                  27, 14, 30, 15, 31)
                        : __builtin_shufflevector(lo, hi, 0, 16, 1, 17, 4, 20, 5, 21, 8, 24, 9,
                                                  25, 12, 28, 13, 29);
#elif FACET_WIDE_LANES == 8
    const Mask v = half ? __builtin_shufflevector(lo, hi, 2, 10, 3, 11, 6, 14, 7, 15)
                        : __builtin_shufflevector(lo, hi, 0, 8, 1, 9, 4, 12, 5, 13);
#else
    const Mask v = half ? __builtin_shufflevector(lo, hi, 2, 6, 3, 7)
                        : __builtin_shufflevector(lo, hi, 0, 4, 1, 5);
#endif
    return std::bit_cast<wide::Quads>(v);
}

// The lanes of `half` of v.
inline wide::HalfIndex half_lanes(const wide::Mask& v, int half) {
#if FACET_WIDE_LANES == 16
    return half ? __builtin_shufflevector(v, v, 2, 3, 6, 7, 10, 11, 14, 15)
                : __builtin_shufflevector(v, v, 0, 1, 4, 5, 8, 9, 12, 13);
#elif FACET_WIDE_LANES == 8
    return half ? __builtin_shufflevector(v, v, 2, 3, 6, 7)
                : __builtin_shufflevector(v, v, 0, 1, 4, 5);
#else
    return half ? __builtin_shufflevector(v, v, 2, 3) : __builtin_shufflevector(v, v, 0, 1);
#endif
}

// Back: the low 32 bits of each 64-bit lane of the two halves, in lane order.
inline wide::Mask join_halves(const wide::Quads& a, const wide::Quads& b) {
    using wide::Mask;
    const Mask x = std::bit_cast<Mask>(a), y = std::bit_cast<Mask>(b);
#if FACET_WIDE_LANES == 16
    return __builtin_shufflevector(x, y, 0, 2, 16, 18, 4, 6, 20, 22, 8, 10, 24, 26, 12, 14, 28, 30);
#elif FACET_WIDE_LANES == 8
    return __builtin_shufflevector(x, y, 0, 2, 8, 10, 4, 6, 12, 14);
#else
    return __builtin_shufflevector(x, y, 0, 2, 4, 6);
#endif
}

// How many taps of a (2R + 1)^2 kernel around each lane's centre texel are
// lit, with `receiver` the centre tap's distance and `step` how much
// deeper each texel further out sees it. A row is read four texels at a time
// from the kernel's first column, so one gather element brings up to four
// taps and one comparison of 16-bit quarters tests them; the texels past
// the kernel get threshold 0, always lit, and are taken off at the end.
template <int R>
inline wide::Mask lit_distances(const facet_shadow_distances& d, const wide::Mask& cx,
                                const wide::Mask& cy, const wide::Float& receiver,
                                const wide::Float& step) {
    using namespace wide;
    constexpr int kQuads = (2 * R + 1 + 3) / 4;  // per row
    constexpr int kExtra = 4 * kQuads - (2 * R + 1);
    constexpr TapDistances kTaps{};
    Mask threshold[R + 1][R + 1];
#pragma GCC unroll 16
    for (int i = 0; i <= R; ++i)
#pragma GCC unroll 16
        for (int j = 0; j <= i; ++j)
            threshold[i][j] = tap_threshold(receiver - step * kTaps.at[i][j]);
    const auto tap = [&](int dx, int ay) {
        const int ax = dx < 0 ? -dx : dx;
        return ax > R ? Mask{} : threshold[std::max(ax, ay)][std::min(ax, ay)];
    };
    // Thresholds of quad k of a row |dy| = ay away, for each half of the lanes.
    Quad16 packed[R + 1][kQuads][2];
#pragma GCC unroll 16
    for (int ay = 0; ay <= R; ++ay)
#pragma GCC unroll 16
        for (int k = 0; k < kQuads; ++k) {
            const int dx = 4 * k - R;
            const Mask lo = tap(dx, ay) | tap(dx + 1, ay) << 16;
            const Mask hi = tap(dx + 2, ay) | tap(dx + 3, ay) << 16;
            for (int h = 0; h < 2; ++h)
                packed[ay][k][h] = std::bit_cast<Quad16>(interleave(lo, hi, h));
        }
    const int stride = int(d.stride);
    const Mask first = cy * stride + (cx - R);  // the kernel's first texel in its middle row
    const HalfIndex start[2] = {half_lanes(first, 0), half_lanes(first, 1)};
    QuadCounts count[2] = {};
#pragma GCC unroll 16
    for (int dy = -R; dy <= R; ++dy)
#pragma GCC unroll 16
        for (int k = 0; k < kQuads; ++k)
            for (int h = 0; h < 2; ++h) {
                const Quad16 texels = std::bit_cast<Quad16>(
                    gather_quads(d.texels, start[h] + (dy * stride + 4 * k)));
                count[h] -= texels >= packed[dy < 0 ? -dy : dy][k][h];  // 0 or -1
            }
    // Each 64-bit lane's four counts, added: 16-bit pairs, then 32-bit pairs.
    Quads sum[2];
    for (int h = 0; h < 2; ++h) {
        const Mask c = std::bit_cast<Mask>(count[h]);
        const Mask pairs = (c & 0xFFFF) + ((c >> 16) & 0xFFFF);
        sum[h] = std::bit_cast<Quads>(pairs) + (std::bit_cast<Quads>(pairs) >> 32);
    }
    return join_halves(sum[0], sum[1]) - kExtra * (2 * R + 1);
}

// slab for each lane: the same operations as the scalar one (plugins are
// built with -ffp-contract=off, so neither fuses a multiply and an add),
// and either way within the margin: it settles only receivers that every
// tap or no tap of the kernel lights.
struct WideSlab {
    wide::Float low, high;
};
inline WideSlab slab(const facet_shadow_planes& g, const wide::Mask& cx, const wide::Mask& cy,
                     int r) {
    using namespace wide;
    Float tile[4];
    gather4(g.tiles, 4 * ((cy >> 3) * int(g.stride) + (cx >> 3)), tile);
    const Float nearest0 = tile[0], dx = tile[1], dy = tile[2], depth = tile[3];
    const Float nearest = nearest0 + dx * __builtin_convertvector(cx & 7, Float) +
                          dy * __builtin_convertvector(cy & 7, Float);
    const Float spread = (abs(dx) + abs(dy)) * float(r);
    return {nearest - spread - 0.25f, nearest + depth + spread + 0.25f};
}

// The share of the (2r + 1)^2 taps around each lane's texel (cx, cy) that
// are lit, for the receivers the planes did not settle: out of line, so that
// the calls the planes settle need no stack frame for it.
[[gnu::noinline]] inline wide::Float filter_distances(const facet_shadow_distances& d, int r,
                                                      wide::Mask cx, wide::Mask cy,
                                                      wide::Float receiver, wide::Float step) {
    using namespace wide;
    Mask lit;
    switch (r) {  // each kernel's loops unrolled
        case 0: lit = lit_distances<0>(d, cx, cy, receiver, step); break;
        case 1: lit = lit_distances<1>(d, cx, cy, receiver, step); break;
        case 2: lit = lit_distances<2>(d, cx, cy, receiver, step); break;
        case 3: lit = lit_distances<3>(d, cx, cy, receiver, step); break;
        case 4: lit = lit_distances<4>(d, cx, cy, receiver, step); break;
        case 5: lit = lit_distances<5>(d, cx, cy, receiver, step); break;
        case 6: lit = lit_distances<6>(d, cx, cy, receiver, step); break;
        default: lit = lit_distances<7>(d, cx, cy, receiver, step); break;
    }
    return __builtin_convertvector(lit, Float) / float((2 * r + 1) * (2 * r + 1));
}
}  // namespace detail

[[gnu::always_inline]] inline wide::Float shadow_visibility(const ShadowMap& m,
                                                            const wide::Vec3& p,
                                                            const wide::Float& n_dot_l, int kernel,
                                                            float bias, float slope_bias) {
    using namespace wide;
    if (!m.distances) return shadow_visibility(*m.map, p, n_dot_l, kernel, bias, slope_bias);
    const facet_shadow_map& sm = *m.map;
    const float* v = sm.view_projection;  // column-major
    const auto row = [&](int r) {
        return (v[r] * p.x + v[4 + r] * p.y) + (v[8 + r] * p.z + splat(v[12 + r]));
    };
    const float scale = 65535.0f / (sm.far_plane - sm.near_plane);
    Float x = row(0), y = row(1), q, texel;
    Mask seen;
    if (sm.projection == FACET_SHADOW_ORTHOGRAPHIC) {
        q = row(2) * 65535.0f;
        texel = splat(sm.texel_size * scale);
        seen = q <= 65535.0f;
    } else {
        const Float w = row(3);
        const Float inv_w = 1.0f / w;
        x = x * inv_w;
        y = y * inv_w;
        q = (w - sm.near_plane) * scale;
        texel = (sm.texel_size * scale) * w;
        seen = w > 0.0f && q <= 65535.0f;
    }
    // The texel (cx, cy) is the scalar filter's (floor(tx), floor(ty)): on the
    // map tx and ty are at least 0, where truncation is the floor.
    const float width = float(sm.width), height = float(sm.height);
    const Float tx = (x * 0.5f + 0.5f) * width, ty = (0.5f - y * 0.5f) * height;
    seen &= tx >= 0.0f && tx < width && ty >= 0.0f && ty < height;  // false for NaN
    if (!any(seen)) return splat(1.0f);
    // Lanes off the map read around texel (0, 0), inside the border.
    const Mask cx = __builtin_convertvector(select(seen, tx, splat(0.0f)), Mask);
    const Mask cy = __builtin_convertvector(select(seen, ty, splat(0.0f)), Mask);
    const Float cos_t = clamp(n_dot_l, 0.1f, 1.0f);
    const Float tan_t = sqrt(1.0f - cos_t * cos_t) / cos_t;
    const Float receiver = q - texel * (bias + slope_bias * tan_t);
    const Float step = texel * tan_t;
    const int r = std::clamp(kernel, 1, 15) / 2;
    if (m.planes && r <= FACET_SHADOW_REACH) {  // as the scalar filter does, lane by lane
        const detail::WideSlab s = detail::slab(*m.planes, cx, cy, r);
        const Float centre = detail::tap_bound(receiver - step * 0.0f);
        const Float corner = detail::tap_bound(receiver - step * detail::diagonal_tap(r));
        const Mask all_lit = s.low >= centre;
        const Mask none_lit = s.high < corner;
        if (!any(seen & !(all_lit | none_lit)))
            return select(seen & none_lit, splat(0.0f), splat(1.0f));
    }
    return select(seen, detail::filter_distances(*m.distances, r, cx, cy, receiver, step),
                  splat(1.0f));
}
#endif

#if FACET_SDK_WIDE
// The same over a point light's cube map, each lane from the face that holds
// the direction from the light to its point: every face some lane needs is
// filtered, for those lanes.
inline wide::Float shadow_visibility(const CubeShadow& c, const wide::Vec3& p,
                                     const wide::Float& n_dot_l, int kernel, float bias,
                                     float slope_bias) {
    using namespace wide;
    const Vec3 d = p - Vec3(c.light);
    const Float ax = abs(d.x), ay = abs(d.y), az = abs(d.z);
    const Mask x = ax >= ay && ax >= az, y = !x && ay >= az;
    const Mask face = select(x, select(d.x > 0.0f, Mask{}, Mask{} + 1),
                             select(y, select(d.y > 0.0f, Mask{} + 2, Mask{} + 3),
                                    select(d.z > 0.0f, Mask{} + 4, Mask{} + 5)));
    Float visible = splat(1.0f);
    for (int f = 0; f < 6; ++f) {
        const Mask here = face == f;
        if (!any(here)) continue;
        visible = select(here, shadow_visibility(c.face(f), p, n_dot_l, kernel, bias, slope_bias),
                         visible);
    }
    return visible;
}
#endif

// ---- what a shader function sees -------------------------------------------

struct VertexIn {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};  // when not asked for: +Z
    glm::vec2 uv{0.0f};                  // when not asked for: 0
    glm::vec4 color{1.0f};               // when not asked for: white
    glm::vec4 tangent{0.0f};             // when not asked for, or the mesh has none: 0
};

// A thin view of facet_draw: accessors build GLM values on demand.
struct Draw {
    const facet_draw* raw;
    glm::mat4 model() const { return glm::make_mat4(raw->model); }
    glm::mat4 view() const { return glm::make_mat4(raw->view); }
    glm::mat4 projection() const { return glm::make_mat4(raw->projection); }
    glm::mat4 view_projection() const { return glm::make_mat4(raw->view_projection); }
    glm::mat4 model_view_projection() const { return glm::make_mat4(raw->model_view_projection); }
    glm::mat3 normal_matrix() const { return glm::mat3(glm::make_mat4(raw->normal_matrix)); }
    glm::vec3 camera_position() const { return glm::make_vec3(raw->camera_position); }
    uint32_t light_count() const { return raw->light_count; }
    const facet_light& light(uint32_t i) const { return raw->lights[i]; }
    // The shadow map of light `i`, or nullptr if it casts none (ABI 1.1).
    const facet_shadow_map* shadow_map(uint32_t i) const {
        if (raw->host->abi_minor < 1) return nullptr;
        for (uint32_t k = 0; k < raw->shadow_map_count; ++k)
            if (raw->shadow_maps[k].light == i) return &raw->shadow_maps[k];
        return nullptr;
    }
    // The same with its distances (ABI 1.3), for shadow_visibility; false
    // if light `i` casts no shadow.
    ShadowMap shadow(uint32_t i) const {
        const facet_shadow_map* map = shadow_map(i);
        if (!map || raw->host->abi_minor < 3 || !raw->shadow_distances) return {map, nullptr};
        const ptrdiff_t k = map - raw->shadow_maps;
        const facet_shadow_planes* planes = raw->host->abi_minor >= 6 && raw->shadow_planes &&
                                                    raw->shadow_planes[k].tiles
                                                ? &raw->shadow_planes[k]
                                                : nullptr;
        return {map, &raw->shadow_distances[k], planes};
    }
    // The cube map of point light `i`, or false if it casts none (ABI 1.3).
    CubeShadow cube_shadow(uint32_t i) const {
        if (raw->host->abi_minor < 3 || !raw->cube_shadow_distances) return {};
        for (uint32_t k = 0; k < raw->cube_shadow_map_count; ++k)
            if (raw->cube_shadow_maps[6 * k].light == i)
                return {raw->cube_shadow_maps + 6 * k, raw->cube_shadow_distances + 6 * k,
                        glm::make_vec3(raw->lights[i].position),
                        raw->host->abi_minor >= 6 && raw->cube_shadow_planes
                            ? raw->cube_shadow_planes + 6 * k
                            : nullptr};
        return {};
    }
    // Whether light `i` has a shadow map or a cube this draw can filter.
    bool has_shadow(uint32_t i) const { return bool(shadow(i)) || bool(cube_shadow(i)); }
};

// Built-ins of one fragment.
struct Fragment {
    glm::vec2 coord;     // pixel centre, window coordinates
    float depth;         // window depth, 0..1
    bool front_facing;
    float ao;            // ambient visibility (1 when no AO was asked for)
    bool discarded = false;

    // Texel of texture parameter `slot` (k-th TEXTURE parameter), sampled by
    // the host at this fragment; white when the material binds none or the
    // shader declares no such slot.
    glm::vec4 texture(int slot) const {
        if (!texels_ || slot < 0 || slot >= texture_count_) return glm::vec4(1.0f);
        const float* t = texels_ + slot * 4 * FACET_BLOCK_LANES + lane_;
        return {t[0], t[FACET_BLOCK_LANES], t[2 * FACET_BLOCK_LANES], t[3 * FACET_BLOCK_LANES]};
    }
    void discard() { discarded = true; }

    const float* texels_ = nullptr;
    int texture_count_ = 0;
    int lane_ = 0;
};

#if FACET_SDK_WIDE
// Built-ins of wide::kLanes fragments of a block (fragment_wide).
struct WideFragment {
    wide::Vec2 coord;    // pixel centres, window coordinates
    wide::Float depth;   // window depth, 0..1
    bool front_facing;   // the same for every lane: one triangle
    wide::Float ao;      // ambient visibility (1 when no AO was asked for)
    wide::Mask discarded{};

    // Texels of texture parameter `slot` at every lane; white when the
    // material binds none or the shader declares no such slot.
    wide::Vec4 texture(int slot) const {
        if (!texels_ || slot < 0 || slot >= texture_count_) return wide::Vec4(glm::vec4(1.0f));
        const float* t = texels_ + slot * 4 * FACET_BLOCK_LANES;
        wide::Vec4 c;
        std::memcpy(&c.x, t, sizeof c.x);
        std::memcpy(&c.y, t + FACET_BLOCK_LANES, sizeof c.y);
        std::memcpy(&c.z, t + 2 * FACET_BLOCK_LANES, sizeof c.z);
        std::memcpy(&c.w, t + 3 * FACET_BLOCK_LANES, sizeof c.w);
        return c;
    }
    // Discards the lanes set in `m`.
    void discard(const wide::Mask& m) { discarded |= m; }

    const float* texels_ = nullptr;  // at this call's first lane
    int texture_count_ = 0;
};

inline wide::Vec3 rgb(const wide::Vec4& v) { return {v.x, v.y, v.z}; }
#endif

// ---- what a surface receives: shadows and ambient occlusion (ABI 1.3) ----------

// The parameters with which a material receives the host's shadow maps and
// AO. A shader that lights surfaces embeds one in its Params, adds its five
// parameters to its schema with with_receiving(), and asks for
// FACET_NEED_SHADOW_MAP and FACET_NEED_AO; then light_visibility() and
// ambient_visibility() give what its lighting multiplies by. The host draws
// shadow maps only for visible materials with receive_shadows on, and runs
// AO only for those with ambient_occlusion above 0.
struct Receiving {
    int32_t shadows;   // receive_shadows: filter the lights' shadow maps (bool)
    int32_t kernel;    // shadow_kernel: PCF width in texels, odd
    float bias;        // shadow_bias: constant bias, texels
    float slope_bias;  // shadow_slope_bias: bias per unit of tan(angle to the light)
    float ao;          // ambient_occlusion: ambient light times AO^this (0: none)
};

// The ambient_occlusion parameter alone, a float at byte `offset`: for a
// shader without lights, which receives AO but no shadows.
constexpr facet_param_desc ambient_occlusion(size_t offset) {
    facet_param_desc p = float1("ambient_occlusion", offset, 0.0f, 0.0f, 8.0f,
                                "colour times AO to this power; 0: no AO");
    p.flags = FACET_PARAM_USES_AO;
    return p;
}

// A cutout (ABI 1.4): fragments whose alpha is below the float at byte
// `offset` are discarded, so that a texture's alpha cuts a shape out of a
// quad (foliage, fences). 0, the default, discards nothing, and the host
// then draws the material as fast as one that cannot discard. A shader
// with it asks for FACET_NEED_DISCARD and calls cut_out() on its colour.
constexpr facet_param_desc alpha_cutoff(size_t offset) {
    facet_param_desc p = float1("alpha_cutoff", offset, 0.0f, 0.0f, 1.0f,
                                "discard fragments with alpha below this; 0: none");
    p.flags = FACET_PARAM_USES_DISCARD;
    return p;
}
// Discards the fragment when `alpha` is below `cutoff`.
inline void cut_out(Fragment& f, float alpha, float cutoff) {
    if (alpha < cutoff) f.discard();
}
#if FACET_SDK_WIDE
inline void cut_out(WideFragment& f, const wide::Float& alpha, float cutoff) {
    if (cutoff > 0.0f) f.discard(alpha < cutoff);
}
#endif

// `own` followed by the five parameters of the Receiving at byte `offset`
// of the parameter block.
template <size_t N>
constexpr std::array<facet_param_desc, N + 5> with_receiving(
    const std::array<facet_param_desc, N>& own, size_t offset) {
    std::array<facet_param_desc, N + 5> all{};
    for (size_t i = 0; i < N; ++i) all[i] = own[i];
    all[N] = boolean("receive_shadows", offset + offsetof(Receiving, shadows), true,
                     "filter the shadow maps of the lights that cast shadows");
    all[N].flags = FACET_PARAM_USES_SHADOWS;
    all[N + 1] = int1("shadow_kernel", offset + offsetof(Receiving, kernel), 3, 1, 15,
                      "percentage-closer filter width in texels (odd)");
    all[N + 2] = float1("shadow_bias", offset + offsetof(Receiving, bias), 1.0f, 0.0f, 64.0f,
                        "constant shadow bias, texels");
    all[N + 3] = float1("shadow_slope_bias", offset + offsetof(Receiving, slope_bias), 1.5f,
                        0.0f, 64.0f, "shadow bias per unit of tan(angle to the light), texels");
    all[N + 4] = float1("ambient_occlusion", offset + offsetof(Receiving, ao), 0.0f, 0.0f, 8.0f,
                        "ambient light times AO to this power; 0: no AO");
    all[N + 4].flags = FACET_PARAM_USES_AO;
    return all;
}

// What reaches p of light `i`: 1, or the share its shadow map lets
// through (shadow_visibility with the material's filter), n_dot_l being the
// cosine between the normal and the direction to the light.
inline float light_visibility(const Draw& d, uint32_t i, const Receiving& r, glm::vec3 p,
                              float n_dot_l) {
    if (!r.shadows) return 1.0f;
    if (const ShadowMap m = d.shadow(i))
        return shadow_visibility(m, p, n_dot_l, r.kernel, r.bias, r.slope_bias);
    if (const CubeShadow c = d.cube_shadow(i))
        return shadow_visibility(c, p, n_dot_l, r.kernel, r.bias, r.slope_bias);
    return 1.0f;
}

// Whether light visibility can be other than 1 in this draw: the material
// receives shadows and some light has a map.
inline bool receives_shadows(const Draw& d, const Receiving& r) {
    if (!r.shadows || d.raw->host->abi_minor < 1) return false;
    return d.raw->shadow_map_count > 0 ||
           (d.raw->host->abi_minor >= 3 && d.raw->cube_shadow_map_count > 0);
}

// Whether a draw's lighting can be darkened at all, by a shadow map or by
// AO. A wide fragment function branches on it once per call to a version
// with neither, so a draw that receives nothing pays little for the
// services (phong, toon and lit were 2-9% slower without the branch; with
// it, 1-4% on scenes without shadows and AO, which the branch and the
// larger loop cost).
inline bool receives(const Draw& d, const Receiving& r) {
    return receives_shadows(d, r) || r.ao > 0.0f;
}

// What the ambient term is multiplied by: AO^strength, or 1.
inline float ambient_visibility(const Fragment& f, float strength) {
    return strength > 0.0f ? std::pow(f.ao, strength) : 1.0f;
}
inline float ambient_visibility(const Fragment& f, const Receiving& r) {
    return ambient_visibility(f, r.ao);
}

#if FACET_SDK_WIDE
[[gnu::always_inline]] inline wide::Float light_visibility(const Draw& d, uint32_t i,
                                                           const Receiving& r, const wide::Vec3& p,
                                                           const wide::Float& n_dot_l) {
    if (!r.shadows) return wide::splat(1.0f);
    if (const ShadowMap m = d.shadow(i))
        return shadow_visibility(m, p, n_dot_l, r.kernel, r.bias, r.slope_bias);
    if (const CubeShadow c = d.cube_shadow(i))
        return shadow_visibility(c, p, n_dot_l, r.kernel, r.bias, r.slope_bias);
    return wide::splat(1.0f);
}

inline wide::Float ambient_visibility(const WideFragment& f, float strength) {
    return strength > 0.0f ? wide::pow(f.ao, strength) : wide::splat(1.0f);
}
inline wide::Float ambient_visibility(const WideFragment& f, const Receiving& r) {
    return ambient_visibility(f, r.ao);
}
#endif

// ---- normal maps (ABI 1.5: tangents) -------------------------------------------

// A normal map is a texture parameter without FACET_PARAM_SRGB whose RGB
// holds a tangent-space normal as n * 0.5 + 0.5, in the OpenGL and glTF
// convention: X along the tangent (+u), Y towards the texture's top row, Z
// out of the surface. A shader that reads one asks for FACET_NEED_TANGENTS,
// passes world_tangent() of VertexIn::tangent to its fragments as a
// 4-component varying, and shades with normal_mapped().

// The two parameters of a normal map: the texture, sampled at the UV of
// varying `uv_varying`, and the scale of its X and Y.
constexpr facet_param_desc normal_texture(size_t offset, int uv_varying) {
    return texture("normal_texture", offset, uv_varying, false,
                   "tangent-space normal map (linear; +Y towards the texture's top)");
}
constexpr facet_param_desc normal_scale(size_t offset) {
    return float1("normal_scale", offset, 1.0f, -16.0f, 16.0f, "scales the normal map's X and Y");
}

// Tangent t (object space, w the handedness) in world space: xyz by the
// model matrix, and w turned around where the model mirrors, so that the
// bitangent cross(n, xyz) * w keeps pointing at the texture's top.
inline glm::vec4 world_tangent(const Draw& d, const glm::vec4& t) {
    const glm::mat3 m(d.model());
    const glm::vec3 xyz = m * glm::vec3(t);
    const float length = glm::length(xyz);
    const float w = glm::determinant(m) < 0.0f ? -t.w : t.w;
    return {length > 0.0f ? xyz / length : xyz, w};
}

// The unit normal a normal map's texel gives, its X and Y times `scale`
// (glTF's normalTexture.scale), in the frame of unit normal n and the
// interpolated world tangent t (not unit, nor perpendicular to n: both are
// mended here). Where t has nothing left across n (a mesh without
// tangents, or a vertex without UVs, gets a zero tangent), n.
inline glm::vec3 normal_mapped(const glm::vec3& n, const glm::vec4& t, const glm::vec4& texel,
                               float scale) {
    const glm::vec3 m((texel.x * 2.0f - 1.0f) * scale, (texel.y * 2.0f - 1.0f) * scale,
                      texel.z * 2.0f - 1.0f);
    glm::vec3 tangent = glm::vec3(t) - n * glm::dot(n, glm::vec3(t));
    const float t2 = glm::dot(tangent, tangent);
    if (!(t2 > 1e-12f)) return n;
    tangent *= 1.0f / std::sqrt(t2);
    const glm::vec3 bitangent = glm::cross(n, tangent) * (t.w < 0.0f ? -1.0f : 1.0f);
    const glm::vec3 r = tangent * m.x + bitangent * m.y + n * m.z;
    const float r2 = glm::dot(r, r);
    return r2 > 1e-12f ? r * (1.0f / std::sqrt(r2)) : n;
}

#if FACET_SDK_WIDE
inline wide::Vec3 normal_mapped(const wide::Vec3& n, const wide::Vec4& t, const wide::Vec4& texel,
                                float scale) {
    using namespace wide;
    const Vec3 m((texel.x * 2.0f - 1.0f) * scale, (texel.y * 2.0f - 1.0f) * scale,
                 texel.z * 2.0f - 1.0f);
    const Vec3 t3(t.x, t.y, t.z);
    Vec3 tangent = t3 - n * dot(n, t3);
    const Float t2 = dot(tangent, tangent);
    const Mask framed = t2 > 1e-12f;
    tangent = tangent * (1.0f / sqrt(select(framed, t2, splat(1.0f))));
    const Vec3 bitangent = cross(n, tangent) * select(t.w < 0.0f, splat(-1.0f), splat(1.0f));
    const Vec3 r = tangent * m.x + bitangent * m.y + n * m.z;
    const Float r2 = dot(r, r);
    const Mask ok = framed && r2 > 1e-12f;
    return select(ok, r * (1.0f / sqrt(select(ok, r2, splat(1.0f)))), n);
}
#endif

// ---- generated glue ----------------------------------------------------------

namespace detail {

template <class S>
constexpr bool has_varyings() {
    return !std::is_empty_v<typename S::Varyings>;
}

template <class S>
constexpr uint32_t varying_floats() {
    uint32_t n = 0;
    if constexpr (has_varyings<S>())
        for (const facet_varying_desc& v : S::varyings) n += v.components;
    return n;
}

template <class S>
constexpr uint32_t varying_count() {
    if constexpr (has_varyings<S>()) return sizeof(S::varyings) / sizeof(S::varyings[0]);
    return 0;
}

template <class S>
constexpr uint32_t param_count() {
    if constexpr (std::is_empty_v<typename S::Params>) return 0;
    else return uint32_t(std::size(S::params));
}

template <class S>
constexpr int texture_count() {
    int n = 0;
    if constexpr (!std::is_empty_v<typename S::Params>)
        for (const facet_param_desc& p : S::params) n += p.type == FACET_PARAM_TEXTURE;
    return n;
}

template <class S>
constexpr uint32_t conditional_varyings() {
    if constexpr (requires { S::conditional_varyings; }) return S::conditional_varyings;
    return 0;
}

constexpr bool same_text(const char* a, const char* b) {
    for (; *a && *a == *b; ++a, ++b) {}
    return *a == *b;
}

// The index of the parameter S::varyings_condition names.
template <class S>
constexpr uint32_t varyings_condition() {
    if constexpr (requires { S::varyings_condition; }) {
        for (uint32_t i = 0; i < uint32_t(std::size(S::params)); ++i)
            if (same_text(S::params[i].name, S::varyings_condition)) return i;
        throw "varyings_condition names no parameter";  // a compile error in a constant
    }
    return 0;
}

// The varying floats a draw with `params` reads: all, or those before the
// conditional varyings when their condition is 0 (the host leaves those
// uninterpolated).
template <class S>
uint32_t read_floats(const typename S::Params& params) {
    constexpr uint32_t all = varying_floats<S>();
    if constexpr (conditional_varyings<S>() == 0) {
        return all;
    } else {
        constexpr uint32_t unconditional = [] {
            uint32_t n = 0;
            for (uint32_t v = 0; v < varying_count<S>() - conditional_varyings<S>(); ++v)
                n += S::varyings[v].components;
            return n;
        }();
        int32_t condition;  // a TEXTURE or BOOL: an int32
        std::memcpy(&condition,
                    reinterpret_cast<const unsigned char*>(&params) +
                        S::params[varyings_condition<S>()].offset,
                    sizeof condition);
        return condition ? all : unconditional;
    }
}

template <class S>
void vertex_batch(const facet_draw* draw, const facet_vertex_batch* b) {
    using V = typename S::Varyings;
    const Draw d{draw};
    const auto& params = *static_cast<const typename S::Params*>(draw->params);
    for (uint32_t i = 0; i < b->count; ++i) {
        VertexIn in;
        in.position = glm::make_vec3(b->position + 3 * i);
        if (b->normal) in.normal = glm::make_vec3(b->normal + 3 * i);
        if (b->uv) in.uv = glm::make_vec2(b->uv + 2 * i);
        if (b->color) in.color = glm::make_vec4(b->color + 4 * i);
        if (b->tangent) in.tangent = glm::make_vec4(b->tangent + 4 * i);
        glm::vec4 clip(0.0f);
        const V out = S::vertex(in, d, params, clip);
        std::memcpy(b->clip_position + 4 * i, &clip, sizeof clip);
        if constexpr (has_varyings<S>())
            std::memcpy(b->varyings + b->varying_floats * i, &out, sizeof out);
    }
}

#if FACET_SDK_WIDE
template <class S>
constexpr bool has_wide() {
    return requires { typename S::WideVaryings; &S::fragment_wide; };
}

// The block in calls of S::fragment_wide, wide::kLanes lanes each; a call
// whose lanes have no fragment is skipped (its colour left 0).
template <class S>
void fragment_batch_wide(const facet_draw* draw, facet_fragment_batch* b) {
    using W = typename S::WideVaryings;
    constexpr int N = FACET_BLOCK_LANES, L = wide::kLanes;
    constexpr uint32_t floats = varying_floats<S>();
    static_assert(sizeof(W) == sizeof(wide::Float) * floats,
                  "WideVaryings must hold a wide::Float for every float of Varyings, in order");
    const Draw d{draw};
    const auto& params = *static_cast<const typename S::Params*>(draw->params);
    const uint32_t read = read_floats<S>(params);
    const auto load = [](const float* p, float otherwise) {
        wide::Float f = wide::splat(otherwise);
        if (p) std::memcpy(&f, p, sizeof f);
        return f;
    };
    // Pixel centres: the host's, when it packs batches (ABI 1.2), or a block's.
    const float* coord = draw->host->abi_minor >= 2 ? b->coord : nullptr;
    wide::Float column, row;
    for (int i = 0; i < L; ++i) column[i] = float(i % 4), row[i] = float(i / 4);
    for (int first = 0; first < N; first += L) {
        const uint32_t lanes = b->mask >> first & ((1u << L) - 1u);
        if (!lanes) {
            for (int c = 0; c < 4; ++c) std::fill_n(b->color + c * N + first, L, 0.0f);
            continue;
        }
        W v;  // the floats the draw does not read stay unset
        for (uint32_t k = 0; k < read; ++k)
            std::memcpy(reinterpret_cast<char*>(&v) + k * sizeof(wide::Float),
                        b->varyings + k * N + first, sizeof(wide::Float));
        WideFragment frag;
        if (coord)
            frag.coord = {load(coord + first, 0.0f), load(coord + N + first, 0.0f)};
        else
            frag.coord = {column + (float(b->x) + 0.5f), row + (float(b->y + first / 4) + 0.5f)};
        frag.depth = load(b->depth + first, 0.0f);
        frag.front_facing = b->front_facing != 0;
        frag.ao = load(b->ao ? b->ao + first : nullptr, 1.0f);
        frag.texels_ = b->texels ? b->texels + first : nullptr;
        frag.texture_count_ = texture_count<S>();
        const wide::Vec4 c = S::fragment_wide(v, frag, d, params);
        std::memcpy(b->color + first, &c.x, sizeof c.x);  // [4][16], as the ABI lays it out
        std::memcpy(b->color + N + first, &c.y, sizeof c.y);
        std::memcpy(b->color + 2 * N + first, &c.z, sizeof c.z);
        std::memcpy(b->color + 3 * N + first, &c.w, sizeof c.w);
        b->mask &= ~(wide::bits(frag.discarded) << first);
    }
}

// The loop a per-path build (FACET_SDK_ISA_*) gives: the wide one, or none.
template <class S>
constexpr facet_fragment_fn wide_loop() {
#if !defined(FACET_SDK_SCALAR)
    if constexpr (has_wide<S>()) return &fragment_batch_wide<S>;
#endif
    return nullptr;
}
#endif

template <class S>
void fragment_batch(const facet_draw* draw, facet_fragment_batch* b) {
#if FACET_SDK_WIDE && !defined(FACET_SDK_SCALAR)
    if constexpr (has_wide<S>()) return fragment_batch_wide<S>(draw, b);
#endif
    using V = typename S::Varyings;
    constexpr int N = FACET_BLOCK_LANES;
    constexpr uint32_t floats = varying_floats<S>();
    const Draw d{draw};
    const auto& params = *static_cast<const typename S::Params*>(draw->params);
    [[maybe_unused]] const uint32_t read = read_floats<S>(params);
    // Pixel centres: the host's, when it packs batches (ABI 1.2), or a block's.
    const float* coord = draw->host->abi_minor >= 2 ? b->coord : nullptr;
    uint32_t keep = b->mask;
    std::fill(b->color, b->color + 4 * N, 0.0f);  // lanes outside the mask
    for (uint32_t lanes = b->mask; lanes; lanes &= lanes - 1) {  // covered lanes only
        const int i = std::countr_zero(lanes);
        V v{};
        if constexpr (has_varyings<S>()) {
            float f[floats] = {};
            for (uint32_t k = 0; k < read; ++k) f[k] = b->varyings[k * N + i];
            std::memcpy(&v, f, sizeof v);
        }
        const glm::vec2 centre = coord ? glm::vec2(coord[i], coord[N + i])
                                       : glm::vec2(float(b->x + i % 4) + 0.5f,
                                                   float(b->y + i / 4) + 0.5f);
        Fragment frag{centre, b->depth[i], b->front_facing != 0, b->ao ? b->ao[i] : 1.0f};
        frag.texels_ = b->texels;
        frag.texture_count_ = texture_count<S>();
        frag.lane_ = i;
        const glm::vec4 c = S::fragment(v, frag, d, params);
        b->color[i] = c.r;
        b->color[N + i] = c.g;
        b->color[2 * N + i] = c.b;
        b->color[3 * N + i] = c.a;
        if (frag.discarded) keep &= ~(1u << i);
    }
    b->mask = keep;
}

// Every loop here works lane by lane, so the host may pack fragments from
// anywhere into a batch - unless the shader asks for derivatives, or says
// `static constexpr bool packable = false;` (its own code mixes lanes).
template <class S>
constexpr uint32_t flags() {
    bool packable = !(S::needs & FACET_NEED_DERIVATIVES);
    if constexpr (requires { S::packable; }) packable &= S::packable;
    return packable ? uint32_t(FACET_SHADER_PACKABLE) : 0u;
}

template <class S>
constexpr const facet_varying_desc* varying_table() {
    if constexpr (has_varyings<S>()) return S::varyings;
    return nullptr;
}

template <class S>
constexpr const facet_param_desc* param_table() {
    if constexpr (std::is_empty_v<typename S::Params>) return nullptr;
    else return std::data(S::params);  // a C array or a std::array
}

}  // namespace detail

}  // namespace facet::sdk

// The plugin's per-path fragment loops, defined by the builds
// facet_add_shader() adds (FACET_SHADER below). Weak and hidden: a plugin
// built without them (another build system, or a host compiling a shader
// into itself) links anyway, and they read as null.
#if !defined(FACET_SDK_ISA_avx2) && !defined(FACET_SDK_ISA_avx512)
extern "C" {
__attribute__((weak, visibility("hidden"))) extern const facet_fragment_fn facet_sdk_fragment_avx2;
__attribute__((weak, visibility("hidden"))) extern const facet_fragment_fn facet_sdk_fragment_avx512;
}
#endif

namespace facet::sdk {

template <class S>
const facet_shader_desc* describe() {
    using V = typename S::Varyings;
    if constexpr (detail::has_varyings<S>()) {
        static_assert(sizeof(V) == detail::varying_floats<S>() * sizeof(float),
                      "Varyings must hold exactly the floats the varyings table declares");
        static_assert(detail::varying_floats<S>() <= FACET_MAX_VARYING_FLOATS,
                      "too many varying floats");
    }
    static_assert(std::is_trivially_copyable_v<V> && std::is_standard_layout_v<typename S::Params>);
    constexpr uint32_t condition = detail::varyings_condition<S>();  // at compile time
    static const facet_shader_desc desc = {
        FACET_ABI_MAJOR, FACET_ABI_MINOR, static_cast<uint32_t>(sizeof(facet_shader_desc)),
        S::name, S::version,
        S::needs,
        detail::varying_count<S>(), detail::varying_table<S>(),
        detail::param_count<S>(), detail::param_table<S>(),
        std::is_empty_v<typename S::Params> ? 0u : static_cast<uint32_t>(sizeof(typename S::Params)),
        &detail::vertex_batch<S>, &detail::fragment_batch<S>,
#if defined(FACET_SDK_ISA_avx2) || defined(FACET_SDK_ISA_avx512)
        nullptr, nullptr,
#else
        &facet_sdk_fragment_avx2 ? facet_sdk_fragment_avx2 : nullptr,
        &facet_sdk_fragment_avx512 ? facet_sdk_fragment_avx512 : nullptr,
#endif
        detail::flags<S>(),
        FACET_KIND_SHADER, nullptr, detail::choice_table<S>(),
        detail::conditional_varyings<S>(), condition,
    };
    return &desc;
}

}  // namespace facet::sdk

// Export shader struct S as this plugin's entry point. One per plugin. In a
// per-path build (facet_add_shader() defines FACET_SDK_ISA_avx2 or _avx512)
// it gives that path's fragment loop instead, which the entry point's
// descriptor then points at.
#if defined(FACET_SDK_ISA_avx2)
#define FACET_SHADER(S)                                                                \
    extern "C" const facet_fragment_fn facet_sdk_fragment_avx2 =                       \
        ::facet::sdk::detail::wide_loop<S>();
#elif defined(FACET_SDK_ISA_avx512)
#define FACET_SHADER(S)                                                                \
    extern "C" const facet_fragment_fn facet_sdk_fragment_avx512 =                     \
        ::facet::sdk::detail::wide_loop<S>();
#else
#define FACET_SHADER(S)                                                        \
    extern "C" FACET_EXPORT const facet_shader_desc* facet_shader_entry(void) { \
        return ::facet::sdk::describe<S>();                                    \
    }
#endif
