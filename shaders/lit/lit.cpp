// lit: Lambert diffuse plus a constant ambient term.
//
//     albedo = base_color * base_texture          (texture optional, sRGB)
//     E      = ambient + sum over lights of radiance * max(dot(n, L), 0)
//     colour = albedo.rgb * E,  alpha = albedo.a
//
// With alpha_cutoff above 0, a fragment whose albedo.a is below it is
// discarded (a cutout). In a scene with an environment, ambient is its
// irradiance / pi at the interpolated normal (<facet/environment.hpp>).
//
// `radiance` is what a light delivers at the point: color * intensity *
// attenuation * spot factor (facet::sdk::incident_light). With per_pixel (the
// default) the normal and the world position are interpolated and E is
// evaluated per fragment. Without it E is evaluated per vertex (Gouraud) and
// interpolated; the texture is still sampled per fragment. A normal_texture
// bends n per fragment (facet::sdk::normal_mapped), with per_pixel only.
//
// With receive_shadows (the default) the term of each light that casts
// shadows is times the share of it its shadow map lets through, evaluated
// per fragment even without per_pixel; with ambient_occlusion above 0 the
// ambient term is times AO to that power, per fragment too
// (facet::sdk::Receiving).
#include <facet/environment.hpp>
#include <facet/lighting.hpp>

namespace {

using namespace facet::sdk;

struct Lit {
    static constexpr const char* name = "lit";
    static constexpr const char* version = "2.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_TANGENTS |
                                      FACET_NEED_LIGHTS | FACET_NEED_TEXTURES |
                                      FACET_NEED_SHADOW_MAP | FACET_NEED_AO | FACET_NEED_DISCARD;

    FACET_VARYINGS((Vec3, position),    // world space
                   (Vec3, normal),      // world space, unit at the vertices
                   (Vec2, uv),
                   (Vec3, irradiance),  // per_pixel off: the vertex's E from unshadowed lights
                   (Vec4, tangent))     // world space, w the handedness
    // The tangent: read only with a normal map, and interpolated only then.
    static constexpr uint32_t conditional_varyings = 1;
    static constexpr const char* varyings_condition = "normal_texture";

    FACET_PARAMS(
        (color4, base_color, {0.8f, 0.8f, 0.8f, 1.0f},
         "linear RGBA albedo; alpha is the output alpha"),
        (color3, ambient, {0.03f, 0.03f, 0.03f},
         "light arriving from everywhere, added to the lights' irradiance"),
        (texture, base_texture, "uv", srgb, "colour texture (sRGB) multiplying base_color"),
        (boolean, per_pixel, true,
         "light each fragment (true) or each vertex, interpolated (false)"),
        (cutoff, alpha_cutoff),
        (normal_map, normal_texture, "uv"),
        (normal_scale, normal_scale),
        (receiving, receive))

    // Which lights a sum of Lambert terms takes: every one, those whose
    // shadow this material receives (each times its visibility), or the others.
    enum class Lights { all, shadowed, unshadowed };
    static bool shadowed(const Draw& d, uint32_t i, const Params& params) {
        return params.receive.shadows && has_shadow(d, i);
    }

    // Irradiance at p with unit normal n from the lights `which` selects,
    // each light's term times its visibility if Shadows.
    template <bool Shadows>
    static Vec3 irradiance(const Vec3& p, const Vec3& n, const Draw& d, const Params& params,
                           Lights which) {
        Vec3 e(splat(0.0f));
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            if (which != Lights::all && (which == Lights::shadowed) != shadowed(d, i, params))
                continue;
            const Incident in = incident_light(d.light(i), p);
            const Float n_l = max(dot(n, in.to_light), splat(0.0f));
            if constexpr (Shadows) {
                if (!any(n_l > 0.0f)) continue;
                e += in.radiance * (n_l * light_visibility(d, i, params.receive, p, n_l));
            } else {
                e += in.radiance * n_l;
            }
        }
        return e;
    }

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params& p, Vec4& clip) {
        clip = d.model_view_projection() * Vec4(in.position, 1.0f);
        const Vec3 world = xyz(d.model() * Vec4(in.position, 1.0f));
        const Vec3 n = normalize(d.normal_matrix() * in.normal);
        const Vec3 e = p.per_pixel ? Vec3(splat(0.0f))
                                   : irradiance<false>(world, n, d, p, Lights::unshadowed);
        const Vec4 t = p.normal_texture ? world_tangent(d, in.tangent) : Vec4(splat(0.0f));
        return {world, n, in.uv, e, t};
    }

    // Two versions: one that receives shadows and AO, and one for draws that
    // receive neither (facet::sdk::receives), where per-vertex lighting is all
    // in v.irradiance.
    static Vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        return receives(d, p.receive) ? shade<true>(v, f, d, p) : shade<false>(v, f, d, p);
    }

    template <bool Receives>
    static Vec4 shade(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        const Vec4 albedo = p.base_color * f.texture(p.base_texture);
        cut_out(f, albedo.w, p.alpha_cutoff);
        Vec3 e(p.ambient);
        if (const Environment env = environment_of(f)) e = env.irradiance(normalize(v.normal));
        if constexpr (Receives) e = e * ambient_visibility(f, p.receive);
        if (p.per_pixel) {
            Vec3 n = normalize(v.normal);
            if (p.normal_texture)
                n = normal_mapped(n, v.tangent, f.texture(p.normal_texture), p.normal_scale);
            e += irradiance<Receives>(v.position, n, d, p, Lights::all);
        } else if (Receives) {
            e += v.irradiance +
                 irradiance<Receives>(v.position, normalize(v.normal), d, p, Lights::shadowed);
        } else {
            e += v.irradiance;
        }
        return {rgb(albedo) * e, albedo.w};
    }
};

}  // namespace

FACET_SHADER(Lit)
