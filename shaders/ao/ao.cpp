// ao: Lambert diffuse plus ambient light scaled by screen-space ambient
// occlusion. The host runs a depth pre-pass and an AO pass (only when a
// visible material uses this shader), with the radius and sample count of
// the scene's render settings (ao_radius, ao_samples), and blurs the
// result; this shader darkens its ambient term by it, raised to `strength`.
#include <facet/shader.hpp>

#include <cstddef>

namespace {

using namespace facet::sdk;

struct Ao {
    struct Params {
        glm::vec4 base_color;
        glm::vec3 ambient;
        float strength;
    };
    struct Varyings {
        glm::vec3 normal;    // world space
        glm::vec3 position;  // world space
    };

    static constexpr const char* name = "ao";
    static constexpr const char* version = "2.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_LIGHTS | FACET_NEED_AO;
    static constexpr facet_varying_desc varyings[] = {varying("normal", 3),
                                                      varying("position", 3)};
    static constexpr facet_param_desc params[] = {
        color4("base_color", offsetof(Params, base_color), {0.8f, 0.8f, 0.8f, 1.0f}),
        color3("ambient", offsetof(Params, ambient), {0.6f, 0.6f, 0.65f}),
        float1("strength", offsetof(Params, strength), 1.0f, 0.0f, 8.0f,
               "exponent on the ambient visibility: 0 ignores AO"),
    };

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, glm::vec4& clip) {
        const glm::vec4 world = d.model() * glm::vec4(in.position, 1.0f);
        clip = d.view_projection() * world;
        return {d.normal_matrix() * in.normal, glm::vec3(world)};
    }

    static glm::vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        glm::vec3 n = glm::normalize(v.normal);
        if (!f.front_facing) n = -n;
        glm::vec3 light = p.ambient * glm::pow(f.ao, p.strength);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), v.position);
            light += in.radiance * glm::max(glm::dot(n, in.to_light), 0.0f);
        }
        return glm::vec4(glm::vec3(p.base_color) * light, p.base_color.a);
    }

    // The same for wide::kLanes fragments at once, which facet runs (the
    // tests hold it to the reference above).
    struct WideVaryings {
        wide::Vec3 normal;
        wide::Vec3 position;
    };

    static wide::Vec4 fragment_wide(const WideVaryings& v, WideFragment& f, const Draw& d,
                                    const Params& p) {
        using namespace wide;
        Vec3 n = normalize(v.normal);
        if (!f.front_facing) n = -n;
        Vec3 light = p.ambient * pow(f.ao, p.strength);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const WideIncident in = incident_light(d.light(i), v.position);
            light += in.radiance * max(dot(n, in.to_light), splat(0.0f));
        }
        return {glm::vec3(p.base_color) * light, splat(p.base_color.a)};
    }
};

}  // namespace

FACET_SHADER(Ao)
