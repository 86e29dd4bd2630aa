// shadow: Lambert diffuse plus ambient, with shadows from every light that
// casts them: an example of the SDK's shadow service, which lit, phong and
// toon also use (receive_shadows). The host renders a depth map from each
// such light (a cube for a point light) when a visible material uses this
// shader; each fragment filters it with percentage-closer filtering over
// pcf_kernel x pcf_kernel texels and a slope-scaled bias, both parameters of
// this shader (light_visibility).
#include <facet/shader.hpp>

#include <cstddef>

namespace {

using namespace facet::sdk;

struct Shadow {
    struct Params {
        glm::vec4 base_color;
        glm::vec3 ambient;
        int32_t pcf_kernel;
        float bias;
        float slope_bias;
    };
    struct Varyings {
        glm::vec3 normal;    // world space
        glm::vec3 position;  // world space
    };

    static constexpr const char* name = "shadow";
    static constexpr const char* version = "1.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_LIGHTS | FACET_NEED_SHADOW_MAP;
    static constexpr facet_varying_desc varyings[] = {varying("normal", 3),
                                                      varying("position", 3)};
    static constexpr facet_param_desc params[] = {
        color4("base_color", offsetof(Params, base_color), {0.8f, 0.8f, 0.8f, 1.0f}),
        color3("ambient", offsetof(Params, ambient), {0.05f, 0.05f, 0.06f}),
        int1("pcf_kernel", offsetof(Params, pcf_kernel), 3, 1, 15,
             "percentage-closer filter width in texels (odd)"),
        float1("bias", offsetof(Params, bias), 1.0f, 0.0f, 64.0f, "constant bias, texels"),
        float1("slope_bias", offsetof(Params, slope_bias), 1.5f, 0.0f, 64.0f,
               "bias per unit of tan(angle to the light), texels"),
    };

    // Its filter as the SDK's shadow service takes it.
    static Receiving receiving(const Params& p) {
        return {1, p.pcf_kernel, p.bias, p.slope_bias, 0.0f};
    }

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, glm::vec4& clip) {
        const glm::vec4 world = d.model() * glm::vec4(in.position, 1.0f);
        clip = d.view_projection() * world;
        return {d.normal_matrix() * in.normal, glm::vec3(world)};
    }

    static glm::vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        glm::vec3 n = glm::normalize(v.normal);
        if (!f.front_facing) n = -n;
        glm::vec3 light(0.0f);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), v.position);
            const float n_dot_l = glm::dot(n, in.to_light);
            if (n_dot_l <= 0.0f || in.radiance == glm::vec3(0.0f)) continue;  // nothing to shadow
            const float visible = light_visibility(d, i, receiving(p), v.position, n_dot_l);
            light += in.radiance * (n_dot_l * visible);
        }
        return glm::vec4(glm::vec3(p.base_color) * (p.ambient + light), p.base_color.a);
    }

    // The same for wide::kLanes fragments at once, which facet runs (the
    // tests hold it to the reference above): a light that reaches no lane
    // (facing away, outside a spot's cone, past its range) is skipped, and
    // its map filtered only where it reaches some lane.
    struct WideVaryings {
        wide::Vec3 normal;
        wide::Vec3 position;
    };

    static wide::Vec4 fragment_wide(const WideVaryings& v, WideFragment& f, const Draw& d,
                                    const Params& p) {
        using namespace wide;
        Vec3 n = normalize(v.normal);
        if (!f.front_facing) n = -n;
        Vec3 light(splat(0.0f));
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const WideIncident in = incident_light(d.light(i), v.position);
            const Float n_dot_l = dot(n, in.to_light);
            const Mask facing = n_dot_l > 0.0f &&
                                (in.radiance.x != 0.0f || in.radiance.y != 0.0f ||
                                 in.radiance.z != 0.0f);
            if (!any(facing)) continue;  // nothing to shadow
            const Float visible = light_visibility(d, i, receiving(p), v.position, n_dot_l);
            light += select(facing, in.radiance * (n_dot_l * visible), Vec3(splat(0.0f)));
        }
        return {glm::vec3(p.base_color) * (p.ambient + light), splat(p.base_color.a)};
    }
};

}  // namespace

FACET_SHADER(Shadow)
