// lit: Lambert diffuse plus a constant ambient term.
//
//     albedo = base_color * base_texture          (texture optional, sRGB)
//     E      = ambient + sum over lights of radiance * max(dot(n, L), 0)
//     colour = albedo.rgb * E,  alpha = albedo.a
//
// With alpha_cutoff above 0, a fragment whose albedo.a is below it is
// discarded (a cutout).
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
#include <facet/shader.hpp>

#include <cstddef>

namespace {

using namespace facet::sdk;

struct Lit {
    struct Params {
        glm::vec4 base_color;
        glm::vec3 ambient;
        int32_t base_texture;  // 1 if bound
        int32_t per_pixel;     // bool
        float alpha_cutoff;
        int32_t normal_texture;  // 1 if bound
        float normal_scale;
        Receiving receive;
    };
    struct Varyings {
        glm::vec3 position;    // world space
        glm::vec3 normal;      // world space, unit at the vertices
        glm::vec2 uv;
        glm::vec3 irradiance;  // per_pixel off: the vertex's E from unshadowed lights
        glm::vec4 tangent;     // world space, w the handedness
    };

    static constexpr const char* name = "lit";
    static constexpr const char* version = "1.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_TANGENTS |
                                      FACET_NEED_LIGHTS | FACET_NEED_TEXTURES |
                                      FACET_NEED_SHADOW_MAP | FACET_NEED_AO | FACET_NEED_DISCARD;
    static constexpr facet_varying_desc varyings[] = {
        varying("position", 3), varying("normal", 3), varying("uv", 2), varying("irradiance", 3),
        varying("tangent", 4)};
    // The tangent: read only with a normal map, and interpolated only then.
    static constexpr uint32_t conditional_varyings = 1;
    static constexpr const char* varyings_condition = "normal_texture";
    static constexpr auto params = with_receiving(std::array{
        color4("base_color", offsetof(Params, base_color), {0.8f, 0.8f, 0.8f, 1.0f},
               "linear RGBA albedo; alpha is the output alpha"),
        color3("ambient", offsetof(Params, ambient), {0.03f, 0.03f, 0.03f},
               "light arriving from everywhere, added to the lights' irradiance"),
        texture("base_texture", offsetof(Params, base_texture), 2, true,
                "colour texture (sRGB) multiplying base_color"),
        boolean("per_pixel", offsetof(Params, per_pixel), true,
                "light each fragment (true) or each vertex, interpolated (false)"),
        alpha_cutoff(offsetof(Params, alpha_cutoff)),
        normal_texture(offsetof(Params, normal_texture), 2),
        normal_scale(offsetof(Params, normal_scale)),
    }, offsetof(Params, receive));

    // Which lights a sum of Lambert terms takes: every one, those whose
    // shadow this material receives (each times its visibility), or the others.
    enum class Lights { all, shadowed, unshadowed };
    static bool shadowed(const Draw& d, uint32_t i, const Params& params) {
        return params.receive.shadows && d.has_shadow(i);
    }

    // Irradiance at p with unit normal n from the lights `which` selects.
    static glm::vec3 irradiance(const glm::vec3& p, const glm::vec3& n, const Draw& d,
                                const Params& params, Lights which) {
        glm::vec3 e(0.0f);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            if (which != Lights::all && (which == Lights::shadowed) != shadowed(d, i, params))
                continue;
            const Incident in = incident_light(d.light(i), p);
            const float n_l = glm::dot(n, in.to_light);
            if (n_l <= 0.0f) continue;
            const float v = which == Lights::unshadowed
                                ? 1.0f
                                : light_visibility(d, i, params.receive, p, n_l);
            e += in.radiance * (n_l * v);
        }
        return e;
    }

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params& p, glm::vec4& clip) {
        clip = d.model_view_projection() * glm::vec4(in.position, 1.0f);
        const glm::vec3 world = glm::vec3(d.model() * glm::vec4(in.position, 1.0f));
        const glm::vec3 n = glm::normalize(d.normal_matrix() * in.normal);
        const glm::vec3 e =
            p.per_pixel ? glm::vec3(0.0f) : irradiance(world, n, d, p, Lights::unshadowed);
        const glm::vec4 t = p.normal_texture ? world_tangent(d, in.tangent) : glm::vec4(0.0f);
        return {world, n, in.uv, e, t};
    }

    static glm::vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        const glm::vec4 albedo = p.base_color * f.texture(0);
        cut_out(f, albedo.a, p.alpha_cutoff);
        glm::vec3 n = glm::normalize(v.normal);
        if (p.normal_texture && p.per_pixel)
            n = normal_mapped(n, v.tangent, f.texture(1), p.normal_scale);
        const glm::vec3 e =
            p.ambient * ambient_visibility(f, p.receive) +
            (p.per_pixel ? irradiance(v.position, n, d, p, Lights::all)
                         : v.irradiance + irradiance(v.position, n, d, p, Lights::shadowed));
        return {glm::vec3(albedo) * e, albedo.a};
    }

    // The same for wide::kLanes fragments at once, which facet runs (the
    // tests hold it to the reference above).
    struct WideVaryings {
        wide::Vec3 position;
        wide::Vec3 normal;
        wide::Vec2 uv;
        wide::Vec3 irradiance;
        wide::Vec4 tangent;
    };

    // Irradiance from the lights `which` selects, each light's term times its
    // visibility if Shadows.
    template <bool Shadows>
    static wide::Vec3 irradiance(const wide::Vec3& p, const wide::Vec3& n, const Draw& d,
                                 const Params& params, Lights which) {
        using namespace wide;
        Vec3 e(splat(0.0f));
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            if (which != Lights::all && (which == Lights::shadowed) != shadowed(d, i, params))
                continue;
            const WideIncident in = incident_light(d.light(i), p);
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

    // Two versions: one that receives shadows and AO, and one for draws that
    // receive neither (facet::sdk::receives), where per-vertex lighting is all
    // in v.irradiance.
    static wide::Vec4 fragment_wide(const WideVaryings& v, WideFragment& f, const Draw& d,
                                    const Params& p) {
        return receives(d, p.receive) ? shade<true>(v, f, d, p) : shade<false>(v, f, d, p);
    }

    template <bool Receives>
    static wide::Vec4 shade(const WideVaryings& v, WideFragment& f, const Draw& d,
                            const Params& p) {
        using namespace wide;
        const Vec4 albedo = Vec4(p.base_color) * f.texture(0);
        cut_out(f, albedo.w, p.alpha_cutoff);
        Vec3 e(p.ambient);
        if constexpr (Receives) e = e * ambient_visibility(f, p.receive);
        if (p.per_pixel) {
            Vec3 n = normalize(v.normal);
            if (p.normal_texture) n = normal_mapped(n, v.tangent, f.texture(1), p.normal_scale);
            e += irradiance<Receives>(v.position, n, d, p, Lights::all);
        }
        else if (Receives)
            e += v.irradiance +
                 irradiance<Receives>(v.position, normalize(v.normal), d, p, Lights::shadowed);
        else
            e += v.irradiance;
        return {rgb(albedo) * e, albedo.w};
    }
};

}  // namespace

FACET_SHADER(Lit)
