// ao: Lambert diffuse plus ambient light scaled by screen-space ambient
// occlusion. The host runs a depth pre-pass and an AO pass (only when a
// visible material uses this shader), with the radius and sample count of
// the scene's render settings (ao_radius, ao_samples), and blurs the
// result; this shader darkens its ambient term by it, raised to `strength`.
#include <facet/lighting.hpp>

namespace {

using namespace facet::sdk;

struct Ao {
    static constexpr const char* name = "ao";
    static constexpr const char* version = "3.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_LIGHTS | FACET_NEED_AO;

    FACET_VARYINGS((Vec3, normal),     // world space
                   (Vec3, position))   // world space
    FACET_PARAMS((color4, base_color, {0.8f, 0.8f, 0.8f, 1.0f}),
                 (color3, ambient, {0.6f, 0.6f, 0.65f}),
                 (float1, strength, 1.0f, 0.0f, 8.0f,
                  "exponent on the ambient visibility: 0 ignores AO"))

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, Vec4& clip) {
        const Vec4 world = d.model() * Vec4(in.position, 1.0f);
        clip = d.view_projection() * world;
        return {d.normal_matrix() * in.normal, xyz(world)};
    }

    static Vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        Vec3 n = normalize(v.normal);
        if (!f.front_facing) n = -n;
        Vec3 light = p.ambient * pow(f.ao, p.strength);
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), v.position);
            light += in.radiance * max(dot(n, in.to_light), splat(0.0f));
        }
        return {glm::vec3(p.base_color) * light, splat(p.base_color.a)};
    }
};

}  // namespace

FACET_SHADER(Ao)
