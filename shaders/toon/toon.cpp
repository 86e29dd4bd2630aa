// toon: cel shading with quantised diffuse bands, a hard specular highlight,
// a rim light and silhouette outlines. Every light contributes.
//
//     band(x)  = ceil(x * bands) / bands for x > 0, else 0
//                (n.L in ((k-1)/bands, k/bands] gives k/bands: `bands` lit
//                 levels, plus the unlit side)
//     colour   = base_color * (ambient + sum of radiance * band(n.L))
//              + sum of radiance * specular_color   where n.L > 0 and
//                                                    max(n.h, 0)^shininess > specular_threshold
//                                                    (n.h > specular_threshold^(1/shininess))
//              + rim_color                          where 1 - n.v > rim_threshold
//     colour   = outline_color                      where n.v < outline_width
//                                                    (outline_width 0: no outline)
//     alpha    = 1
//
// n is the interpolated normal, normalised per fragment, or with a
// normal_texture the normal it gives (facet::sdk::normal_mapped); v points
// to the camera, h = normalize(L + v). `radiance` is color * intensity *
// attenuation * spot factor (facet::sdk::incident_light): bands quantise the
// angle term only, so a point light's falloff stays smooth. The outline is
// drawn where the surface turns away from the viewer, so it is thicker where
// the surface curves gently; flat surfaces seen at a grazing angle (a large
// ground plane) need outline_width 0. With receive_shadows (the default) a
// light's band and highlight are times the share of it its shadow map lets
// through; with ambient_occlusion above 0, ambient is times AO to that power
// (facet::sdk::Receiving).
#include <facet/lighting.hpp>

#include <cmath>

namespace {

using namespace facet::sdk;

struct Toon {
    static constexpr const char* name = "toon";
    static constexpr const char* version = "2.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_TANGENTS |
                                      FACET_NEED_TEXTURES | FACET_NEED_LIGHTS |
                                      FACET_NEED_SHADOW_MAP | FACET_NEED_AO;

    FACET_VARYINGS((Vec3, position),  // world space
                   (Vec3, normal),    // world space, unit at the vertices
                   (Vec2, uv),
                   (Vec4, tangent))   // world space, w the handedness
    // The UV and the tangent: read only with a normal map, and interpolated only then.
    static constexpr uint32_t conditional_varyings = 2;
    static constexpr const char* varyings_condition = "normal_texture";

    FACET_PARAMS(
        (color3, base_color, {0.8f, 0.3f, 0.2f}, "linear RGB albedo"),
        (color3, ambient, {0.08f, 0.08f, 0.1f}, "light on the unlit side, multiplied by base_color"),
        (int1, bands, 3, 1, 16, "lit diffuse levels"),
        (color3, specular_color, {1.0f, 1.0f, 1.0f},
         "colour of the hard highlight (times the light's radiance)"),
        (float1, shininess, 48.0f, 1.0f, 10000.0f, "Blinn exponent: higher is a smaller highlight"),
        (float1, specular_threshold, 0.5f, 0.0f, 1.0f,
         "highlight where max(n.h, 0)^shininess exceeds this"),
        (color3, rim_color, {0.15f, 0.15f, 0.2f}, "linear RGB added near the silhouette"),
        (float1, rim_threshold, 0.6f, 0.0f, 1.0f, "rim where 1 - n.v exceeds this"),
        (color3, outline_color, {0.0f, 0.0f, 0.0f}, "linear RGB of the silhouette outline"),
        (float1, outline_width, 0.2f, 0.0f, 1.0f, "outline where n.v is below this; 0: no outline"),
        (normal_map, normal_texture, "uv"),
        (normal_scale, normal_scale),
        (receiving, receive))

    // max(n.h, 0)^shininess > specular_threshold where n.h exceeds this.
    static float highlight_cos(const Params& p) {
        return std::pow(p.specular_threshold, 1.0f / p.shininess);
    }

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params& p, Vec4& clip) {
        return surface_vertex<Varyings>(in, d, bool(p.normal_texture), clip);
    }

    // Two versions: one that receives shadows and AO, and one for draws that
    // receive neither (facet::sdk::receives).
    static Vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        return receives(d, p.receive) ? shade<true>(v, f, d, p) : shade<false>(v, f, d, p);
    }

    template <bool Receives>
    static Vec4 shade(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        Vec3 n = normalize(v.normal);
        if (p.normal_texture)
            n = normal_mapped(n, v.tangent, f.texture(p.normal_texture), p.normal_scale);
        const Vec3 to_eye = normalize(d.camera_position() - v.position);
        const Float n_v = dot(n, to_eye);
        const Mask outline = p.outline_width > 0.0f ? n_v < p.outline_width : Mask{};
        const float highlight = highlight_cos(p), bands = float(p.bands);
        Vec3 light(p.ambient), shine(splat(0.0f));
        if constexpr (Receives) light = light * ambient_visibility(f, p.receive);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), v.position);
            const Float n_l = dot(n, in.to_light);
            const Mask facing = n_l > 0.0f;
            if (!any(facing)) continue;
            Vec3 radiance = in.radiance;
            if constexpr (Receives)
                radiance = radiance * light_visibility(d, i, p.receive, v.position, n_l);
            light += radiance * select(facing, ceil(n_l * bands) / bands, splat(0.0f));
            const Mask shines = facing && dot(n, normalize(in.to_light + to_eye)) > highlight;
            shine += select(shines, radiance * p.specular_color, Vec3(splat(0.0f)));
        }
        const Vec3 rim = select(1.0f - n_v > p.rim_threshold, Vec3(p.rim_color), Vec3(splat(0.0f)));
        const Vec3 c = p.base_color * light + shine + rim;
        return {select(outline, Vec3(p.outline_color), c), splat(1.0f)};
    }
};

}  // namespace

FACET_SHADER(Toon)
