// pbr: metallic-roughness shading as glTF 2.0 defines it (its Appendix B):
// a Lambert diffuse and a GGX specular lobe, with any number of
// directional, point and spot lights, shadows and AO.
//
//     base      = base_color * base_texture                 (sRGB; alpha too)
//     metallic  = metallic  * metallic_roughness_texture.b  (linear)
//     roughness = roughness * metallic_roughness_texture.g, at least 0.03
//     c_diff = base.rgb * (1 - metallic),  f0 = mix(0.04, base.rgb, metallic)
//     a = roughness^2,  h = normalize(L + v)
//     F = f0 + (1 - f0) (1 - v.h)^5                          (Schlick)
//     D = a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2)               (GGX, Trowbridge-Reitz)
//     V = 0.5 / (n.L sqrt((n.v)^2 (1 - a^2) + a^2)
//              + n.v sqrt((n.L)^2 (1 - a^2) + a^2))          (Smith, height-correlated)
//     colour = emissive * emissive_texture
//            + ambient * (c_diff + f0 * A + B) * occlusion
//            + sum over lights of radiance * n.L * ((1 - F) c_diff + pi F D V)
//
// The lights' term is pi times the BRDF's, so that a light's intensity
// means what it means to lit and phong: a white Lambertian surface facing a
// light of intensity 1 is 1. `ambient` is light arriving equally from
// everywhere; its specular share uses A, B, the split-sum environment BRDF
// fitted by Karis (2014), so rough and smooth surfaces keep their energy.
// occlusion = 1 + occlusion_strength * (occlusion_texture.r - 1), times
// AO^ambient_occlusion when the host runs AO. n is the interpolated normal,
// or with a normal_texture the normal it gives (normal_scale scales its X
// and Y; facet::sdk::normal_mapped); on a back face (a double-sided
// material) n and the tangent frame turn around. v points to the camera.
// With alpha_cutoff above 0, fragments whose base alpha is below it are
// discarded; the output alpha is base alpha, or 1 with opaque_alpha (glTF's
// OPAQUE and MASK modes). glTF materials map to it (docs/MATERIALS.md).
#include <facet/shader.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace {

using namespace facet::sdk;

constexpr float kPi = 3.14159265358979f;
constexpr float kMinRoughness = 0.03f;  // a mirror's lobe is narrower than a pixel can show

struct Pbr {
    struct Params {
        glm::vec4 base_color;
        glm::vec3 emissive;
        float metallic;
        glm::vec3 ambient;
        float roughness;
        float normal_scale;
        float occlusion_strength;
        int32_t base_texture;  // 1 if bound, as each texture below
        int32_t metallic_roughness_texture;
        int32_t normal_texture;
        int32_t occlusion_texture;
        int32_t emissive_texture;
        float alpha_cutoff;
        int32_t opaque_alpha;  // bool
        Receiving receive;
    };
    struct Varyings {
        glm::vec3 position;  // world space
        glm::vec3 normal;    // world space, unit at the vertices
        glm::vec2 uv;
        glm::vec4 tangent;   // world space, w the handedness
    };

    static constexpr const char* name = "pbr";
    static constexpr const char* version = "1.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_TANGENTS |
                                      FACET_NEED_LIGHTS | FACET_NEED_TEXTURES |
                                      FACET_NEED_SHADOW_MAP | FACET_NEED_AO | FACET_NEED_DISCARD;
    static constexpr facet_varying_desc varyings[] = {varying("position", 3), varying("normal", 3),
                                                      varying("uv", 2), varying("tangent", 4)};
    // The tangent: read only with a normal map, and interpolated only then.
    static constexpr uint32_t conditional_varyings = 1;
    static constexpr const char* varyings_condition = "normal_texture";
    // Texture slots, in the order of the schema.
    enum Slot { kBase, kMetallicRoughness, kNormal, kOcclusion, kEmissive };
    static constexpr auto params = with_receiving(std::array{
        color4("base_color", offsetof(Params, base_color), {1.0f, 1.0f, 1.0f, 1.0f},
               "linear RGBA base colour: albedo, or a metal's reflectance; alpha is the output's"),
        texture("base_texture", offsetof(Params, base_texture), 2, true,
                "colour texture (sRGB) multiplying base_color"),
        float1("metallic", offsetof(Params, metallic), 0.0f, 0.0f, 1.0f,
               "0: a dielectric, 1: a metal"),
        float1("roughness", offsetof(Params, roughness), 0.5f, 0.0f, 1.0f,
               "perceptual roughness: 0 a mirror, 1 fully rough"),
        texture("metallic_roughness_texture", offsetof(Params, metallic_roughness_texture), 2,
                false, "roughness in G and metallic in B (linear), multiplying the two above"),
        normal_texture(offsetof(Params, normal_texture), 2),
        normal_scale(offsetof(Params, normal_scale)),
        texture("occlusion_texture", offsetof(Params, occlusion_texture), 2, false,
                "ambient occlusion baked in R (linear)"),
        float1("occlusion_strength", offsetof(Params, occlusion_strength), 1.0f, 0.0f, 1.0f,
               "how much of the occlusion texture applies"),
        color3("emissive", offsetof(Params, emissive), {0.0f, 0.0f, 0.0f},
               "linear RGB the surface emits"),
        texture("emissive_texture", offsetof(Params, emissive_texture), 2, true,
                "colour texture (sRGB) multiplying emissive"),
        color3("ambient", offsetof(Params, ambient), {0.03f, 0.03f, 0.03f},
               "light arriving equally from everywhere"),
        alpha_cutoff(offsetof(Params, alpha_cutoff)),
        boolean("opaque_alpha", offsetof(Params, opaque_alpha), false,
                "write alpha 1 (glTF's OPAQUE and MASK) rather than the base alpha"),
    }, offsetof(Params, receive));

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params& p, glm::vec4& clip) {
        clip = d.model_view_projection() * glm::vec4(in.position, 1.0f);
        const glm::vec3 world = glm::vec3(d.model() * glm::vec4(in.position, 1.0f));
        return {world, glm::normalize(d.normal_matrix() * in.normal), in.uv,
                p.normal_texture ? world_tangent(d, in.tangent) : glm::vec4(0.0f)};
    }

    // What a surface point is made of.
    struct Surface {
        glm::vec3 n, v;
        glm::vec3 c_diff, f0;
        float a2;   // roughness^4: alpha squared
        float n_v;
    };

    // The lights' BRDF times pi, times n.L (> 0), for unit L.
    static glm::vec3 reflected(const Surface& s, const glm::vec3& l, float n_l) {
        const glm::vec3 h = glm::normalize(l + s.v);
        const float n_h = std::max(glm::dot(s.n, h), 0.0f);
        const float v_h = std::max(glm::dot(s.v, h), 0.0f);
        const float q = 1.0f - v_h, q2 = q * q;
        const glm::vec3 f = s.f0 + (1.0f - s.f0) * (q2 * q2 * q);
        const float k = n_h * n_h * (s.a2 - 1.0f) + 1.0f;
        const float d = s.a2 / (k * k);  // times pi: the pi of D cancels
        const float vis = 0.5f / (n_l * std::sqrt(s.n_v * s.n_v * (1.0f - s.a2) + s.a2) +
                                  s.n_v * std::sqrt(n_l * n_l * (1.0f - s.a2) + s.a2));
        return ((1.0f - f) * s.c_diff + f * (d * vis)) * n_l;
    }

    // The share of uniform ambient light a surface reflects towards v
    // (Karis's fit of the split-sum integral).
    static glm::vec3 ambient_share(const Surface& s, float roughness) {
        const glm::vec4 r = roughness * glm::vec4(-1.0f, -0.0275f, -0.572f, 0.022f) +
                            glm::vec4(1.0f, 0.0425f, 1.04f, -0.04f);
        const float a = std::min(r.x * r.x, std::exp2(-9.28f * s.n_v)) * r.x + r.y;
        const float scale = -1.04f * a + r.z, bias = 1.04f * a + r.w;
        return s.c_diff + s.f0 * scale + bias;
    }

    // The reference: plain per-fragment code.
    static glm::vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        const glm::vec4 base = p.base_color * f.texture(kBase);
        cut_out(f, base.a, p.alpha_cutoff);
        const glm::vec4 mr = f.texture(kMetallicRoughness);
        const float metallic = p.metallic * mr.z;
        const float roughness = std::max(p.roughness * mr.y, kMinRoughness);
        glm::vec3 n = glm::normalize(v.normal);
        if (!f.front_facing) n = -n;
        if (p.normal_texture)  // the tangent is read (and interpolated) only then
            n = normal_mapped(n, f.front_facing ? v.tangent : -v.tangent, f.texture(kNormal),
                              p.normal_scale);
        Surface s;
        s.n = n;
        s.v = glm::normalize(d.camera_position() - v.position);
        s.n_v = std::max(glm::dot(n, s.v), 1e-4f);
        s.c_diff = glm::vec3(base) * (1.0f - metallic);
        s.f0 = glm::mix(glm::vec3(0.04f), glm::vec3(base), metallic);
        const float a = roughness * roughness;
        s.a2 = a * a;
        const float occlusion = 1.0f + p.occlusion_strength * (f.texture(kOcclusion).x - 1.0f);
        glm::vec3 c = p.emissive * glm::vec3(f.texture(kEmissive)) +
                      p.ambient * ambient_share(s, roughness) *
                          (occlusion * ambient_visibility(f, p.receive));
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), v.position);
            const float n_l = glm::dot(n, in.to_light);
            if (n_l <= 0.0f || in.radiance == glm::vec3(0.0f)) continue;
            c += in.radiance * reflected(s, in.to_light, n_l) *
                 light_visibility(d, i, p.receive, v.position, n_l);
        }
        return {c, p.opaque_alpha ? 1.0f : base.a};
    }

    // The same for wide::kLanes fragments at once, which facet runs (the
    // tests hold it to the reference above).
    struct WideVaryings {
        wide::Vec3 position;
        wide::Vec3 normal;
        wide::Vec2 uv;
        wide::Vec4 tangent;
    };

    struct WideSurface {
        wide::Vec3 n, v;
        wide::Vec3 c_diff, f0;
        wide::Float a2, n_v;
    };

    static wide::Vec3 reflected(const WideSurface& s, const wide::Vec3& l, const wide::Float& n_l) {
        using namespace wide;
        const Vec3 h = normalize(l + s.v);
        const Float n_h = max(dot(s.n, h), splat(0.0f));
        const Float v_h = max(dot(s.v, h), splat(0.0f));
        const Float q = 1.0f - v_h, q2 = q * q;
        const Vec3 f = s.f0 + (Vec3(splat(1.0f)) - s.f0) * (q2 * q2 * q);
        const Float k = n_h * n_h * (s.a2 - 1.0f) + 1.0f;
        const Float d = s.a2 / (k * k);
        const Float vis = 0.5f / (n_l * sqrt(s.n_v * s.n_v * (1.0f - s.a2) + s.a2) +
                                  s.n_v * sqrt(n_l * n_l * (1.0f - s.a2) + s.a2));
        return ((Vec3(splat(1.0f)) - f) * s.c_diff + f * (d * vis)) * n_l;
    }

    static wide::Vec3 ambient_share(const WideSurface& s, const wide::Float& roughness) {
        using namespace wide;
        const Float rx = 1.0f - roughness, ry = 0.0425f - 0.0275f * roughness;
        const Float rz = 1.04f - 0.572f * roughness, rw = 0.022f * roughness - 0.04f;
        const Float a = min(rx * rx, exp2(-9.28f * s.n_v)) * rx + ry;
        const Float scale = -1.04f * a + rz, bias = 1.04f * a + rw;
        return s.c_diff + s.f0 * scale + Vec3(bias);
    }

    static wide::Vec4 fragment_wide(const WideVaryings& v, WideFragment& f, const Draw& d,
                                    const Params& p) {
        return receives(d, p.receive) ? shade<true>(v, f, d, p) : shade<false>(v, f, d, p);
    }

    template <bool Receives>
    static wide::Vec4 shade(const WideVaryings& v, WideFragment& f, const Draw& d,
                            const Params& p) {
        using namespace wide;
        const Vec4 base = f.texture(kBase) * p.base_color;
        cut_out(f, base.w, p.alpha_cutoff);
        const Vec4 mr = f.texture(kMetallicRoughness);
        const Float metallic = mr.z * p.metallic;
        const Float roughness = max(mr.y * p.roughness, splat(kMinRoughness));
        Vec3 n = normalize(v.normal);
        if (!f.front_facing) n = -n;
        if (p.normal_texture) {  // the tangent is read (and interpolated) only then
            Vec4 t = v.tangent;
            if (!f.front_facing) t = {-t.x, -t.y, -t.z, -t.w};
            n = normal_mapped(n, t, f.texture(kNormal), p.normal_scale);
        }
        WideSurface s;
        s.n = n;
        s.v = normalize(d.camera_position() - v.position);
        s.n_v = max(dot(n, s.v), splat(1e-4f));
        const Vec3 albedo = rgb(base);
        s.c_diff = albedo * (1.0f - metallic);
        s.f0 = Vec3(splat(0.04f)) + (albedo - Vec3(splat(0.04f))) * metallic;
        const Float a = roughness * roughness;
        s.a2 = a * a;
        Float occlusion = 1.0f + p.occlusion_strength * (f.texture(kOcclusion).x - 1.0f);
        if constexpr (Receives) occlusion = occlusion * ambient_visibility(f, p.receive);
        Vec3 c = p.emissive * rgb(f.texture(kEmissive)) +
                 p.ambient * ambient_share(s, roughness) * occlusion;
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const WideIncident in = incident_light(d.light(i), v.position);
            const Float n_l = dot(n, in.to_light);
            const Mask facing = n_l > 0.0f && (in.radiance.x != 0.0f || in.radiance.y != 0.0f ||
                                               in.radiance.z != 0.0f);
            if (!any(facing)) continue;
            // Lanes facing away take n.L of 1 here, and their term is dropped below.
            const Float n_l_safe = select(facing, n_l, splat(1.0f));
            Vec3 lit = in.radiance * reflected(s, in.to_light, n_l_safe);
            if constexpr (Receives) lit = lit * light_visibility(d, i, p.receive, v.position, n_l);
            c += select(facing, lit, Vec3(splat(0.0f)));
        }
        return {c, p.opaque_alpha ? splat(1.0f) : base.w};
    }
};

}  // namespace

FACET_SHADER(Pbr)
