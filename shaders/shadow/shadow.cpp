// shadow: Lambert diffuse plus ambient, with shadows from every light that
// casts them: an example of the SDK's shadow service, which lit, phong and
// toon also use (receive_shadows). The host renders a depth map from each
// such light (a cube for a point light) when a visible material uses this
// shader; each fragment filters it with percentage-closer filtering over
// pcf_kernel x pcf_kernel texels and a slope-scaled bias, both parameters of
// this shader (light_visibility).
#include <facet/lighting.hpp>

namespace {

using namespace facet::sdk;

struct Shadow {
    static constexpr const char* name = "shadow";
    static constexpr const char* version = "2.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_LIGHTS | FACET_NEED_SHADOW_MAP;

    FACET_VARYINGS((Vec3, normal),     // world space
                   (Vec3, position))   // world space
    FACET_PARAMS((color4, base_color, {0.8f, 0.8f, 0.8f, 1.0f}),
                 (color3, ambient, {0.05f, 0.05f, 0.06f}),
                 (int1, pcf_kernel, 3, 1, 15, "percentage-closer filter width in texels (odd)"),
                 (float1, bias, 1.0f, 0.0f, 64.0f, "constant bias, texels"),
                 (float1, slope_bias, 1.5f, 0.0f, 64.0f,
                  "bias per unit of tan(angle to the light), texels"))

    // Its filter as the SDK's shadow service takes it.
    static Receiving receiving(const Params& p) {
        return {1, p.pcf_kernel, p.bias, p.slope_bias, 0.0f};
    }

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, Vec4& clip) {
        const Vec4 world = d.model() * Vec4(in.position, 1.0f);
        clip = d.view_projection() * world;
        return {d.normal_matrix() * in.normal, xyz(world)};
    }

    // A light that reaches no lane (facing away, outside a spot's cone, past
    // its range) is skipped, and its map filtered only where it reaches some.
    static Vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        Vec3 n = normalize(v.normal);
        if (!f.front_facing) n = -n;
        Vec3 light(splat(0.0f));
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), v.position);
            const Float n_dot_l = dot(n, in.to_light);
            const Mask reached = lit_by(in, n_dot_l);
            if (!any(reached)) continue;  // nothing to shadow
            const Float visible = light_visibility(d, i, receiving(p), v.position, n_dot_l);
            light += select(reached, in.radiance * (n_dot_l * visible), Vec3(splat(0.0f)));
        }
        return {glm::vec3(p.base_color) * (p.ambient + light), splat(p.base_color.a)};
    }
};

}  // namespace

FACET_SHADER(Shadow)
