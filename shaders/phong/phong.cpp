// phong: per-pixel Phong or Blinn-Phong with any number of directional,
// point and spot lights.
//
//     colour = emission + ambient
//            + sum over lights of radiance * (kd * max(n.L, 0) + specular * s)
//     kd     = diffuse * base_texture             (texture optional, sRGB)
//     s      = max(r.v, 0)^shininess,  r = reflect(-L, n)         (Phong)
//            = max(n.h, 0)^shininess,  h = normalize(L + v)       (blinn: true)
//     s      = 0 where n.L <= 0;  alpha = base_texture alpha (1 without one),
//     and with alpha_cutoff above 0 a fragment of lower alpha is discarded
//
// n is the interpolated normal, normalised per fragment, or with a
// normal_texture the normal it gives (facet::sdk::normal_mapped); v points
// from the fragment to the camera. `radiance` is color * intensity * attenuation *
// spot factor (facet::sdk::incident_light). All colours are linear. In a
// scene with an environment, ambient is kd times its irradiance / pi at n
// (<facet/environment.hpp>). With receive_shadows (the default) each
// light's term is times the share of it its shadow map lets through, if it
// casts shadows; with ambient_occlusion above 0, ambient is times AO to
// that power (facet::sdk::Receiving).
//
// With gouraud: true each light's diffuse and specular terms (attenuation,
// spot cone and range included) are summed at the vertices and
// interpolated, as fixed-function Gouraud shading with specular does:
//     colour = emission + ambient + kd * D + specular * S
// D and S the interpolated sums of radiance * max(n.L, 0) and radiance * s
// at the vertices (v from each vertex to the camera); the texture is still
// sampled per fragment. A light whose shadow map the draw receives is lit
// per fragment instead, so that its shadow stays sharp. A normal_texture
// is not read under gouraud.
#include <facet/environment.hpp>
#include <facet/lighting.hpp>

namespace {

using namespace facet::sdk;

struct Phong {
    static constexpr const char* name = "phong";
    static constexpr const char* version = "2.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_TANGENTS |
                                      FACET_NEED_LIGHTS | FACET_NEED_TEXTURES |
                                      FACET_NEED_SHADOW_MAP | FACET_NEED_AO | FACET_NEED_DISCARD;

    FACET_VARYINGS((Vec3, position),         // world space
                   (Vec3, normal),           // world space, unit at the vertices
                   (Vec2, uv),
                   (Vec3, vertex_diffuse),   // gouraud: D at the vertices
                   (Vec3, vertex_specular),  // gouraud: S at the vertices
                   (Vec4, tangent))          // world space, w the handedness
    // Read only with a normal map or under gouraud, and interpolated only then.
    static constexpr uint32_t conditional_varyings = 3;
    static constexpr const char* varyings_condition = "normal_texture";
    static constexpr const char* varyings_condition_also = "gouraud";

    FACET_PARAMS(
        (color3, ambient, {0.02f, 0.02f, 0.02f}, "linear RGB added everywhere"),
        (color3, diffuse, {0.6f, 0.6f, 0.6f}, "linear RGB Lambert reflectance"),
        (color3, specular, {0.3f, 0.3f, 0.3f}, "linear RGB specular reflectance"),
        (color3, emission, {0.0f, 0.0f, 0.0f}, "linear RGB the surface emits"),
        (float1, shininess, 32.0f, 1.0f, 10000.0f,
         "specular exponent: higher is a smaller, sharper highlight"),
        (boolean, blinn, false, "Blinn-Phong (half vector) instead of Phong (reflected vector)"),
        (boolean, gouraud, false,
         "light each vertex and interpolate (Gouraud, with specular) instead of each fragment"),
        (texture, base_texture, "uv", srgb,
         "colour texture (sRGB) multiplying diffuse; its alpha is the output's"),
        (cutoff, alpha_cutoff),
        (normal_map, normal_texture, "uv"),
        (normal_scale, normal_scale),
        (receiving, receive))

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params& p, Vec4& clip) {
        Vec3 diffuse(splat(0.0f)), specular(splat(0.0f));
        if (p.gouraud) {
            const Vec3 world = xyz(d.model() * Vec4(in.position, 1.0f));
            const Vec3 n = normalize(d.normal_matrix() * in.normal);
            const Vec3 to_eye = normalize(d.camera_position() - world);
            for (uint32_t i = 0; i < d.light_count(); ++i)
                if (!shadowed(d, i, p)) add_light(d.light(i), world, n, to_eye, p, diffuse, specular);
        }
        return surface_vertex<Varyings>(in, d, bool(p.normal_texture) && !p.gouraud, clip, diffuse,
                                        specular);
    }

    // Whether light i's term is lit per fragment under gouraud: its shadow
    // map is one the draw receives.
    static bool shadowed(const Draw& d, uint32_t i, const Params& p) {
        return p.receive.shadows && has_shadow(d, i);
    }

    // Light `l`'s diffuse (radiance * n.L) and specular (radiance * s) terms
    // at p, added; 0 where it does not reach.
    static void add_light(const facet_light& l, const Vec3& p, const Vec3& n, const Vec3& to_eye,
                          const Params& params, Vec3& diffuse, Vec3& specular) {
        const Incident in = incident_light(l, p);
        const Float n_l = dot(n, in.to_light);
        const Mask reached = lit_by(in, n_l);
        if (!any(reached)) return;
        diffuse += select(reached, in.radiance * n_l, Vec3(splat(0.0f)));
        specular += select(reached, in.radiance * lobe(n, in.to_light, to_eye, params),
                           Vec3(splat(0.0f)));
    }

    // The specular lobe s for unit n, L, v; 0 where n.L <= 0 is left to the caller.
    static Float lobe(const Vec3& n, const Vec3& l, const Vec3& v, const Params& p) {
        const Float c = p.blinn ? dot(n, normalize(l + v)) : dot(reflect(-l, n), v);
        if (!any(c > 0.0f)) return splat(0.0f);  // pow(0, shininess >= 1): no highlight here
        return pow(max(c, splat(0.0f)), p.shininess);
    }

    // Lanes a light does not reach (facing away, outside a spot's cone, past
    // its range) select 0, and a light that reaches no lane is skipped. Two
    // versions: one that receives shadows and AO, and one for draws that
    // receive neither (facet::sdk::receives).
    static Vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        return receives(d, p.receive) ? shade<true>(v, f, d, p) : shade<false>(v, f, d, p);
    }

    template <bool Receives>
    static Vec4 shade(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        Vec3 n = normalize(v.normal);
        if (p.normal_texture && !p.gouraud)
            n = normal_mapped(n, v.tangent, f.texture(p.normal_texture), p.normal_scale);
        const Vec3 to_eye = normalize(d.camera_position() - v.position);
        const Vec4 base = f.texture(p.base_texture);
        cut_out(f, base.w, p.alpha_cutoff);
        const Vec3 kd = p.diffuse * rgb(base);
        Vec3 ambient(p.ambient);
        if (const Environment env = environment_of(f)) ambient = kd * env.irradiance(n);
        Vec3 c = p.emission + ambient;
        if constexpr (Receives) c = p.emission + ambient * ambient_visibility(f, p.receive);
        if (p.gouraud) c += kd * v.vertex_diffuse + p.specular * v.vertex_specular;
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            if (p.gouraud && !(Receives && shadowed(d, i, p))) continue;  // summed at the vertices
            const Incident in = incident_light(d.light(i), v.position);
            const Float n_l = dot(n, in.to_light);
            const Mask reached = lit_by(in, n_l);
            if (!any(reached)) continue;
            Vec3 lit = in.radiance * (kd * n_l + p.specular * lobe(n, in.to_light, to_eye, p));
            if constexpr (Receives) lit = lit * light_visibility(d, i, p.receive, v.position, n_l);
            c += select(reached, lit, Vec3(splat(0.0f)));
        }
        return {c, base.w};
    }
};

}  // namespace

FACET_SHADER(Phong)
