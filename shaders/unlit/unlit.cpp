// unlit: vertex colour x base colour x optional texture. No lighting, so
// no shadows; with ambient_occlusion above 0 (a lightmapped look) the colour
// is times the host's AO to that power. alpha_cutoff cuts out what the
// alpha (of the texture, mostly) leaves below it.
#include <facet/lighting.hpp>

namespace {

using namespace facet::sdk;

struct Unlit {
    static constexpr const char* name = "unlit";
    static constexpr const char* version = "2.0";
    static constexpr uint32_t needs =
        FACET_NEED_COLORS | FACET_NEED_UVS | FACET_NEED_TEXTURES | FACET_NEED_AO | FACET_NEED_DISCARD;

    FACET_VARYINGS((Vec4, color), (Vec2, uv))
    FACET_PARAMS((color4, base_color, {1, 1, 1, 1}, "linear RGBA multiplied into every fragment"),
                 (texture, base_texture, "uv", srgb,
                  "colour texture (sRGB), sampled at the mesh UVs"),
                 (ao_strength, ambient_occlusion),
                 (cutoff, alpha_cutoff))

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, Vec4& clip) {
        clip = d.model_view_projection() * Vec4(in.position, 1.0f);
        return {in.color, in.uv};
    }

    static Vec4 fragment(const Varyings& v, Fragment& f, const Draw&, const Params& p) {
        const Vec4 c = v.color * p.base_color * f.texture(p.base_texture);
        cut_out(f, c.w, p.alpha_cutoff);
        return {rgb(c) * ambient_visibility(f, p.ambient_occlusion), c.w};
    }
};

}  // namespace

FACET_SHADER(Unlit)
