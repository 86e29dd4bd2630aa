// unlit: vertex colour x base colour x optional texture. No lighting, so
// no shadows; with ambient_occlusion above 0 (a lightmapped look) the colour
// is times the host's AO to that power. alpha_cutoff cuts out what the
// alpha (of the texture, mostly) leaves below it.
#include <facet/shader.hpp>

#include <cstddef>

namespace {

using namespace facet::sdk;

struct Unlit {
    struct Params {
        glm::vec4 base_color;
        int32_t base_texture;  // 1 if bound
        float ambient_occlusion;
        float alpha_cutoff;
    };
    struct Varyings {
        glm::vec4 color;
        glm::vec2 uv;
    };

    static constexpr const char* name = "unlit";
    static constexpr const char* version = "1.0";
    static constexpr uint32_t needs =
        FACET_NEED_COLORS | FACET_NEED_UVS | FACET_NEED_TEXTURES | FACET_NEED_AO | FACET_NEED_DISCARD;
    static constexpr facet_varying_desc varyings[] = {varying("color", 4), varying("uv", 2)};
    static constexpr facet_param_desc params[] = {
        color4("base_color", offsetof(Params, base_color), {1, 1, 1, 1},
               "linear RGBA multiplied into every fragment"),
        texture("base_texture", offsetof(Params, base_texture), 1, true,
                "colour texture (sRGB), sampled at the mesh UVs"),
        ambient_occlusion(offsetof(Params, ambient_occlusion)),
        alpha_cutoff(offsetof(Params, alpha_cutoff)),
    };

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, glm::vec4& clip) {
        clip = d.model_view_projection() * glm::vec4(in.position, 1.0f);
        return {in.color, in.uv};
    }

    static glm::vec4 fragment(const Varyings& v, Fragment& f, const Draw&, const Params& p) {
        const glm::vec4 c = v.color * p.base_color * f.texture(0);
        cut_out(f, c.a, p.alpha_cutoff);
        return {glm::vec3(c) * ambient_visibility(f, p.ambient_occlusion), c.a};
    }

    // The same for 16 fragments at once, which facet runs.
    struct WideVaryings {
        wide::Vec4 color;
        wide::Vec2 uv;
    };
    static wide::Vec4 fragment_wide(const WideVaryings& v, WideFragment& f, const Draw&,
                                    const Params& p) {
        const wide::Vec4 c = v.color * p.base_color * f.texture(0);
        cut_out(f, c.w, p.alpha_cutoff);
        return {rgb(c) * ambient_visibility(f, p.ambient_occlusion), c.w};
    }
};

}  // namespace

FACET_SHADER(Unlit)
