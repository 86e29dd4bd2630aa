// pbr: metallic-roughness shading as glTF 2.0 defines it (its Appendix B):
// a Lambert diffuse and a GGX specular lobe, with any number of
// directional, point and spot lights, shadows and AO.
//
//     base      = base_color * base_texture                 (sRGB; alpha too)
//     metallic  = metallic  * metallic_roughness_texture.b  (linear)
//     roughness = roughness * metallic_roughness_texture.g, at least 0.03
//     c_diff = base.rgb * (1 - metallic)
//     f0  = mix(min(((ior - 1) / (ior + 1))^2 specular_color, 1) specular, base.rgb, metallic)
//     f90 = mix(specular, 1, metallic)      (KHR_materials_ior and _specular;
//                                            by default f0 = 0.04, f90 = 1)
//     a = roughness^2,  h = normalize(L + v)
//     F = f0 + (f90 - f0) (1 - v.h)^5                        (Schlick)
//     D = a^2 / (pi ((n.h)^2 (a^2 - 1) + 1)^2)               (GGX, Trowbridge-Reitz)
//     V = 0.5 / (n.L sqrt((n.v)^2 (1 - a^2) + a^2)
//              + n.v sqrt((n.L)^2 (1 - a^2) + a^2))          (Smith, height-correlated)
//     colour = emissive * emissive_texture
//            + ambient * (c_diff + f0 * A + f90 * B) * occlusion       (no environment)
//            + (c_diff E(n) + S(r, roughness) (f0 A + f90 B)) * occlusion  (an environment)
//            + sum over lights of radiance * n.L * ((1 - F) c_diff + pi F D V)
//
// A clear coat (KHR_materials_clearcoat) lies over the rest, emission too:
// with w = clearcoat * clearcoat_texture.r * (0.04 + 0.96 (1 - n.v)^5),
// the base's light and emission are times (1 - w), and w times a GGX lobe of
// clearcoat_roughness (times clearcoat_roughness_texture.g) with F = 1 is
// added, lit as the base is. The coat follows the interpolated normal.
//
// The lights' term is pi times the BRDF's, so that a light's intensity
// means what it means to lit and phong: a white Lambertian surface facing a
// light of intensity 1 is 1. `ambient` is light arriving equally from
// everywhere; its specular share uses A, B, the split-sum environment BRDF
// fitted by Karis (2014), so rough and smooth surfaces keep their energy.
// A scene with an environment lights by it instead (<facet/environment.hpp>):
// E(n) its irradiance / pi, S its radiance prefiltered for the roughness
// around the reflected view r, A and B from the split-sum table.
// occlusion = 1 + occlusion_strength * (occlusion_texture.r - 1), times
// AO^ambient_occlusion when the host runs AO. n is the interpolated normal,
// or with a normal_texture the normal it gives (normal_scale scales its X
// and Y; facet::sdk::normal_mapped); on a back face (a double-sided
// material) n and the tangent frame turn around. v points to the camera.
// With alpha_cutoff above 0, fragments whose base alpha is below it are
// discarded; the output alpha is base alpha, or 1 with opaque_alpha (glTF's
// OPAQUE and MASK modes). glTF materials map to it (docs/MATERIALS.md).
#include <facet/environment.hpp>
#include <facet/lighting.hpp>

namespace {

using namespace facet::sdk;

constexpr float kMinRoughness = 0.03f;  // a mirror's lobe is narrower than a pixel can show

struct Pbr {
    static constexpr const char* name = "pbr";
    static constexpr const char* version = "2.0";
    static constexpr uint32_t needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_UV1 |
                                      FACET_NEED_TANGENTS | FACET_NEED_LIGHTS |
                                      FACET_NEED_TEXTURES | FACET_NEED_SHADOW_MAP |
                                      FACET_NEED_AO | FACET_NEED_DISCARD;

    FACET_VARYINGS((Vec3, position),  // world space
                   (Vec3, normal),    // world space, unit at the vertices
                   (Vec2, uv),
                   (Vec2, uv1),       // the second set: textures a material binds to it
                   (Vec4, tangent))   // world space, w the handedness
    static constexpr const char* second_uv = "uv1";
    // The tangent: read only with a normal map, and interpolated only then.
    static constexpr uint32_t conditional_varyings = 1;
    static constexpr const char* varyings_condition = "normal_texture";

    FACET_PARAMS(
        (color4, base_color, {1.0f, 1.0f, 1.0f, 1.0f},
         "linear RGBA base colour: albedo, or a metal's reflectance; alpha is the output's"),
        (texture, base_texture, "uv", srgb, "colour texture (sRGB) multiplying base_color"),
        (float1, metallic, 0.0f, 0.0f, 1.0f, "0: a dielectric, 1: a metal"),
        (float1, roughness, 0.5f, 0.0f, 1.0f, "perceptual roughness: 0 a mirror, 1 fully rough"),
        (texture, metallic_roughness_texture, "uv", linear,
         "roughness in G and metallic in B (linear), multiplying the two above"),
        (normal_map, normal_texture, "uv"),
        (normal_scale, normal_scale),
        (texture, occlusion_texture, "uv", linear, "ambient occlusion baked in R (linear)"),
        (float1, occlusion_strength, 1.0f, 0.0f, 1.0f, "how much of the occlusion texture applies"),
        (color3, emissive, {0.0f, 0.0f, 0.0f}, "linear RGB the surface emits"),
        (texture, emissive_texture, "uv", srgb, "colour texture (sRGB) multiplying emissive"),
        (color3, ambient, {0.03f, 0.03f, 0.03f}, "light arriving equally from everywhere"),
        (float1, ior, 1.5f, 0.0f, 10.0f,
         "a dielectric's index of refraction (glTF KHR_materials_ior); 0: it reflects all (F0 = 1)"),
        (float1, specular, 1.0f, 0.0f, 1.0f,
         "a dielectric's specular weight (glTF KHR_materials_specular): 0 none"),
        (color3, specular_color, {1.0f, 1.0f, 1.0f},
         "tints a dielectric's reflectance at normal incidence (KHR_materials_specular)"),
        (float1, clearcoat, 0.0f, 0.0f, 1.0f, "a clear coat's strength: 0 none (KHR_materials_clearcoat)"),
        (float1, clearcoat_roughness, 0.0f, 0.0f, 1.0f, "the clear coat's perceptual roughness"),
        (texture, clearcoat_texture, "uv", linear, "clear coat strength in R (linear), multiplying clearcoat"),
        (texture, clearcoat_roughness_texture, "uv", linear,
         "clear coat roughness in G (linear), multiplying clearcoat_roughness"),
        (cutoff, alpha_cutoff),
        (boolean, opaque_alpha, false,
         "write alpha 1 (glTF's OPAQUE and MASK) rather than the base alpha"),
        (receiving, receive))

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params& p, Vec4& clip) {
        return surface_vertex<Varyings>(in, d, bool(p.normal_texture), clip, in.uv1);
    }

    // What a surface point is made of.
    struct Surface {
        Vec3 n, v;
        Vec3 c_diff, f0;
        Float f90;
        Float a2;  // roughness^4: alpha squared
        Float n_v;
    };

    // The lights' BRDF times pi, times n.L (> 0), for unit L.
    static Vec3 reflected(const Surface& s, const Vec3& l, const Float& n_l) {
        const Vec3 h = normalize(l + s.v);
        const Float n_h = max(dot(s.n, h), splat(0.0f));
        const Float v_h = max(dot(s.v, h), splat(0.0f));
        const Float q = 1.0f - v_h, q2 = q * q;
        const Vec3 f = s.f0 + (s.f90 - s.f0) * (q2 * q2 * q);
        const Float k = n_h * n_h * (s.a2 - 1.0f) + 1.0f;
        const Float d = s.a2 / (k * k);  // times pi: the pi of D cancels
        const Float vis = 0.5f / (n_l * sqrt(s.n_v * s.n_v * (1.0f - s.a2) + s.a2) +
                                  s.n_v * sqrt(n_l * n_l * (1.0f - s.a2) + s.a2));
        return ((1.0f - f) * s.c_diff + f * (d * vis)) * n_l;
    }

    // The share of uniform ambient light a surface reflects towards v
    // (Karis's fit of the split-sum integral).
    static Vec3 ambient_share(const Surface& s, const Float& roughness) {
        const Float rx = 1.0f - roughness, ry = 0.0425f - 0.0275f * roughness;
        const Float rz = 1.04f - 0.572f * roughness, rw = 0.022f * roughness - 0.04f;
        const Float a = min(rx * rx, exp2(-9.28f * s.n_v)) * rx + ry;
        const Float scale = -1.04f * a + rz, bias = 1.04f * a + rw;
        return s.c_diff + s.f0 * scale + s.f90 * bias;
    }

    // A dielectric's reflectance at normal incidence (KHR_materials_ior and
    // _specular): in double, so that the default index 1.5 gives glTF's 0.04.
    static glm::vec3 dielectric_f0(const Params& p) {
        const double r = (double(p.ior) - 1.0) / (double(p.ior) + 1.0);
        return glm::min(float(r * r) * p.specular_color, glm::vec3(1.0f)) * p.specular;
    }

    // The clear coat: a surface of its own (F = 1: its Fresnel is in its
    // weight) and that weight, w; none where p.clearcoat is 0.
    struct Coat {
        Surface s;
        Float roughness, w;
    };
    static Coat coat_of(const Params& p, Fragment& f, const Vec3& n, const Vec3& v) {
        Coat c;
        c.s.n = n;
        c.s.v = v;
        c.s.n_v = max(dot(n, v), splat(1e-4f));
        c.s.c_diff = Vec3(splat(0.0f));
        c.s.f0 = Vec3(splat(1.0f));
        c.s.f90 = splat(1.0f);
        c.roughness = max(f.texture(p.clearcoat_roughness_texture).y * p.clearcoat_roughness,
                          splat(kMinRoughness));
        const Float a = c.roughness * c.roughness;
        c.s.a2 = a * a;
        const Float q = 1.0f - c.s.n_v, q2 = q * q;
        c.w = f.texture(p.clearcoat_texture).x * p.clearcoat * (0.04f + 0.96f * (q2 * q2 * q));
        return c;
    }

    // Two versions: one that receives shadows and AO, and one for draws that
    // receive neither (facet::sdk::receives).
    static Vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        return receives(d, p.receive) ? shade<true>(v, f, d, p) : shade<false>(v, f, d, p);
    }

    template <bool Receives>
    static Vec4 shade(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        const Vec4 base = f.texture(p.base_texture) * p.base_color;
        cut_out(f, base.w, p.alpha_cutoff);
        const Vec4 mr = f.texture(p.metallic_roughness_texture);
        const Float metallic = mr.z * p.metallic;
        const Float roughness = max(mr.y * p.roughness, splat(kMinRoughness));
        Vec3 n = normalize(v.normal);
        if (!f.front_facing) n = -n;
        const Vec3 geometric = n;
        if (p.normal_texture) {  // the tangent is read (and interpolated) only then
            const Vec4 t = f.front_facing ? v.tangent : -v.tangent;
            n = normal_mapped(n, t, f.texture(p.normal_texture), p.normal_scale);
        }
        Surface s;
        s.n = n;
        s.v = normalize(d.camera_position() - v.position);
        s.n_v = max(dot(n, s.v), splat(1e-4f));
        const Vec3 albedo = rgb(base);
        s.c_diff = albedo * (1.0f - metallic);
        s.f0 = mix(Vec3(dielectric_f0(p)), albedo, metallic);
        s.f90 = p.specular + (1.0f - p.specular) * metallic;
        const Float a = roughness * roughness;
        s.a2 = a * a;
        const bool coated = p.clearcoat > 0.0f;
        const Coat coat = coated ? coat_of(p, f, geometric, s.v) : Coat{};
        Float occlusion = 1.0f + p.occlusion_strength * (f.texture(p.occlusion_texture).x - 1.0f);
        if constexpr (Receives) occlusion = occlusion * ambient_visibility(f, p.receive);
        Vec3 c = p.emissive * rgb(f.texture(p.emissive_texture));
        if (coated) {
            c = c * (1.0f - coat.w) + ambient_light(s, roughness, f, p) * occlusion * (1.0f - coat.w) +
                 ambient_light(coat.s, coat.roughness, f, p) * (occlusion * coat.w);
        } else {
            c += ambient_light(s, roughness, f, p) * occlusion;
        }
        for (uint32_t i = 0; i < d.light_count(); ++i) {
            const Incident in = incident_light(d.light(i), v.position);
            const Float n_l = dot(n, in.to_light);
            const Mask reached = lit_by(in, n_l);
            if (!any(reached)) continue;
            // Lanes facing away take n.L of 1 here, and their term is dropped below.
            const Float n_l_safe = select(reached, n_l, splat(1.0f));
            Vec3 lit = in.radiance * reflected(s, in.to_light, n_l_safe);
            if (coated) {
                const Float coat_l = max(dot(coat.s.n, in.to_light), splat(0.0f));
                lit = lit * (1.0f - coat.w) + in.radiance * reflected(coat.s, in.to_light, coat_l) * coat.w;
            }
            if constexpr (Receives) lit = lit * light_visibility(d, i, p.receive, v.position, n_l);
            c += select(reached, lit, Vec3(splat(0.0f)));
        }
        return {c, p.opaque_alpha ? splat(1.0f) : base.w};
    }

    // Light arriving from all around, reflected towards v: the scene's
    // environment, or else its uniform ambient.
    static Vec3 ambient_light(const Surface& s, const Float& roughness, Fragment& f, const Params& p) {
        const Environment env = environment_of(f);
        if (!env) return p.ambient * ambient_share(s, roughness);
        const Vec2 ab = env.brdf(s.n_v, roughness);
        // The lobe's peak leans from the mirror direction towards n as it
        // widens (the dominant direction: Lagarde and de Rousiers 2014).
        const Vec3 towards = mix(reflect(-s.v, s.n), s.n, roughness * roughness);
        const Vec3 specular = env.specular(towards, roughness) * (s.f0 * ab.x + s.f90 * ab.y);
        return s.c_diff * env.irradiance(s.n) + specular;
    }
};

}  // namespace

FACET_SHADER(Pbr)
