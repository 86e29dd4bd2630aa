// Fuzz target: the scene loader, load_scene() (core/src/assets/scene.cpp,
// yaml_util.cpp, and through it the material, mesh and texture loaders),
// then one tiny render of each scene it accepts (core/src/frame/renderer.cpp,
// shadow.cpp, ao.cpp and the pipeline).
//
// The input is a scene file, written to configs/scenes/ in the sandbox
// (support.hpp), so the repository scenes' relative paths
// (../materials/x.yaml, ../../assets/...) resolve, to small stand-ins.
//
// Checks:
//  - load_scene() returns a scene or throws facet::Error naming a file; any
//    other exception is a finding;
//  - a scene that loaded keeps the rules scene.hpp states: size, MSAA,
//    shadow map size and sub-pixel bits in range, a usable camera, light
//    directions of unit length, rotations of unit length, non-zero scales,
//    valid meshes, and materials bound as material_yaml checks them;
//  - it renders at no more than 16x12 pixels (shadow maps at 64x64) without
//    throwing, and every triangle in ends in exactly one outcome.
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/framebuffer.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <algorithm>
#include <cmath>

namespace facet::fuzz {

namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool unit(float length) { return std::abs(length - 1.0f) < 1e-3f; }

void check_settings(const RenderSettings& s) {
    check(s.width >= 1 && s.width <= Framebuffer::kMaxSize && s.height >= 1 &&
              s.height <= Framebuffer::kMaxSize,
          "render size out of range");
    check(s.msaa == 1 || s.msaa == 2 || s.msaa == 4 || s.msaa == 8, "msaa out of range");
    check(s.shadow_map_size >= 16 && s.shadow_map_size <= 8192, "shadow_map_size out of range");
    check(s.subpixel_bits >= 1 && s.subpixel_bits <= 8, "subpixel_bits out of range");
}

void check_camera(const Camera& c) {
    check(finite(c.position) && finite(c.target) && finite(c.up), "camera vectors not finite");
    check(c.near > 0.0f && c.far > c.near, "camera near/far out of range");
    check(c.fov_y > 0.0f && c.fov_y < 180.0f && c.ortho_height > 0.0f,
          "camera field of view out of range");
}

void check_light(const Light& l) {
    check(finite(l.direction) && unit(glm::length(l.direction)),
          "a light's direction is not of unit length (scene.hpp: normalised by the loader)");
    check(l.color.r >= 0.0f && l.color.g >= 0.0f && l.color.b >= 0.0f && l.intensity >= 0.0f &&
              l.range >= 0.0f,
          "a light's colour, intensity or range is negative");
    check(l.spot_inner >= 0.0f && l.spot_inner <= l.spot_outer && l.spot_outer <= 90.0f,
          "a light's spot angles are out of range");
}

void check_object(const Object& o) {
    check(o.mesh != nullptr, "object '" + o.name + "' has no mesh");
    for (size_t i = 0; i < o.mesh->part_count(); ++i)
        check(o.material_of(i) != nullptr,
              "object '" + o.name + "': part " + std::to_string(i) + " has no material");
    try {
        validate_mesh(*o.mesh);
    } catch (const Error& e) {
        fail("object '" + o.name + "' has an invalid mesh: " + e.what());
    }
    check(unit(glm::length(o.transform.rotation)),
          "object '" + o.name + "' has a rotation that is not of unit length");
    const glm::vec3& s = o.transform.scale;
    check(finite(s) && s.x != 0.0f && s.y != 0.0f && s.z != 0.0f,
          "object '" + o.name + "' has a zero or non-finite scale");
    for (const Material* m : o.materials()) check_bound(*m);
}

// Renders `scene` small; FrameStats says each triangle has one outcome.
void render_small(Scene scene) {
    RenderSettings& s = scene.settings;
    s.width = std::min(s.width, 16);
    s.height = std::min(s.height, 12);
    s.shadow_map_size = std::min(s.shadow_map_size, 64);
    Renderer renderer(1);
    Framebuffer target;
    FrameStats stats;
    try {
        stats = renderer.render(scene, target);
    } catch (const std::exception& e) {
        fail("rendering a scene that loaded threw " + describe(e));
    }
    check(stats.triangles_in == stats.triangles_culled_frustum + stats.triangles_culled_backface +
                                    stats.triangles_culled_degenerate + stats.triangles_invalid +
                                    stats.triangles_rasterized,
          "the frame's triangle outcomes do not add up to the triangles in");
}

}  // namespace

void scene_yaml(const uint8_t* data, size_t size) {
    const InputFile input(sandbox() / "configs" / "scenes" / "fuzz-input.yaml", data, size);
    PluginRegistry registry{std::vector<std::filesystem::path>{}};
    add_shaders(registry);
    Scene scene;
    try {
        scene = load_scene(input.path(), registry);
    } catch (const Error& e) {
        check(!e.file().empty(), std::string("an error names no file: ") + e.what());
        return;
    } catch (const std::exception& e) {
        unexpected("load_scene", e);
    }
    check_settings(scene.settings);
    check_camera(scene.camera);
    for (const Light& l : scene.lights) check_light(l);
    for (const Object& o : scene.objects) check_object(o);
    for (const auto& folder : scene.plugin_paths)
        check(folder.is_absolute(), "a plugin path is not absolute");
    render_small(std::move(scene));
}

}  // namespace facet::fuzz
