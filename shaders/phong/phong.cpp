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
// spot factor (facet::sdk::incident_light). All colours are linear. With
// receive_shadows (the default) each light's term is times the share of it
// its shadow map lets through, if it casts shadows; with ambient_occlusion
// above 0, ambient is times AO to that power (facet::sdk::Receiving).
#include <facet/shader.hpp>

#include <cmath>
#include <cstddef>

namespace {

using namespace facet::sdk;

struct Phong {
    struct Params {
        glm::vec3 ambient;
        glm::vec3 diffuse;
        glm::vec3 specular;
        glm::vec3 emission;
        float shininess;
        int32_t blinn;         // bool
        int32_t base_texture;  // 1 if bound
        float alpha_cutoff;
        int32_t normal_texture;  // 1 if bound
        float normal_scale;
        Receiving receive;
    };
    struct Varyings {
        glm::vec3 position;  // world space
        glm::vec3 normal;    // world space, unit at the vertices
        glm::vec2 uv;
        glm::vec4 tangent;   // world space, w the handedness
    };

    static constexpr const char* name = "phong";
    static constexpr const char* version = "1.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_TANGENTS |
                                      FACET_NEED_LIGHTS | FACET_NEED_TEXTURES |
                                      FACET_NEED_SHADOW_MAP | FACET_NEED_AO | FACET_NEED_DISCARD;
    static constexpr facet_varying_desc varyings[] = {
        varying("position", 3), varying("normal", 3), varying("uv", 2), varying("tangent", 4)};
    // The tangent: read only with a normal map, and interpolated only then.
    static constexpr uint32_t conditional_varyings = 1;
    static constexpr const char* varyings_condition = "normal_texture";
    static constexpr auto params = with_receiving(std::array{
        color3("ambient", offsetof(Params, ambient), {0.02f, 0.02f, 0.02f},
               "linear RGB added everywhere"),
        color3("diffuse", offsetof(Params, diffuse), {0.6f, 0.6f, 0.6f},
               "linear RGB Lambert reflectance"),
        color3("specular", offsetof(Params, specular), {0.3f, 0.3f, 0.3f},
               "linear RGB specular reflectance"),
        color3("emission", offsetof(Params, emission), {0.0f, 0.0f, 0.0f},
               "linear RGB the surface emits"),
        float1("shininess", offsetof(Params, shininess), 32.0f, 1.0f, 10000.0f,
               "specular exponent: higher is a smaller, sharper highlight"),
        boolean("blinn", offsetof(Params, blinn), false,
                "Blinn-Phong (half vector) instead of Phong (reflected vector)"),
        texture("base_texture", offsetof(Params, base_texture), 2, true,
                "colour texture (sRGB) multiplying diffuse; its alpha is the output's"),
        alpha_cutoff(offsetof(Params, alpha_cutoff)),
        normal_texture(offsetof(Params, normal_texture), 2),
        normal_scale(offsetof(Params, normal_scale)),
    }, offsetof(Params, receive));

    // The specular lobe s for unit n, L, v (n.L > 0).
    static float lobe(const glm::vec3& n, const glm::vec3& l, const glm::vec3& v, const Params& p) {
        const float c = p.blinn ? glm::dot(n, glm::normalize(l + v))
                                : glm::dot(glm::reflect(-l, n), v);
        return std::pow(glm::max(c, 0.0f), p.shininess);
    }

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params& p, glm::vec4& clip) {
        clip = d.model_view_projection() * glm::vec4(in.position, 1.0f);
        const glm::vec3 world = glm::vec3(d.model() * glm::vec4(in.position, 1.0f));
        return {world, glm::normalize(d.normal_matrix() * in.normal), in.uv,
                p.normal_texture ? world_tangent(d, in.tangent) : glm::vec4(0.0f)};
    }

    // The reference: plain per-fragment code.
    static glm::vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        glm::vec3 n = glm::normalize(v.normal);
        if (p.normal_texture) n = normal_mapped(n, v.tangent, f.texture(1), p.normal_scale);
        const glm::vec3 to_eye = glm::normalize(d.camera_position() - v.position);
        const glm::vec4 base = f.texture(0);
        cut_out(f, base.a, p.alpha_cutoff);
        const glm::vec3 kd = p.diffuse * glm::vec3(base);
        glm::vec3 c = p.emission + p.ambient * ambient_visibility(f, p.receive);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), v.position);
            const float n_l = glm::dot(n, in.to_light);
            if (n_l <= 0.0f || in.radiance == glm::vec3(0.0f)) continue;
            c += in.radiance * (kd * n_l + p.specular * lobe(n, in.to_light, to_eye, p)) *
                 light_visibility(d, i, p.receive, v.position, n_l);
        }
        return {c, base.a};
    }

    // The same for wide::kLanes fragments at once, which facet runs (the
    // tests hold it to the reference above): lanes a light does not reach
    // (facing away, outside a spot's cone, past its range) select 0, and a
    // light that reaches no lane is skipped.
    struct WideVaryings {
        wide::Vec3 position;
        wide::Vec3 normal;
        wide::Vec2 uv;
        wide::Vec4 tangent;
    };

    static wide::Float lobe(const wide::Vec3& n, const wide::Vec3& l, const wide::Vec3& v,
                            const Params& p) {
        using namespace wide;
        const Float c = p.blinn ? dot(n, normalize(l + v)) : dot(reflect(-l, n), v);
        if (!any(c > 0.0f)) return splat(0.0f);  // pow(0, shininess >= 1): no highlight here
        return pow(max(c, splat(0.0f)), p.shininess);
    }

    // Two versions: one that receives shadows and AO, and one for draws that
    // receive neither (facet::sdk::receives).
    static wide::Vec4 fragment_wide(const WideVaryings& v, WideFragment& f, const Draw& d,
                                    const Params& p) {
        return receives(d, p.receive) ? shade<true>(v, f, d, p) : shade<false>(v, f, d, p);
    }

    template <bool Receives>
    static wide::Vec4 shade(const WideVaryings& v, WideFragment& f, const Draw& d,
                            const Params& p) {
        using namespace wide;
        Vec3 n = normalize(v.normal);
        if (p.normal_texture) n = normal_mapped(n, v.tangent, f.texture(1), p.normal_scale);
        const Vec3 to_eye = normalize(d.camera_position() - v.position);
        const Vec4 base = f.texture(0);
        cut_out(f, base.w, p.alpha_cutoff);
        const Vec3 kd = p.diffuse * rgb(base);
        Vec3 c(p.emission + p.ambient);
        if constexpr (Receives) c = p.emission + p.ambient * ambient_visibility(f, p.receive);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const WideIncident in = incident_light(d.light(i), v.position);
            const Float n_l = dot(n, in.to_light);
            const Mask facing = n_l > 0.0f && (in.radiance.x != 0.0f || in.radiance.y != 0.0f ||
                                               in.radiance.z != 0.0f);
            if (!any(facing)) continue;
            Vec3 lit = in.radiance * (kd * n_l + p.specular * lobe(n, in.to_light, to_eye, p));
            if constexpr (Receives) lit = lit * light_visibility(d, i, p.receive, v.position, n_l);
            c += select(facing, lit, Vec3(splat(0.0f)));
        }
        return {c, base.w};
    }
};

}  // namespace

FACET_SHADER(Phong)
