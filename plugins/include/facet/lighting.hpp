// facet lighting for shaders (C++20, header-only): the light arriving at a
// point from the host's lights, the share of it a shadow map lets through,
// ambient occlusion, and normal maps; for kLanes points at once. Include it
// in a shader that lights surfaces, beside <facet/shader.hpp>.
//
// A shader that receives the host's shadows and AO declares the parameters
// `(receiving, receive)` (params.hpp: receive_shadows, shadow_kernel,
// shadow_bias, shadow_slope_bias, ambient_occlusion), asks for
// FACET_NEED_SHADOW_MAP and FACET_NEED_AO, and multiplies each light's term
// by light_visibility() and its ambient term by ambient_visibility().
#pragma once

#include <facet/shader.hpp>
#include <facet/shadows.hpp>

#include <limits>

namespace facet::sdk {

// ---- lights ----------------------------------------------------------------------

// Light arriving at kLanes points.
struct Incident {
    Vec3 to_light;  // unit vectors towards the light
    Vec3 radiance;  // colour * intensity * attenuation * spot cone; 0 past range
    Float distance;  // to the light; infinite for directional lights
};

// How much of a spot light's cone reaches a point at `cos_angle` from its
// axis: smoothstep(cos outer, cos inner, cos angle), or a hard edge when the
// two cones are equal. A multiply by the reciprocal where smoothstep
// divides: within an ulp or two.
inline Float spot_cone(const facet_light& l, const Float& cos_angle) {
    return smoothstep(l.spot_cos_outer, l.spot_cos_inner, cos_angle);
}

// Directional lights shine along `direction` (the host normalises it).
// Point and spot lights fall off as 1 / (c + l d + q d^2) with attenuation =
// {c, l, q}, give nothing past `range` (if not 0) or at their own position,
// and a spot light is limited to its cone (spot_cone).
inline Incident incident_light(const facet_light& l, const Vec3& p) {
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
    return {select(dark, Vec3(splat(0.0f)), to_light), color * select(dark, splat(0.0f), scale),
            d};
}

// The lanes a light reaches: facing it (n.L > 0) and within its reach.
inline Mask lit_by(const Incident& in, const Float& n_dot_l) {
    return n_dot_l > 0.0f &&
           (in.radiance.x != 0.0f || in.radiance.y != 0.0f || in.radiance.z != 0.0f);
}

// ---- what a surface receives: shadows and ambient occlusion ---------------------

// What reaches points p of light `i`: 1, or the share its shadow map lets
// through (shadow_visibility with the material's filter), n_dot_l being the
// cosine between the normal and the direction to the light.
[[gnu::always_inline]] inline Float light_visibility(const Draw& d, uint32_t i,
                                                     const Receiving& r, const Vec3& p,
                                                     const Float& n_dot_l) {
    if (!r.shadows) return splat(1.0f);
    if (const ShadowMap m = shadow_of(d, i))
        return shadow_visibility(m, p, n_dot_l, r.kernel, r.bias, r.slope_bias);
    if (const CubeShadow c = cube_shadow_of(d, i))
        return shadow_visibility(c, p, n_dot_l, r.kernel, r.bias, r.slope_bias);
    return splat(1.0f);
}

// Whether light visibility can be other than 1 in this draw: the material
// receives shadows and some light has a map.
inline bool receives_shadows(const Draw& d, const Receiving& r) {
    if (!r.shadows) return false;
    for (uint32_t i = 0; i < d.light_count(); ++i)
        if (has_shadow(d, i)) return true;
    return false;
}

// Whether a draw's lighting can be darkened at all, by a shadow map or by
// AO. A fragment function branches on it once per call to a version with
// neither, so a draw that receives nothing pays little for the services
// (phong, toon and lit were 2-9% slower without the branch).
inline bool receives(const Draw& d, const Receiving& r) {
    return receives_shadows(d, r) || r.ao > 0.0f;
}

// What the ambient term is multiplied by: AO^strength, or 1.
inline Float ambient_visibility(const Fragment& f, float strength) {
    return strength > 0.0f ? pow(f.ao, strength) : splat(1.0f);
}
inline Float ambient_visibility(const Fragment& f, const Receiving& r) {
    return ambient_visibility(f, r.ao);
}

// ---- normal maps -----------------------------------------------------------------

// A normal map (the `normal_map` kind) holds a tangent-space normal as RGB
// = n * 0.5 + 0.5, in the OpenGL and glTF convention: X along the tangent
// (+u), Y towards the texture's top row, Z out of the surface. A shader that
// reads one asks for FACET_NEED_TANGENTS, passes world_tangent() of
// VertexIn::tangent to its fragments as a Vec4 varying, and shades with
// normal_mapped().

// Tangents t (object space, w the handedness) in world space: xyz by the
// model matrix, and w turned around where the model mirrors, so that the
// bitangent cross(n, xyz) * w keeps pointing at the texture's top.
inline Vec4 world_tangent(const Draw& d, const Vec4& t) {
    const glm::mat3 m(d.model());
    const Vec3 xyz = m * Vec3(t.x, t.y, t.z);
    const Float length2 = dot(xyz, xyz);
    const Vec3 unit = select(length2 > 0.0f, xyz / sqrt(length2), xyz);
    return {unit, glm::determinant(m) < 0.0f ? -t.w : t.w};
}

// The vertex stage of a lit surface that may be normal mapped: clip, and
// varyings V of world position, unit world normal, UV, any `more` (a
// second UV set, ...) and world tangent (0 without a normal map, whose
// tangent the host then does not interpolate: conditional_varyings).
template <class V, class... More>
V surface_vertex(const VertexIn& in, const Draw& d, bool with_tangent, Vec4& clip,
                 const More&... more) {
    clip = d.model_view_projection() * Vec4(in.position, 1.0f);
    const Vec3 world = xyz(d.model() * Vec4(in.position, 1.0f));
    return {world, normalize(d.normal_matrix() * in.normal), in.uv, more...,
            with_tangent ? world_tangent(d, in.tangent) : Vec4(splat(0.0f))};
}

// The unit normals a normal map's texels give, their X and Y times `scale`,
// in the frame of unit normals n and the interpolated world tangents t (not
// unit, nor perpendicular to n: both are mended here). Where t has nothing
// left across n (a mesh without tangents, or a vertex without UVs, gets a
// zero tangent), n.
inline Vec3 normal_mapped(const Vec3& n, const Vec4& t, const Vec4& texel, float scale) {
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

}  // namespace facet::sdk
