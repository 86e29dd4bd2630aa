// lit: Lambert diffuse plus a constant ambient term.
//
//     albedo = base_color * base_texture          (texture optional, sRGB)
//     E      = ambient + sum over lights of radiance * max(dot(n, L), 0)
//     colour = albedo.rgb * E,  alpha = albedo.a
//
// `radiance` is what a light delivers at the point: color * intensity *
// attenuation * spot factor (facet::sdk::incident_light). With per_pixel (the
// default) the normal and the world position are interpolated and E is
// evaluated per fragment. Without it E is evaluated per vertex (Gouraud) and
// interpolated; the texture is still sampled per fragment.
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
    };
    struct Varyings {
        glm::vec3 position;    // world space
        glm::vec3 normal;      // world space, unit at the vertices
        glm::vec2 uv;
        glm::vec3 irradiance;  // E of the vertex (per_pixel off only)
    };

    static constexpr const char* name = "lit";
    static constexpr const char* version = "1.0";
    static constexpr uint32_t needs =
        FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_LIGHTS | FACET_NEED_TEXTURES;
    static constexpr facet_varying_desc varyings[] = {
        varying("position", 3), varying("normal", 3), varying("uv", 2), varying("irradiance", 3)};
    static constexpr facet_param_desc params[] = {
        color4("base_color", offsetof(Params, base_color), {0.8f, 0.8f, 0.8f, 1.0f},
               "linear RGBA albedo; alpha is the output alpha"),
        color3("ambient", offsetof(Params, ambient), {0.03f, 0.03f, 0.03f},
               "light arriving from everywhere, added to the lights' irradiance"),
        texture("base_texture", offsetof(Params, base_texture), 2, true,
                "colour texture (sRGB) multiplying base_color"),
        boolean("per_pixel", offsetof(Params, per_pixel), true,
                "light each fragment (true) or each vertex, interpolated (false)"),
    };

    // Irradiance at p with unit normal n: ambient plus every light's Lambert term.
    static glm::vec3 irradiance(const glm::vec3& p, const glm::vec3& n, const Draw& d,
                                const Params& params) {
        glm::vec3 e = params.ambient;
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), p);
            e += in.radiance * glm::max(glm::dot(n, in.to_light), 0.0f);
        }
        return e;
    }

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params& p, glm::vec4& clip) {
        clip = d.model_view_projection() * glm::vec4(in.position, 1.0f);
        const glm::vec3 world = glm::vec3(d.model() * glm::vec4(in.position, 1.0f));
        const glm::vec3 n = glm::normalize(d.normal_matrix() * in.normal);
        const glm::vec3 e = p.per_pixel ? glm::vec3(0.0f) : irradiance(world, n, d, p);
        return {world, n, in.uv, e};
    }

    static glm::vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        const glm::vec4 albedo = p.base_color * f.texture(0);
        const glm::vec3 e =
            p.per_pixel ? irradiance(v.position, glm::normalize(v.normal), d, p) : v.irradiance;
        return {glm::vec3(albedo) * e, albedo.a};
    }

    // The same for wide::kLanes fragments at once, which facet runs (the
    // tests hold it to the reference above).
    struct WideVaryings {
        wide::Vec3 position;
        wide::Vec3 normal;
        wide::Vec2 uv;
        wide::Vec3 irradiance;
    };

    static wide::Vec3 irradiance(const wide::Vec3& p, const wide::Vec3& n, const Draw& d,
                                 const Params& params) {
        using namespace wide;
        Vec3 e(params.ambient);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const WideIncident in = incident_light(d.light(i), p);
            e += in.radiance * max(dot(n, in.to_light), splat(0.0f));
        }
        return e;
    }

    static wide::Vec4 fragment_wide(const WideVaryings& v, WideFragment& f, const Draw& d,
                                    const Params& p) {
        using namespace wide;
        const Vec4 albedo = Vec4(p.base_color) * f.texture(0);
        const Vec3 e =
            p.per_pixel ? irradiance(v.position, normalize(v.normal), d, p) : v.irradiance;
        return {rgb(albedo) * e, albedo.w};
    }
};

}  // namespace

FACET_SHADER(Lit)
