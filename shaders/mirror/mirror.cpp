// mirror: a mirror that reflects an environment cube map, times a tint.
// The level of detail comes from how fast the reflected direction turns
// across each 2x2 quad of pixels, so a curved mirror reads the cube's
// smaller mip levels where the reflection is minified; `blur` adds levels,
// for a duller look (not a physically prefiltered glossy one).
//
//     r      = reflect(normalize(p - eye), normalize(n))
//     colour = tint * environment(r),  alpha = 1
#include <facet/shader.hpp>

namespace {

using namespace facet::sdk;

struct Mirror {
    static constexpr const char* name = "mirror";
    static constexpr const char* version = "1.0";
    static constexpr uint32_t needs =
        FACET_NEED_NORMALS | FACET_NEED_TEXTURES | FACET_NEED_DERIVATIVES;

    FACET_VARYINGS((Vec3, position),  // world space
                   (Vec3, normal))    // world space, unit at the vertices
    FACET_PARAMS((cube, environment, srgb, "the cube map it reflects (six faces, or equirectangular)"),
                 (color3, tint, {1.0f, 1.0f, 1.0f}, "linear RGB the reflection is multiplied by"),
                 (float1, blur, 0.0f, 0.0f, 16.0f, "mip levels added to the reflection's"))

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, Vec4& clip) {
        const Vec4 world = d.model() * Vec4(in.position, 1.0f);
        clip = d.view_projection() * world;
        return {xyz(world), normalize(d.normal_matrix() * in.normal)};
    }

    static Vec4 fragment(const Varyings& v, Fragment& f, const Draw& d, const Params& p) {
        const Vec3 view = normalize(v.position - d.camera_position());
        const Vec3 r = reflect(view, normalize(v.normal));
        return {p.tint * rgb(f.sample_cube(p.environment, r, p.blur)), splat(1.0f)};
    }
};

}  // namespace

FACET_SHADER(Mirror)
