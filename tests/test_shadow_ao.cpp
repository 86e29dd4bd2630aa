// Shadows and ambient occlusion against the exact ray caster, and the frame
// plan's skips. Scenes are YAML, rendered through the real shadow.so / ao.so.
#include "frame/shadow.hpp"
#include "pipeline/ao_frame.hpp"
#include "pipeline/bin.hpp"
#include "pipeline/kernels.hpp"
#include "pipeline/shadow_rows.hpp"
#include "reference/raycast.hpp"
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/frame_report.hpp>
#include <facet/framebuffer.hpp>
#include <facet/math.hpp>
#include <facet/plugin.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/lighting.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

using namespace facet;
namespace fs = std::filesystem;

namespace {

// A scene folder with a ground plane (ground.obj, 12 units square at y = 0)
// and the template's unit cube (cube.obj).
struct ShadowAoDir : test::SceneDir {
    ShadowAoDir() : test::SceneDir("shadow-ao") {
        folder.write("ground.obj", "v -6 0 -6\nv 6 0 -6\nv 6 0 6\nv -6 0 6\nvn 0 1 0\n"
                                   "f 1//1 3//1 2//1\nf 1//1 4//1 3//1\n");
        fs::copy_file(fs::path(FACET_SOURCE_DIR) / "plugins/template/cube.obj", dir / "cube.obj");
    }
};

// Material that shows only the light (white, no ambient): its colour is
// n.l times the light's visibility.
const char* kShadowed =
    "{shader: shadow, params: {base_color: [1, 1, 1, 1], ambient: [0, 0, 0], pcf_kernel: 1}}";
// Material that shows only the ambient visibility (white, ambient 1, AO).
const char* kAoOnly =
    "{shader: ao, params: {base_color: [1, 1, 1, 1], ambient: [1, 1, 1], strength: 1}}";

std::string camera(int w, int h) {
    return "camera: {position: [3, 3.5, 4.5], target: [0, 0.2, 0], fov_y: 45}\n"
           "render: {size: [" + std::to_string(w) + ", " + std::to_string(h) +
           "], shadow_map_size: 1024, color_format: rgba32f, ao_radius: 0.5, ao_samples: 16}\n";
}


// Inside a spot light's full-intensity cone (directional lights: everywhere).
bool in_inner_cone(const Light& l, const glm::dvec3& p) {
    if (l.type != LightType::spot) return true;
    const glm::dvec3 to_p = glm::normalize(p - glm::dvec3(l.position));
    return glm::dot(to_p, glm::normalize(glm::dvec3(l.direction))) >
           std::cos(glm::radians(double(l.spot_inner)));
}

// Renders a cube over the ground in `material`, which shows only the light
// (zero exactly where it is blocked), lit by `light` alone, and requires
// every ground pixel away from the penumbra to be lit or dark as the ray
// caster's hard shadow says.
void check_hard_shadows(const std::string& material, const std::string& light) {
    ShadowAoDir sd;
    const Scene scene = sd.load(camera(200, 150) + "lights: [" + light + "]\nobjects:\n" +
                                "  - {mesh: ground.obj, material: " + material + "}\n" +
                                "  - {mesh: cube.obj, position: [0, 0.8, 0], material: " +
                                material + "}\n");
    Framebuffer fb;
    const FrameStats stats = Renderer().render(scene, fb);
    CHECK(stats.shadow_passes == (scene.lights[0].type == LightType::point ? 6u : 1u));
    const reference::RayCaster rc(scene);
    const Light& l = scene.lights[0];
    int lit = 0, dark = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) {
            const auto hit = rc.camera_hit(scene, x + 0.5, y + 0.5);
            if (!hit || hit->object != 0) continue;       // ground only
            if (!in_inner_cone(l, hit->point)) continue;  // the cone, not a shadow, darkens
            const bool truth = rc.lit(l, hit->point, hit->normal);
            // Skip the penumbra band: a neighbour a pixel away disagrees.
            bool edge = false;
            for (auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
                const auto n = rc.camera_hit(scene, x + 0.5 + dx, y + 0.5 + dy);
                edge |= !n || n->object != 0 || rc.lit(l, n->point, n->normal) != truth;
            }
            if (edge) continue;
            // Lit ground shows n.l times the spot cone; shadow shows 0.
            REQUIRE((fb.pixel(x, y).r > 0.02f) == truth);
            (truth ? lit : dark) += 1;
        }
    CHECK(lit > 500);
    CHECK(dark > 200);
}

const char* const kDirectional =
    "{type: directional, direction: [0.7, -1, 0.5], color: [1, 1, 1], intensity: 1, "
    "casts_shadow: true}";
const char* const kSpot =
    "{type: spot, position: [1.2, 3.2, 1.0], direction: [-0.35, -1, -0.3], color: [1, 1, 1], "
    "intensity: 1, spot_inner: 40, spot_outer: 45, casts_shadow: true}";
// Above a corner of the cube: the ground around it falls in five of the cube
// map's faces.
const char* const kPoint =
    "{type: point, position: [0.9, 2.4, 0.7], color: [1, 1, 1], intensity: 1, "
    "casts_shadow: true, shadow_map_size: 512}";

}  // namespace

TEST_CASE("shadow maps classify lit and shadowed points as the ray caster does",
          "[shadow]") {
    for (const char* light : {kDirectional, kSpot, kPoint}) {
        INFO(light);
        check_hard_shadows(kShadowed, light);
    }
}

TEST_CASE("a plane facing the light shows no acne, at any angle and kernel", "[shadow]") {
    for (double degrees : {0.0, 30.0, 60.0, 75.0, 80.0})
        for (int kernel : {1, 3, 5, 9}) {
            INFO(degrees << " degrees, kernel " << kernel);
            const double a = glm::radians(degrees);
            ShadowAoDir sd;
            const std::string dir = "[" + std::to_string(-std::sin(a)) + ", " +
                                    std::to_string(-std::cos(a)) + ", 0]";
            const std::string material =
                "{shader: shadow, params: {base_color: [1, 1, 1, 1], ambient: [0, 0, 0], "
                "pcf_kernel: " + std::to_string(kernel) + "}}";
            const Scene scene = sd.load(
                camera(128, 96) + "lights: [{type: directional, direction: " + dir +
                ", intensity: 1, casts_shadow: true}]\nobjects:\n  - {mesh: ground.obj, " +
                "material: " + material + "}\n");
            Framebuffer fb;
            Renderer().render(scene, fb);
            const float expected = float(std::cos(a));  // n.l, fully lit
            int checked = 0;
            for (int y = 0; y < fb.height(); ++y)
                for (int x = 0; x < fb.width(); ++x) {
                    if (fb.depth_at(x, y) == 0.0f) continue;  // sky
                    REQUIRE(fb.pixel(x, y).r == Approx(expected).epsilon(1e-4));
                    ++checked;
                }
            CHECK(checked > 3000);
        }
}

TEST_CASE("ambient occlusion: an open plane is unoccluded", "[ao]") {
    const std::string resolution = GENERATE(std::string("full"), std::string("half"));
    const bool orthographic = GENERATE(false, true);
    INFO("ao_resolution " << resolution << (orthographic ? ", orthographic" : ", perspective"));
    ShadowAoDir sd;
    Scene scene = sd.load(camera(160, 120) + "objects:\n  - {mesh: ground.obj, material: " +
                          kAoOnly + "}\n");
    scene.settings.ao_half_resolution = resolution == "half";
    scene.camera.orthographic = orthographic;
    scene.camera.ortho_height = 9.0f;  // the plane's far edge in view, as in perspective
    Framebuffer fb;
    const FrameStats stats = Renderer().render(scene, fb);
    CHECK(stats.depth_prepasses == 1);  // the frame's, which it reads
    CHECK(stats.prepasses == 0);        // ... rather than one of its own
    CHECK(stats.ao_passes == 1);
    CHECK(stats.fragments_depth_only > 5000);  // the AO pre-pass calls no shader
    double sum = 0, low = 1;
    int n = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) {
            if (fb.depth_at(x, y) == 0.0f) continue;
            sum += fb.pixel(x, y).r;
            low = std::min(low, double(fb.pixel(x, y).r));
            ++n;
        }
    CHECK(n > 5000);
    CHECK(sum / n > 0.995);
    CHECK(low > 0.95);
}

// A room's corner, 192x144: the floor and two walls (cubes stretched into
// slabs) meeting at the origin, all in the AO-only material, with the given
// extra render settings.
static std::string room_corner(const std::string& render) {
    const std::string wall = std::string(", material: ") + kAoOnly + "}\n";
    return "camera: {position: [2.6, 1.9, 2.6], target: [0, 0.4, 0], fov_y: 50}\n"
           "render: {size: [192, 144], color_format: rgba32f, " + render + "}\nobjects:\n"
           "  - {mesh: ground.obj" + wall +
           "  - {mesh: cube.obj, position: [-0.05, 1.5, 1.5], scale: [0.1, 3, 3]" + wall +
           "  - {mesh: cube.obj, position: [1.5, 1.5, -0.05], scale: [3, 3, 0.1]" + wall;
}

TEST_CASE("ambient occlusion: the inside corner of a box is darker than its faces, and "
          "SSAO agrees with ray-traced AO",
          "[ao]") {
    // Inside a room corner: the floor and two walls (cubes stretched into
    // slabs). At half resolution too, where the depth-aware upsample must
    // keep each wall's occlusion off the others.
    const std::string resolution = GENERATE(std::string("full"), std::string("half"));
    INFO("ao_resolution " << resolution);
    ShadowAoDir sd;
    const Scene scene = sd.load(room_corner("ao_resolution: " + resolution));
    Framebuffer fb;
    Renderer().render(scene, fb);
    const reference::RayCaster rc(scene);
    double corner = 0, open = 0, sq_err = 0;
    int n_corner = 0, n_open = 0, n = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) {
            const auto hit = rc.camera_hit(scene, x + 0.5, y + 0.5);
            if (!hit) continue;
            const double ssao = fb.pixel(x, y).r;
            const double truth = rc.ambient_visibility(hit->point, hit->normal, 0.5, 256);
            sq_err += (ssao - truth) * (ssao - truth);
            ++n;
            const glm::dvec3 p = hit->point;
            // Distance to the corner's three edges (the planes' meeting lines).
            const double to_edge = std::min({glm::length(glm::dvec2(p.x, p.y)),
                                             glm::length(glm::dvec2(p.y, p.z)),
                                             glm::length(glm::dvec2(p.x, p.z))});
            if (to_edge < 0.1) corner += ssao, ++n_corner;
            if (to_edge > 1.0) open += ssao, ++n_open;
        }
    REQUIRE(n_corner > 50);
    REQUIRE(n_open > 500);
    const double rmse = std::sqrt(sq_err / n);
    INFO("corner " << corner / n_corner << ", open " << open / n_open << ", RMSE " << rmse);
    CHECK(corner / n_corner < open / n_open - 0.2);
    CHECK(rmse < 0.08);  // stated tolerance: SSAO vs ray-traced AO (radius 0.5, 256 rays)
}

TEST_CASE("the AO pass reaches as far as render: ao_radius says, for every AO material",
          "[ao]") {
    // The same room corner with a short and a long reach: near the corner's
    // edges, ambient visibility must fall as the radius grows.
    ShadowAoDir sd;
    auto corner_visibility = [&](const char* radius) {
        const Scene scene = sd.load(room_corner("ao_samples: 8, ao_radius: " + std::string(radius)));
        Framebuffer fb;
        Renderer().render(scene, fb);
        const reference::RayCaster rc(scene);
        double sum = 0;
        int n = 0;
        for (int y = 0; y < fb.height(); ++y)
            for (int x = 0; x < fb.width(); ++x) {
                const auto hit = rc.camera_hit(scene, x + 0.5, y + 0.5);
                if (!hit) continue;
                const glm::dvec3 p = hit->point;
                const double to_edge = std::min({glm::length(glm::dvec2(p.x, p.y)),
                                                 glm::length(glm::dvec2(p.y, p.z)),
                                                 glm::length(glm::dvec2(p.x, p.z))});
                if (to_edge < 0.2) sum += fb.pixel(x, y).r, ++n;
            }
        REQUIRE(n > 100);
        return sum / n;
    };
    const double short_reach = corner_visibility("0.02"), long_reach = corner_visibility("0.5");
    INFO("visibility near the corner: radius 0.02 " << short_reach << ", radius 0.5 "
                                                    << long_reach);
    CHECK(short_reach > long_reach + 0.08);  // the same image if the setting were ignored
}

TEST_CASE("the frame plan runs shadow, pre-pass and AO passes only when a visible material "
          "needs them",
          "[shadow][ao][skip]") {
    ShadowAoDir sd;
    const std::string lights =
        "lights: [{type: directional, direction: [0, -1, 0], casts_shadow: true},\n"
        "         {type: spot, position: [0, 3, 0], direction: [0, -1, 0], casts_shadow: true},\n"
        "         {type: point, position: [1, 2, 0], casts_shadow: true},\n"
        "         {type: directional, direction: [1, -1, 0]}]\n";
    auto stats_for = [&](const std::string& objects) {
        Framebuffer fb;
        return Renderer().render(sd.load(camera(64, 48) + lights + "objects:\n" + objects), fb);
    };
    const std::string unlit = "  - {mesh: ground.obj, material: {shader: unlit}}\n";
    const FrameStats plain = stats_for(unlit);
    CHECK(plain.shadow_passes == 0);
    CHECK(plain.prepasses + plain.depth_prepasses == 0);
    CHECK(plain.ao_passes == 0);
    const FrameStats shadowed =
        stats_for(unlit + "  - {mesh: cube.obj, material: " + kShadowed + "}\n");
    CHECK(shadowed.shadow_passes == 8);  // directional, spot and the point light's six faces
    CHECK(shadowed.ao_passes == 0);
    const FrameStats hidden = stats_for(
        unlit + "  - {mesh: cube.obj, visible: false, material: " + kShadowed + "}\n" +
        "  - {mesh: cube.obj, position: [0, 0, 80], material: " + kAoOnly + "}\n");  // culled
    CHECK(hidden.shadow_passes == 0);
    CHECK(hidden.prepasses + hidden.depth_prepasses == 0);
    CHECK(hidden.ao_passes == 0);
    CHECK(hidden.objects_culled == 1);
    const FrameStats ao = stats_for(unlit + "  - {mesh: cube.obj, material: " + kAoOnly + "}\n");
    CHECK(ao.depth_prepasses == 1);
    CHECK(ao.prepasses == 0);
    CHECK(ao.ao_passes == 1);
    CHECK(ao.shadow_passes == 0);

    // The render settings switch the passes off (the viewer's keys do).
    Scene both = sd.load(camera(64, 48) + lights + "objects:\n" + unlit +
                         "  - {mesh: cube.obj, material: " + kShadowed + "}\n" +
                         "  - {mesh: cube.obj, position: [1, 0, 0], material: " + kAoOnly + "}\n");
    Framebuffer fb;
    Renderer renderer;
    const FrameStats on = renderer.render(both, fb);
    CHECK(on.shadow_passes == 8);
    CHECK(on.ao_passes == 1);
    both.settings.shadows = false;
    const FrameStats no_shadows = renderer.render(both, fb);
    CHECK(no_shadows.shadow_passes == 0);
    CHECK(no_shadows.ao_passes == 1);
    both.settings.ao = false;
    const FrameStats neither = renderer.render(both, fb);
    CHECK(neither.shadow_passes == 0);
    CHECK(neither.prepasses + neither.depth_prepasses == 0);
    CHECK(neither.ao_passes == 0);
}

TEST_CASE("shadow.so and ao.so match Lambert plus ambient where nothing occludes", "[shader]") {
    // A point light (with attenuation) and a directional light over an open
    // plane: the reference evaluates the formula in double precision at the
    // exact surface point of each sampled pixel's centre.
    const char* materials[] = {
        "{shader: shadow, params: {base_color: [0.9, 0.7, 0.5, 1], ambient: [0.05, 0.06, 0.07], "
        "pcf_kernel: 3}}",
        "{shader: ao, params: {base_color: [0.9, 0.7, 0.5, 1], ambient: [0.05, 0.06, 0.07], "
        "strength: 0}}"};
    for (const char* material : materials) {
        INFO(material);
        ShadowAoDir sd;
        const Scene scene = sd.load(
            camera(120, 90) +
            "lights:\n"
            "  - {type: directional, direction: [-0.3, -1, -0.2], color: [1, 0.9, 0.8], "
            "intensity: 0.6, casts_shadow: true}\n"
            "  - {type: point, position: [0.5, 1.2, 0.8], color: [0.5, 0.7, 1], intensity: 1.5, "
            "attenuation: [1, 0.3, 0.6]}\n"
            "objects:\n  - {mesh: ground.obj, material: " + material + "}\n");
        Framebuffer fb;
        Renderer().render(scene, fb);
        const reference::RayCaster rc(scene);
        const glm::dvec3 base(0.9, 0.7, 0.5), ambient(0.05, 0.06, 0.07);
        int checked = 0;
        for (int y = 1; y < fb.height(); y += 3)
            for (int x = 1; x < fb.width(); x += 3) {
                const auto hit = rc.camera_hit(scene, x + 0.5, y + 0.5);
                if (!hit) continue;
                glm::dvec3 light = ambient;
                for (const Light& l : scene.lights) {
                    glm::dvec3 to = -glm::normalize(glm::dvec3(l.direction));
                    double falloff = 1.0;
                    if (l.type == LightType::point) {
                        const glm::dvec3 offset = glm::dvec3(l.position) - hit->point;
                        const double d = glm::length(offset);
                        to = offset / d;
                        falloff = 1.0 / (l.attenuation.x + l.attenuation.y * d +
                                         l.attenuation.z * d * d);
                    }
                    light += glm::dvec3(l.color) * double(l.intensity) * falloff *
                             std::max(glm::dot(hit->normal, to), 0.0);
                }
                const glm::dvec3 expected = base * light;
                for (int c = 0; c < 3; ++c)
                    REQUIRE(std::abs(int(linear_to_srgb8(fb.pixel(x, y)[c])) -
                                     int(linear_to_srgb8(float(expected[c])))) <= 1);
                ++checked;
            }
        CHECK(checked > 500);
    }
}

TEST_CASE("two shadow-casting lights each cast their own shadow in one frame", "[shadow]") {
    // A directional light and a spot light, both casting: each ground pixel
    // shows the sum of n.l over the lights that the ray caster says it sees.
    ShadowAoDir sd;
    const Scene scene = sd.load(
        camera(200, 150) +
        "lights:\n"
        "  - {type: directional, direction: [0.7, -1, 0.5], intensity: 0.5, casts_shadow: true}\n"
        "  - {type: spot, position: [-1.0, 3.2, 1.2], direction: [0.3, -1, -0.35], "
        "intensity: 0.5, spot_inner: 40, spot_outer: 45, casts_shadow: true}\n"
        "objects:\n  - {mesh: ground.obj, material: " + std::string(kShadowed) + "}\n" +
        "  - {mesh: cube.obj, position: [0, 0.8, 0], material: " + kShadowed + "}\n");
    Framebuffer fb;
    REQUIRE(Renderer().render(scene, fb).shadow_passes == 2);
    const reference::RayCaster rc(scene);
    int shadowed_by[2] = {0, 0};
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) {
            const auto hit = rc.camera_hit(scene, x + 0.5, y + 0.5);
            if (!hit || hit->object != 0 || !in_inner_cone(scene.lights[1], hit->point)) continue;
            double expected = 0;
            bool edge = false;
            for (size_t l = 0; l < 2; ++l) {
                const Light& light = scene.lights[l];
                const bool lit = rc.lit(light, hit->point, hit->normal);
                for (auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
                    const auto n = rc.camera_hit(scene, x + 0.5 + dx, y + 0.5 + dy);
                    edge |= !n || n->object != 0 || rc.lit(light, n->point, n->normal) != lit;
                }
                const glm::dvec3 to = light.type == LightType::spot
                                          ? glm::normalize(glm::dvec3(light.position) - hit->point)
                                          : -glm::normalize(glm::dvec3(light.direction));
                expected += lit ? 0.5 * std::max(to.y, 0.0) : 0.0;
                shadowed_by[l] += !lit;
            }
            if (edge) continue;
            REQUIRE(fb.pixel(x, y).r == Approx(expected).margin(2e-3));
        }
    CHECK(shadowed_by[0] > 100);
    CHECK(shadowed_by[1] > 100);
}

TEST_CASE("a shadow map is drawn again only when its casters, its light or its fitted bounds "
          "change, and never shows a stale map",
          "[shadow][skip]") {
    ShadowAoDir sd;
    Scene scene = sd.load(
        camera(96, 72) +
        "lights:\n"
        "  - {type: directional, direction: [0.7, -1, 0.5], intensity: 0.5, casts_shadow: true}\n"
        "  - {type: spot, position: [-1.0, 3.2, 1.2], direction: [0.3, -1, -0.35], "
        "intensity: 0.5, spot_inner: 25, spot_outer: 30, casts_shadow: true}\n"
        "objects:\n  - {mesh: ground.obj, material: " + std::string(kShadowed) + "}\n" +
        "  - {name: cube, mesh: cube.obj, position: [0, 0.8, 0], material: " + kShadowed + "}\n" +
        // Behind the camera and outside the spot's cone: no map can see it.
        "  - {name: far, mesh: cube.obj, position: [9, 9, 12], material: " + kShadowed + "}\n");
    Renderer renderer(2);
    Framebuffer fb;
    // Each frame of `renderer` against a renderer that has never drawn a map.
    auto frame = [&](uint64_t drawn, uint64_t reused) {
        const FrameStats s = renderer.render(scene, fb);
        CHECK(s.shadow_passes == drawn);
        CHECK(s.shadow_maps_reused == reused);
        Framebuffer fresh;
        Renderer(1).render(scene, fresh);
        CHECK(test::same_image(fb, fresh));
        return s;
    };
    const FrameStats first = frame(2, 0);
    CHECK(first.fragments_depth_only > 1000);  // the maps, drawn with no shader call
    // Neither map sees the far cube: it is outside the spot's cone, and
    // across the sun's light outside the view, which the sun's map is
    // fitted to.
    CHECK(first.shadow_casters_culled == 2);
    SECTION("nothing changed: no map is drawn") {
        CHECK(frame(0, 2).fragments_depth_only == 0);
        frame(0, 2);
    }
    SECTION("a caster moved: both maps see it") {
        frame(0, 2);  // kept: the filters' planes are made (ABI 1.6) ...
        scene.objects[1].transform.translation.x += 0.3f;
        frame(2, 0);  // ... and dropped with the maps they bound
        frame(0, 2);
    }
    SECTION("a caster got a new mesh, equal to the old one: drawn again, to be safe") {
        scene.objects[1].mesh = std::make_shared<Mesh>(*scene.objects[1].mesh);
        frame(2, 0);
    }
    SECTION("the spot light turned: its map only") {
        scene.lights[1].direction.x += 0.05f;
        frame(1, 1);
    }
    SECTION("the light's colour changed: no map") {
        scene.lights[1].intensity = 0.7f;
        frame(0, 2);
    }
    SECTION("the camera moved: the directional map's fitted bounds changed") {
        scene.camera.position.x += 0.2f;
        frame(1, 1);
    }
    SECTION("the map size changed") {
        scene.settings.shadow_map_size = 512;
        frame(2, 0);
    }
    SECTION("shadows off, then on: the kept maps are still good") {
        scene.settings.shadows = false;
        frame(0, 0);
        scene.settings.shadows = true;
        frame(0, 2);
    }
}

TEST_CASE("a directional or spot map that takes over a cube face's slot reads as nothing drawn "
          "past its edge",
          "[shadow][skip]") {
    // A point light inside a box: each cube face is drawn with a margin as
    // wide as the distances' border, and the box fills it. Then the same
    // slots hold a spot light's map, then a directional one's, of the same
    // size: their border must read 65535 (nothing drawn, so lit), not the
    // face's distances, whichever slot a filter kernel reaches past the
    // map's edge through.
    ShadowAoDir sd;
    const std::string box = "objects:\n  - {mesh: cube.obj, scale: 4, material: " +
                            std::string(kShadowed) + "}\n";
    const std::string point = "lights: [{type: point, position: [0, 0, 0], casts_shadow: true, "
                              "shadow_map_size: 64}]\n";
    const std::string spot = "lights: [{type: spot, position: [0, 0, 0], direction: [0, -1, 0], "
                             "casts_shadow: true, shadow_map_size: 64}]\n";
    const std::string sun = "lights: [{type: directional, direction: [0.2, -1, 0.1], "
                            "casts_shadow: true, shadow_map_size: 64}]\n";
    Pipeline pipeline(2);
    ShadowMaps maps;
    FrameStats stats;
    // The texels of slot 0 past the map's edge that hold `value`, and all
    // of them.
    const auto border = [&](uint16_t value) {
        const std::vector<uint16_t>& texels = maps.distance_texels.at(0);
        constexpr int b = FACET_SHADOW_BORDER;
        const int size = 64, stride = int(maps.distance_texels.at(0).size()) / (size + 2 * b);
        int count = 0, all = 0;
        for (int y = 0; y < size + 2 * b; ++y)
            for (int x = 0; x < size + 2 * b; ++x) {
                if (y >= b && y < size + b && x >= b && x < size + b) continue;  // the map
                count += texels[size_t(y) * size_t(stride) + size_t(x)] == value;
                ++all;
            }
        return std::pair(count, all);
    };
    const auto draw = [&](const std::string& lights) {
        const Scene scene = sd.load(camera(32, 24) + lights + box);
        std::vector<DrawItem> casters;
        for (const Object& o : scene.objects) add_draw_items(o, casters);
        render_shadow_maps(scene, casters, pipeline, maps, stats);
    };
    draw(point);
    REQUIRE(maps.faces.size() == 6);
    REQUIRE(maps.by_light[0].map_count == 6);
    const auto [face_far, face_all] = border(65535);
    REQUIRE(face_all > 0);
    REQUIRE(face_far < face_all / 2);  // the face drew the box into its margin
    for (const std::string& lights : {spot, point, sun}) {
        INFO(lights);
        draw(lights);
        if (lights == point) {  // back to a face, to be taken over again
            REQUIRE(border(65535).first < face_all / 2);
            continue;
        }
        REQUIRE(maps.faces.size() == 1);
        REQUIRE(maps.by_light[0].maps == &maps.faces[0]);
        REQUIRE(maps.faces[0].width == 64);
        const auto [far, all] = border(65535);
        CHECK(far == all);
    }
}

TEST_CASE("the frame report says which passes ran, which were skipped and why, and the early "
          "depth test's count, as the frame's statistics have them",
          "[shadow][skip][report]") {
    ShadowAoDir sd;
    Scene scene = sd.load(
        camera(96, 72) +
        "lights:\n"
        "  - {type: directional, direction: [0.7, -1, 0.5], intensity: 0.5, casts_shadow: true}\n"
        "objects:\n  - {mesh: ground.obj, material: " + std::string(kShadowed) + "}\n" +
        "  - {name: cube, mesh: cube.obj, position: [0, 0.8, 0], material: " + kShadowed + "}\n" +
        "  - {name: behind, mesh: cube.obj, position: [0, 0.8, -1.5], material: " + kShadowed +
        "}\n" +
        "  - {name: far, mesh: cube.obj, position: [9, 9, 12], material: " + kShadowed + "}\n");
    Renderer renderer(2);
    Framebuffer fb;
    const auto has = [](const std::vector<std::string>& parts, const std::string& part) {
        return std::find(parts.begin(), parts.end(), part) != parts.end();
    };
    const FrameStats first = renderer.render(scene, fb);
    const std::vector<std::string> ran = passes_run(first);
    REQUIRE(ran.size() == 1);
    CHECK(ran[0].rfind("1 shadow map ", 0) == 0);
    std::vector<std::string> skipped = work_skipped(first, scene.settings, Counts::full);
    CHECK(has(skipped, "AO (not needed)"));
    CHECK(has(skipped, "1 object out of view"));
    // The cube behind the first hides part of itself from the early depth test.
    REQUIRE(first.fragments_depth_rejected > 0);
    CHECK(has(skipped, std::to_string(first.fragments_depth_rejected) +
                           " fragments hidden (early depth test)"));
    CHECK(has(skipped, std::to_string(first.fragments_depth_only) +
                           " depth-only fragments (no shader)"));
    CHECK_FALSE(has(skipped, "shadow maps (off)"));

    // Nothing moved: the map is kept, and no pass ran.
    const FrameStats second = renderer.render(scene, fb);
    CHECK(passes_run(second).empty());
    skipped = work_skipped(second, scene.settings, Counts::full);
    CHECK(has(skipped, "1 shadow map unchanged"));
    CHECK_FALSE(has(skipped, "shadow maps (not needed)"));

    scene.settings.shadows = false;
    const FrameStats off = renderer.render(scene, fb);
    CHECK(has(work_skipped(off, scene.settings, Counts::full), "shadow maps (off)"));
    CHECK(off.draws_redrawn == 0);

    // With a depth pre-pass, the main pass shades the pre-pass's triangles.
    scene.settings.depth_prepass = true;
    const FrameStats prepassed = renderer.render(scene, fb);
    CHECK(prepassed.draws_redrawn == 3);  // the ground and two cubes: the far one is out of view
    CHECK(has(work_skipped(prepassed, scene.settings, Counts::full),
              "3 draws on the pre-pass's triangles (no vertex stage or setup)"));
    scene.settings.depth_prepass = false;

    // No material asks for shadows: not needed, whatever the settings say.
    scene.settings.shadows = true;
    for (Object& o : scene.objects) o.visible = o.name == "far";
    const FrameStats none = renderer.render(scene, fb);
    CHECK(has(work_skipped(none, scene.settings, Counts::full), "shadow maps (not needed)"));
    CHECK(count_text(12'345'678, Counts::short_form) == "12.3M");
    CHECK(count_text(12'345'678, Counts::full) == "12345678");
}

// ---- 16-bit distance maps ---------------------------------------------------

namespace {

// A square map of `size` texels of 16-bit distances, with its border,
// every texel `fill` (the border 65535).
struct DistanceMap {
    int size;
    std::vector<uint16_t> texels;
    const uint16_t* first = nullptr;  // texel (0, 0)
    uint32_t stride = 0;
    DistanceMap(int size_, uint16_t fill) : size(size_) {
        stride = uint32_t(size + 2 * FACET_SHADOW_BORDER);
        texels.assign(size_t(stride) * size_t(stride), uint16_t(65535));
        first = texels.data() + FACET_SHADOW_BORDER * (stride + 1);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) at(x, y) = fill;
    }
    uint16_t& at(int x, int y) {
        return texels[size_t(y + FACET_SHADOW_BORDER) * stride + size_t(x + FACET_SHADOW_BORDER)];
    }
    // Map `sm` holding these texels, and the planes `tiles` if given.
    facet_shadow_map over(facet_shadow_map sm, const float* tiles = nullptr,
                          uint32_t tile_stride = 0) const {
        sm.texels = first, sm.stride = stride;
        sm.tiles = tiles, sm.tile_stride = tile_stride;
        return sm;
    }
};

facet_shadow_map map_header(int size, uint32_t projection, const glm::mat4& vp) {
    facet_shadow_map sm{};
    sm.projection = projection;
    sm.width = sm.height = uint32_t(size);
    sm.near_plane = 0.5f;
    sm.far_plane = 8.0f;
    sm.texel_size = projection == FACET_SHADOW_ORTHOGRAPHIC ? 4.0f / float(size)
                                                           : 2.0f * std::tan(glm::radians(30.0f)) / float(size);
    std::memcpy(sm.view_projection, &vp[0][0], sizeof sm.view_projection);
    return sm;
}

// The lanes of a wide call, from scalar values.
sdk::wide::Float lanes(const std::vector<float>& v, size_t first) {
    sdk::wide::Float f;
    for (int i = 0; i < sdk::wide::kLanes; ++i) f[i] = v[first + size_t(i)];
    return f;
}

// The reference the SDK's filter (facet/shadows.hpp) is held to: the same
// percentage-closer filter, plain code a receiver at a time.
namespace pcf_reference {

// A tap is lit where the stored distance is at least its threshold: the
// tap's distance (in the map's units of 1/65535 of near..far) rounded up,
// within 0..65535 (in front of the near plane everything is lit; at or
// past the far plane, and for NaN, only where nothing was drawn).
int32_t tap_threshold(float q) {
    if (!(q == q)) return 65535;
    return int32_t(std::ceil(std::clamp(q, 0.0f, 65535.0f)));
}

// The tap's distance q within 0..65535 (65535 for NaN), unrounded: a
// stored distance (a whole number) at least this is at least the tap's
// threshold, and one below it below the threshold, so that bounds on the
// stored distances are compared with it as they are.
float tap_bound(float q) { return q == q ? std::clamp(q, 0.0f, 65535.0f) : 65535.0f; }

// The lowest and the highest distance a kernel of radius r <=
// FACET_SHADOW_REACH around texel (cx, cy) can read, from the planes of the
// tile that holds (cx, cy): the planes at (cx, cy), moved apart by the most
// they rise or fall r texels away on each axis, and by a quarter unit more
// than float rounding can move them (the ABI bounds the slopes by 2048
// units a texel and the planes by 2^17, so no sum here reaches 2^18, below
// which each rounding is within 1/64).
static_assert(FACET_SHADOW_TILE == 8, "a texel's tile is its coordinates >> 3");
struct Slab {
    float low, high;
};
Slab slab(const facet_shadow_map& g, int cx, int cy, int r) {
    const float* t = g.tiles + 4 * (ptrdiff_t(cy >> 3) * ptrdiff_t(g.tile_stride) + (cx >> 3));
    const float nearest = t[0] + t[1] * float(cx & 7) + t[2] * float(cy & 7);
    const float spread = (std::abs(t[1]) + std::abs(t[2])) * float(r);
    return {nearest - spread - 0.25f, nearest + t[3] + spread + 0.25f};
}

float shadow_visibility(const sdk::ShadowMap& m, glm::vec3 p, float n_dot_l, int kernel,
                        float bias, float slope_bias) {
    const facet_shadow_map& sm = *m.map;
    const float* v = sm.view_projection;  // column-major
    const auto row = [&](int r) {
        return (v[r] * p.x + v[4 + r] * p.y) + (v[8 + r] * p.z + v[12 + r]);
    };
    const float scale = 65535.0f / (sm.far_plane - sm.near_plane);
    float x = row(0), y = row(1), q, texel;  // texel: a texel's world size, in map units
    if (sm.projection == FACET_SHADOW_ORTHOGRAPHIC) {
        q = row(2) * 65535.0f;  // window depth is the distance, 0..1
        texel = sm.texel_size * scale;
    } else {
        const float w = row(3);  // the distance along the light's axis
        if (!(w > 0.0f)) return 1.0f;
        const float inv_w = 1.0f / w;
        x = x * inv_w;
        y = y * inv_w;
        q = (w - sm.near_plane) * scale;
        texel = (sm.texel_size * scale) * w;
    }
    if (!(q <= 65535.0f)) return 1.0f;  // past the far plane
    const float fx = std::floor((x * 0.5f + 0.5f) * float(sm.width));
    const float fy = std::floor((0.5f - y * 0.5f) * float(sm.height));
    if (!(fx >= 0.0f && fx < float(sm.width) && fy >= 0.0f && fy < float(sm.height))) return 1.0f;
    const float cos_t = glm::clamp(n_dot_l, 0.1f, 1.0f);
    const float tan_t = std::sqrt(1.0f - cos_t * cos_t) / cos_t;
    const float receiver = q - texel * (bias + slope_bias * tan_t);
    const float step = texel * tan_t;  // a tap k texels away sees the receiver k * step deeper
    const int r = std::clamp(kernel, 1, 15) / 2;
    constexpr sdk::detail::TapDistances kTaps{};
    if (sm.tiles && r <= FACET_SHADOW_REACH) {
        // The centre's threshold is the highest and the corners' the lowest:
        // at or above the one every tap is lit; below the other, none is.
        const Slab s = slab(sm, int(fx), int(fy), r);
        if (s.low >= tap_bound(receiver - step * kTaps.at[0][0])) return 1.0f;
        if (s.high < tap_bound(receiver - step * kTaps.at[r][r])) return 0.0f;
    }
    const ptrdiff_t stride = sm.stride;
    const uint16_t* centre = sm.texels + ptrdiff_t(fy) * stride + ptrdiff_t(fx);
    int lit = 0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const int i = std::max(std::abs(dx), std::abs(dy));
            const int j = std::min(std::abs(dx), std::abs(dy));
            const int32_t threshold = tap_threshold(receiver - step * kTaps.at[i][j]);
            lit += int32_t(centre[dy * stride + dx]) >= threshold;
        }
    return float(lit) / float((2 * r + 1) * (2 * r + 1));
}

// The same over a point light's cube map: the face that holds the

}  // namespace pcf_reference

}  // namespace

TEST_CASE("the filters' tap distances are std::sqrt of whole numbers", "[shadow]") {
    constexpr sdk::detail::TapDistances taps{};
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) CHECK(taps.at[i][j] == std::sqrt(float(i * i + j * j)));
}

TEST_CASE("16-bit distance maps: the SDK's filter counts the taps the reference does, which are "
          "those a double-precision reading of the definition lights",
          "[shadow]") {
    // An orthographic and a perspective map over a noisy field of casters,
    // and receivers around their surfaces, at every kernel size.
    const int size = 64;
    const glm::mat4 ortho = glm::mat4(glm::vec4(0.5f, 0, 0, 0), glm::vec4(0, 0.5f, 0, 0),
                                      glm::vec4(0, 0, -1.0f / 7.5f, 0),
                                      glm::vec4(0, 0, -0.5f / 7.5f, 1));
    const glm::mat4 persp = perspective(glm::radians(60.0f), 1.0f, 0.5f, 8.0f, false);
    for (uint32_t projection : {uint32_t(FACET_SHADOW_ORTHOGRAPHIC), uint32_t(FACET_SHADOW_PERSPECTIVE)}) {
        INFO("projection " << projection);
        const facet_shadow_map sm = map_header(size, projection,
                                               projection == FACET_SHADOW_ORTHOGRAPHIC ? ortho : persp);
        DistanceMap dm(size, 0);
        uint32_t seed = 12345;
        const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) dm.at(x, y) = uint16_t(20000 + next() % 4000);
        const facet_shadow_map map = dm.over(sm);
        const sdk::ShadowMap m{&map};
        const float scale = 65535.0f / (sm.far_plane - sm.near_plane);
        // Receivers: points along the light's axis at distances around the
        // casters', spread over the map and a little past its edges.
        const size_t n = 64 * size_t(sdk::wide::kLanes);
        std::vector<float> px(n), py(n), pz(n), nl(n);
        for (size_t i = 0; i < n; ++i) {
            const float u = float(next() % 2200) / 1000.0f - 1.1f, v = float(next() % 2200) / 1000.0f - 1.1f;
            const float distance = sm.near_plane + (20000.0f + float(next() % 4400) - 200.0f) / scale;
            if (projection == FACET_SHADOW_ORTHOGRAPHIC) {  // x = 0.5 px, y = 0.5 py, z = -distance
                px[i] = 2.0f * u, py[i] = 2.0f * v, pz[i] = -distance;
            } else {  // ndc = (x, y) / distance * cot(30 degrees)
                const float t = std::tan(glm::radians(30.0f));
                px[i] = u * distance * t, py[i] = v * distance * t, pz[i] = -distance;
            }
            nl[i] = float(next() % 1000) / 1000.0f;
        }
        for (int kernel = 1; kernel <= 15; kernel += 2) {
            INFO("kernel " << kernel);
            int settled = 0, checked = 0;
            for (size_t first = 0; first < n; first += size_t(sdk::wide::kLanes)) {
                const sdk::wide::Vec3 wp{lanes(px, first), lanes(py, first), lanes(pz, first)};
                const sdk::wide::Float wide =
                    sdk::shadow_visibility(m, wp, lanes(nl, first), kernel, 1.0f, 1.5f);
                for (int l = 0; l < sdk::wide::kLanes; ++l) {
                    const size_t i = first + size_t(l);
                    const glm::vec3 p(px[i], py[i], pz[i]);
                    const float scalar = pcf_reference::shadow_visibility(m, p, nl[i], kernel, 1.0f, 1.5f);
                    REQUIRE(wide[l] == scalar);
                    // The definition in double: the centre texel, and each tap lit
                    // where its stored distance is at least the tap's.
                    const glm::dvec4 c = glm::dmat4(projection == FACET_SHADOW_ORTHOGRAPHIC ? ortho : persp) *
                                         glm::dvec4(glm::dvec3(p), 1.0);
                    const double w = projection == FACET_SHADOW_ORTHOGRAPHIC ? 1.0 : c.w;
                    const double q = projection == FACET_SHADOW_ORTHOGRAPHIC
                                         ? c.z * 65535.0
                                         : (c.w - sm.near_plane) * double(scale);
                    const double fx = std::floor((c.x / w * 0.5 + 0.5) * size);
                    const double fy = std::floor((0.5 - c.y / w * 0.5) * size);
                    ++checked;
                    if (fx < 0 || fy < 0 || fx >= size || fy >= size) {
                        REQUIRE(scalar == 1.0f);
                        continue;
                    }
                    const double cos_t = std::clamp(double(nl[i]), 0.1, 1.0);
                    const double tan_t = std::sqrt(1.0 - cos_t * cos_t) / cos_t;
                    const double texel = double(sm.texel_size) * double(scale) *
                                         (projection == FACET_SHADOW_ORTHOGRAPHIC ? 1.0 : w);
                    // Taps within float rounding of a whole unit may go either way.
                    const int r = kernel / 2;
                    int lit_min = 0, lit_max = 0;
                    for (int dy = -r; dy <= r; ++dy)
                        for (int dx = -r; dx <= r; ++dx) {
                            const double tap = q - texel * (1.0 + 1.5 * tan_t) -
                                               texel * tan_t * std::sqrt(double(dx * dx + dy * dy));
                            const int tx = int(fx) + dx, ty = int(fy) + dy;
                            const bool on_map = tx >= 0 && ty >= 0 && tx < size && ty < size;
                            const double stored = on_map ? double(dm.at(tx, ty)) : 65535.0;
                            lit_min += stored >= std::ceil(std::clamp(tap + 0.01, 0.0, 65535.0));
                            lit_max += stored >= std::ceil(std::clamp(tap - 0.01, 0.0, 65535.0));
                        }
                    const float count = scalar * float(kernel * kernel);
                    REQUIRE(count >= float(lit_min) - 1e-3f);
                    REQUIRE(count <= float(lit_max) + 1e-3f);
                    settled += lit_min == lit_max;
                }
            }
            CHECK(settled > checked / 2);
        }
    }
}

TEST_CASE("16-bit distance maps: the planes that bound them tile by tile hold every texel "
          "within reach on every path, and settle receivers as the taps do",
          "[shadow][isa]") {
    // A lit floor seen at a slant (distances rising across the map), a
    // caster nearer the light over part of it, a corner where nothing was
    // drawn, a tile across a silhouette (a step from 0 to "nothing"), and a
    // little noise; the border reads 65535.
    const int size = 64;
    DistanceMap dm(size, 0);
    uint32_t seed = 99;
    const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const bool caster = x >= 16 && x < 48 && y >= 8 && y < 40;
            const bool empty = (x >= 52 && y >= 52) || (x >= 52 && x < 56 && y < 8);
            const bool step = x >= 48 && x < 52 && y < 8;  // beside empty texels: tile (6, 0)
            dm.at(x, y) = empty    ? uint16_t(65535)
                          : step   ? uint16_t(0)
                          : caster ? uint16_t(12000 + next() % 3)
                                   : uint16_t(20000 + 400 * x + 250 * y + next() % 3);
        }
    const glm::mat4 ortho = glm::mat4(glm::vec4(0.5f, 0, 0, 0), glm::vec4(0, 0.5f, 0, 0),
                                      glm::vec4(0, 0, -1.0f / 7.5f, 0),
                                      glm::vec4(0, 0, -0.5f / 7.5f, 1));
    const facet_shadow_map sm = map_header(size, FACET_SHADOW_ORTHOGRAPHIC, ortho);
    const float scale = 65535.0f / (sm.far_plane - sm.near_plane);
    // Receivers on the floor (lit, or under the caster), and above and below
    // it by up to a few texels' rise (546 units a texel), with any slope to
    // the light; those of a wide call in neighbouring texels, as a block's
    // fragments are, and one call in eight past the map's left edge.
    const size_t n = 256 * size_t(sdk::wide::kLanes);
    std::vector<float> px(n), py(n), pz(n), nl(n);
    int bx = 0, by = 0, above = 0;
    for (size_t i = 0; i < n; ++i) {
        if (i % size_t(sdk::wide::kLanes) == 0)
            bx = int(next() % (size - 4)), by = int(next() % (size - 4)), above = int(next() % 3000) - 1500;
        const int x = (i / size_t(sdk::wide::kLanes)) % 8 == 7 ? -1 - int(i % 4) : bx + int(i % 4);
        const int y = by + int(i / 4 % 4);
        const float u = (float(x) + 0.5f) / float(size) * 2.0f - 1.0f;
        const float v = 1.0f - (float(y) + 0.5f) / float(size) * 2.0f;
        const float floor = 20000.0f + 400.0f * float(x) + 250.0f * float(y);
        const float q = floor + float(above + int(next() % 100) - 50);
        px[i] = 2.0f * u, py[i] = 2.0f * v, pz[i] = -(sm.near_plane + q / scale);
        nl[i] = float(next() % 1000) / 1000.0f;
    }
    constexpr int kTiles = size / FACET_SHADOW_TILE;
    for (Isa isa : supported_isas()) {
        INFO("path " << isa_name(isa));
        std::vector<float> tiles(4 * kTiles * kTiles, std::nanf(""));
        ShadowPlaneRows rows;
        rows.distances = dm.first;
        rows.stride = int(dm.stride);
        rows.width = size;
        rows.tiles = tiles.data();
        kernels(isa).shadow_plane_rows(rows, 0, kTiles);
        // Every texel within reach of a tile, border included, lies between
        // its planes, in exact arithmetic; on the floor they are close.
        for (int ty = 0; ty < kTiles; ++ty)
            for (int tx = 0; tx < kTiles; ++tx) {
                const float* t = &tiles[size_t(4 * (ty * kTiles + tx))];
                const int x0 = tx * FACET_SHADOW_TILE, y0 = ty * FACET_SHADOW_TILE;
                for (int y = y0 - FACET_SHADOW_REACH; y < y0 + FACET_SHADOW_TILE + FACET_SHADOW_REACH; ++y)
                    for (int x = x0 - FACET_SHADOW_REACH; x < x0 + FACET_SHADOW_TILE + FACET_SHADOW_REACH; ++x) {
                        const double d = dm.texels[size_t(y + FACET_SHADOW_BORDER) * dm.stride +
                                                   size_t(x + FACET_SHADOW_BORDER)];
                        const double nearest = double(t[0]) + double(t[1]) * (x - x0) + double(t[2]) * (y - y0);
                        REQUIRE(d >= nearest);
                        REQUIRE(d <= nearest + double(t[3]));
                    }
                if (tx == 1 && ty == 6) CHECK(t[3] < 4.0f);  // the floor's texels only
                REQUIRE(std::abs(t[1]) <= 2048.0f);  // the ABI's bounds
                REQUIRE(std::abs(t[2]) <= 2048.0f);
                REQUIRE(t[0] >= -131072.0f);
                REQUIRE(double(t[0]) + double(t[3]) <= 131072.0);
            }
        CHECK(tiles[4 * 6 + 1] == 0.0f);  // the silhouette's slope, past 2048, taken as 0
        const facet_shadow_map planed = dm.over(sm, tiles.data(), kTiles), bare = dm.over(sm);
        const sdk::ShadowMap with{&planed}, without{&bare};
        // The same planes over taps that all read 0: a lit receiver comes
        // out lit only where the planes settled it; over taps that all
        // read "nothing drawn", a shadowed one comes out shadowed only so.
        DistanceMap dark(size, 0), clear(size, 65535);
        const facet_shadow_map dark_map = dark.over(sm, tiles.data(), kTiles),
                               clear_map = clear.over(sm, tiles.data(), kTiles);
        const sdk::ShadowMap poisoned{&dark_map}, cleared{&clear_map};
        for (int kernel = 1; kernel <= 15; kernel += 2) {
            INFO("kernel " << kernel);
            int lit = 0, settled_scalar = 0, settled_wide = 0;
            int shadowed = 0, settled_dark = 0, settled_dark_wide = 0;
            for (size_t first = 0; first < n; first += size_t(sdk::wide::kLanes)) {
                const sdk::wide::Vec3 wp{lanes(px, first), lanes(py, first), lanes(pz, first)};
                const sdk::wide::Float a = sdk::shadow_visibility(with, wp, lanes(nl, first), kernel, 1.0f, 1.5f);
                const sdk::wide::Float b = sdk::shadow_visibility(without, wp, lanes(nl, first), kernel, 1.0f, 1.5f);
                const sdk::wide::Float c = sdk::shadow_visibility(poisoned, wp, lanes(nl, first), kernel, 1.0f, 1.5f);
                const sdk::wide::Float e = sdk::shadow_visibility(cleared, wp, lanes(nl, first), kernel, 1.0f, 1.5f);
                for (int l = 0; l < sdk::wide::kLanes; ++l) {
                    const size_t i = first + size_t(l);
                    const glm::vec3 p(px[i], py[i], pz[i]);
                    const float scalar = pcf_reference::shadow_visibility(without, p, nl[i], kernel, 1.0f, 1.5f);
                    REQUIRE(pcf_reference::shadow_visibility(with, p, nl[i], kernel, 1.0f, 1.5f) == scalar);
                    REQUIRE(a[l] == scalar);
                    REQUIRE(b[l] == scalar);
                    if (px[i] < -2.0f) continue;  // off the map: lit, and nothing to settle
                    lit += scalar == 1.0f;
                    settled_scalar += pcf_reference::shadow_visibility(poisoned, p, nl[i], kernel, 1.0f, 1.5f) == 1.0f;
                    settled_wide += c[l] == 1.0f;
                    shadowed += scalar == 0.0f;
                    settled_dark += pcf_reference::shadow_visibility(cleared, p, nl[i], kernel, 1.0f, 1.5f) == 0.0f;
                    settled_dark_wide += e[l] == 0.0f;
                }
            }
            // Many receivers are settled by the planes, for kernels within
            // their reach; wider ones read their taps. (A call settles its
            // lanes only when it settles them all.)
            CHECK(lit > int(n) / 4);
            CHECK(shadowed > int(n) / 30);
            if (kernel / 2 <= FACET_SHADOW_REACH) {
                CHECK(settled_scalar > lit / 4);
                CHECK(settled_wide > lit / 20);
                CHECK(settled_dark > shadowed / 8);
                CHECK(settled_dark_wide > 0);
            } else {
                CHECK(settled_scalar == 0);
                CHECK(settled_wide == 0);
                CHECK(settled_dark == 0);
                CHECK(settled_dark_wide == 0);
            }
        }
    }
}

TEST_CASE("16-bit distance maps: taps in front of a perspective map's near plane and past its "
          "edge are lit",
          "[shadow]") {
    const int size = 16;
    const glm::mat4 vp = perspective(glm::radians(170.0f), 1.0f, 0.1f, 10.0f, false);
    facet_shadow_map sm = map_header(size, FACET_SHADOW_PERSPECTIVE, vp);
    sm.near_plane = 0.1f;
    sm.far_plane = 10.0f;
    sm.texel_size = 2.0f * std::tan(glm::radians(85.0f)) / float(size);
    // Nothing drawn: a grazing receiver's outer taps move in front of the light.
    DistanceMap empty(size, 65535);
    const glm::vec3 p(0.05f, 0.0f, -2.0f);
    const facet_shadow_map empty_map = empty.over(sm);
    CHECK(pcf_reference::shadow_visibility(sdk::ShadowMap{&empty_map}, p, 0.1f, 15, 1.0f, 1.5f) == 1.0f);
    // A map of 64 texels over 60 degrees with everything at its near plane:
    // all shadowed, but for the taps past the edge of the map, which read
    // its border.
    const facet_shadow_map narrow =
        map_header(64, FACET_SHADOW_PERSPECTIVE, perspective(glm::radians(60.0f), 1.0f, 0.5f, 8.0f, false));
    DistanceMap wall(64, 0);
    const facet_shadow_map wall_map = wall.over(narrow);
    const sdk::ShadowMap m{&wall_map};
    CHECK(pcf_reference::shadow_visibility(m, p, 1.0f, 3, 1.0f, 1.5f) == 0.0f);
    // The centre of the corner texel (0, 0): of a 3x3 kernel, 5 taps lie
    // past the edge.
    const float t = std::tan(glm::radians(30.0f)), centre = 1.0f - 1.0f / 64.0f;
    const glm::vec3 corner(-centre * t * 2.0f, centre * t * 2.0f, -2.0f);
    CHECK(pcf_reference::shadow_visibility(m, corner, 1.0f, 3, 1.0f, 1.5f) == 5.0f / 9.0f);
    sdk::wide::Vec3 wc{sdk::wide::splat(corner.x), sdk::wide::splat(corner.y), sdk::wide::splat(corner.z)};
    const sdk::wide::Float v = sdk::shadow_visibility(m, wc, sdk::wide::splat(1.0f), 3, 1.0f, 1.5f);
    for (int i = 0; i < sdk::wide::kLanes; ++i) CHECK(v[i] == 5.0f / 9.0f);
}

TEST_CASE("16-bit distance maps: every path turns window depth into the same distances, each "
          "the exact distance rounded up",
          "[shadow][isa]") {
    const int size = 64;
    std::vector<float> depth(size_t(size) * size);
    uint32_t seed = 7;
    for (float& z : depth) {
        seed = seed * 1664525u + 1013904223u;
        z = float(seed >> 8) / float(1u << 24);  // [0, 1)
    }
    depth[5] = 1.0f;  // nothing drawn
    depth[6] = 0.0f;  // at the near plane
    for (bool orthographic : {true, false}) {
        INFO((orthographic ? "orthographic" : "perspective"));
        std::vector<std::vector<uint16_t>> out;
        for (Isa isa : supported_isas()) {
            std::vector<uint16_t>& d = out.emplace_back(depth.size(), 0);
            ShadowDistanceRows rows;
            rows.depth = depth.data();
            rows.depth_stride = size;
            rows.distances = d.data();
            rows.distance_stride = size;
            rows.width = size;
            rows.orthographic = orthographic;
            rows.near_plane = 0.01f;
            rows.far_plane = 8.0f;
            kernels(isa).shadow_distance_rows(rows, 0, size);
            CHECK(d == out.front());
        }
        const std::vector<uint16_t>& d = out.front();
        CHECK(d[5] == 65535);
        CHECK(d[6] == 0);
        for (size_t i = 0; i < depth.size(); ++i) {
            const double z = depth[i], n = 0.01, f = 8.0;
            const double distance = orthographic ? n + z * (f - n) : n * f / (f - z * (f - n));
            const double exact = (distance - n) / (f - n) * 65535.0;
            // Rounded up, within the float arithmetic's error in distance.
            REQUIRE(double(d[i]) >= exact - 1e-6 * exact - 1e-3);
            REQUIRE(double(d[i]) < exact + 1.0 + 1e-6 * exact);
        }
    }
}

namespace {

// ao_normal_rows on `isa` over a w x h grid of view z, seen orthographically
// at x = 0.01 i, y = -0.01 j; `z` holds a row and a vector of padding on
// either side, as the AO pass keeps it. Gives nx, ny and nz.
std::array<std::vector<float>, 3> orthographic_normals(Isa isa, std::vector<float>& z, int w,
                                                       int h) {
    std::array<std::vector<float>, 3> n;
    for (std::vector<float>& c : n) c.resize(size_t(w * h));
    AoFrame f;
    f.width = f.target_width = w, f.height = f.target_height = h;
    f.perspective = false;
    f.x1 = 0.01f, f.y1 = -0.01f;
    f.z = z.data() + (w + 16);
    f.nx = n[0].data(), f.ny = n[1].data(), f.nz = n[2].data();
    kernels(isa).ao_normal_rows(f, 0, h);
    return n;
}

}  // namespace

TEST_CASE("the AO pass's normals take the neighbour nearer in depth on each axis, so that no "
          "normal straddles an edge, the same on every path",
          "[ao][isa]") {
    // A 32x24 grid of view positions, seen orthographically (x = 0.01 i,
    // y = -0.01 j): a plane tilted about x (z = -2 - 0.1 y) left of column
    // 12, and one far behind it (z = -6, facing the camera) from column 12
    // on; nothing drawn in the last row.
    const int w = 32, h = 24, pad = w + 16;
    std::vector<float> z(w * h + 2 * pad);
    for (int j = 0; j < h - 1; ++j)
        for (int i = 0; i < w; ++i)
            z[size_t(pad + j * w + i)] = i < 12 ? -2.0f - 0.1f * float(j) : -6.0f;
    std::vector<std::array<std::vector<float>, 3>> normals;
    for (Isa isa : supported_isas()) {
        INFO(isa_name(isa));
        normals.push_back(orthographic_normals(isa, z, w, h));
        const auto& [nx, ny, nz] = normals.back();
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const size_t k = size_t(j * w + i);
                const glm::vec3 n(nx[k], ny[k], nz[k]);
                INFO("texel " << i << ", " << j);
                REQUIRE(glm::length(n) == Approx(1.0f).epsilon(1e-5));
                if (j == h - 1) {
                    CHECK(n == glm::vec3(0, 0, 1));  // nothing drawn
                } else if (i < 12) {
                    // The tilted plane's normal turned to the camera: also in
                    // column 11, whose right neighbour is far behind, and in
                    // row 22, which has no neighbour below.
                    const glm::vec3 expected = glm::normalize(glm::vec3(0.0f, -0.1f, 0.01f));
                    CHECK(glm::length(n - expected) < 1e-4f);
                } else {
                    CHECK(glm::length(n - glm::vec3(0, 0, 1)) < 1e-4f);  // column 12 too
                }
            }
    }
    for (size_t i = 1; i < normals.size(); ++i)
        for (int c = 0; c < 3; ++c) CHECK(normals[i][c] == normals[0][c]);
}

TEST_CASE("an AO texel with neighbours on one axis only gets the normal nearest the eye's "
          "direction across its step; an orthographic eye looks along -Z",
          "[ao][isa]") {
    // Orthographic positions x = 0.01 i, y = -0.01 j on a 32x8 grid: row 5
    // alone drawn, a strip of the plane z = -2 - 0.5 x (so texels there have
    // neighbours across but none up or down), and texel (20, 2) alone.
    const int w = 32, h = 8, pad = w + 16;
    std::vector<float> z(w * h + 2 * pad);
    for (int i = 0; i < w; ++i) z[size_t(pad + 5 * w + i)] = -2.0f - 0.5f * (0.01f * float(i));
    z[size_t(pad + 2 * w + 20)] = -3.0f;
    std::vector<std::array<std::vector<float>, 3>> normals;
    for (Isa isa : supported_isas()) {
        INFO(isa_name(isa));
        normals.push_back(orthographic_normals(isa, z, w, h));
        const auto& [nx, ny, nz] = normals.back();
        const glm::vec3 strip = glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f));  // the plane's
        for (int i = 0; i < w; ++i) {
            INFO("texel " << i << ", 5");
            const size_t k = size_t(5 * w + i);
            CHECK(glm::length(glm::vec3(nx[k], ny[k], nz[k]) - strip) < 1e-4f);
        }
        const size_t alone = size_t(2 * w + 20);
        CHECK(glm::length(glm::vec3(nx[alone], ny[alone], nz[alone]) - glm::vec3(0, 0, 1)) < 1e-6f);
    }
    for (size_t i = 1; i < normals.size(); ++i)
        for (int c = 0; c < 3; ++c) CHECK(normals[i][c] == normals[0][c]);
}

TEST_CASE("the AO pass finds a plane's view positions and normal from its depth under a "
          "perspective projection, at half size on an odd-sized target, the same on every path",
          "[ao][isa]") {
    // A 33x25 target whose every pixel sees one tilted plane, its window
    // depth worked out in double; the AO grid is 17x13, its last column and
    // row standing for the target's last pixel column and row (32 and 24).
    const int tw = 33, th = 25;
    const glm::mat4 proj = facet::perspective(glm::radians(50.0f), float(tw) / float(th), 0.1f,
                                              100.0f, false);
    const glm::dvec3 normal = glm::normalize(glm::dvec3(0.25, 0.6, 0.76));  // faces the eye
    const glm::dvec3 on_plane(0.3, -0.2, -5.0);
    const glm::dmat4 dproj(proj), inverse = glm::inverse(dproj);
    // The view position pixel (px, py)'s ray meets the plane at.
    const auto seen = [&](int px, int py) {
        const glm::dvec4 ndc(((px + 0.5) * 2.0 / tw) - 1.0, 1.0 - ((py + 0.5) * 2.0 / th), 0.5, 1.0);
        const glm::dvec4 p = inverse * ndc;
        const glm::dvec3 ray = glm::dvec3(p) / p.w;  // from the eye at the origin
        return ray * (glm::dot(normal, on_plane) / glm::dot(normal, ray));
    };
    std::vector<float> depth(size_t(tw) * size_t(th));
    for (int py = 0; py < th; ++py)
        for (int px = 0; px < tw; ++px) {
            const glm::dvec4 clip = dproj * glm::dvec4(seen(px, py), 1.0);
            depth[size_t(py * tw + px)] = float(clip.z / clip.w);
        }
    const int w = (tw + 1) / 2, h = (th + 1) / 2, pad = w + 16;
    constexpr int border = AoFrame::kBorder;
    std::vector<std::vector<float>> results;
    for (Isa isa : supported_isas()) {
        INFO(isa_name(isa));
        std::vector<float> z(size_t(w * h + 2 * pad)), nx(size_t(w * h)), ny(size_t(w * h)),
            nz(size_t(w * h)), key(size_t((w + 2 * border) * (h + 2 * border)));
        AoFrame f;
        f.width = w, f.height = h, f.scale = 2, f.target_width = tw, f.target_height = th;
        f.set_pixel_rays(proj);
        REQUIRE(f.perspective);
        const glm::mat4 inv = glm::inverse(proj);
        f.z_row = {inv[0][2], inv[1][2], inv[2][2], inv[3][2]};
        f.w_row = {inv[0][3], inv[1][3], inv[2][3], inv[3][3]};
        f.target_depth = depth.data(), f.target_stride = tw, f.background = 1.0f;
        f.z = z.data() + pad;
        f.key_stride = w + 2 * border;
        f.key = key.data() + size_t(border * f.key_stride + border);
        f.nx = nx.data(), f.ny = ny.data(), f.nz = nz.data();
        kernels(isa).ao_position_rows(f, 0, h);
        kernels(isa).ao_normal_rows(f, 0, h);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                INFO("texel " << i << ", " << j);
                const size_t k = size_t(j * w + i);
                const glm::dvec3 truth = seen(std::min(2 * i, tw - 1), std::min(2 * j, th - 1));
                CHECK(f.z[k] == Approx(truth.z).epsilon(1e-5));
                const glm::dvec3 n(nx[k], ny[k], nz[k]);
                CHECK(glm::length(n - normal) < 1e-3);
            }
        results.push_back(z), results.push_back(nx), results.push_back(ny), results.push_back(nz);
    }
    for (size_t i = 4; i < results.size(); ++i) CHECK(results[i] == results[i % 4]);
}

// ---- shadows and AO as services of every lit shader (ABI 1.3) --------------

TEST_CASE("phong (Gouraud too), toon and lit receive shadows from directional, spot and point "
          "lights as the ray caster casts them",
          "[shadow]") {
    // Materials that show only the light: their colour is zero exactly where
    // the light is blocked.
    const std::pair<const char*, const char*> materials[] = {
        {"phong", "{shader: phong, params: {ambient: [0, 0, 0], diffuse: [1, 1, 1], "
                  "specular: [0, 0, 0], shadow_kernel: 1}}"},
        {"toon", "{shader: toon, params: {base_color: [1, 1, 1], ambient: [0, 0, 0], bands: 16, "
                 "specular_color: [0, 0, 0], rim_color: [0, 0, 0], outline_width: 0, "
                 "shadow_kernel: 1}}"},
        {"lit", "{shader: lit, params: {base_color: [1, 1, 1, 1], ambient: [0, 0, 0], "
                "shadow_kernel: 1}}"},
        {"lit per vertex", "{shader: lit, params: {base_color: [1, 1, 1, 1], ambient: [0, 0, 0], "
                           "per_pixel: false, shadow_kernel: 1}}"},
        {"phong gouraud", "{shader: phong, params: {ambient: [0, 0, 0], diffuse: [1, 1, 1], "
                          "specular: [0, 0, 0], gouraud: true, shadow_kernel: 1}}"}};
    for (const auto& [shader, material] : materials)
        for (const char* light : {kDirectional, kSpot, kPoint}) {
            INFO(shader << ", " << light);
            check_hard_shadows(material, light);
        }
}

TEST_CASE("shadow maps and AO are drawn only for the visible materials that use them",
          "[shadow][ao][skip]") {
    ShadowAoDir sd;
    const auto frame = [&](const std::string& params) {
        const Scene scene = sd.load(
            camera(96, 72) +
            "lights: [{type: directional, direction: [0.7, -1, 0.5], casts_shadow: true}]\n"
            "objects:\n  - {mesh: ground.obj, material: {shader: phong, params: {" + params +
            "}}}\n  - {mesh: cube.obj, position: [0, 0.8, 0], material: {shader: phong, "
            "params: {" + params + "}}}\n");
        Framebuffer fb;
        return Renderer().render(scene, fb);
    };
    const FrameStats both = frame("ambient_occlusion: 1");  // shadows on by default
    CHECK(both.shadows_needed);
    CHECK(both.shadow_passes == 1);
    CHECK(both.ao_needed);
    CHECK(both.ao_passes == 1);
    const FrameStats neither = frame("receive_shadows: false");  // AO off by default
    CHECK_FALSE(neither.shadows_needed);
    CHECK(neither.shadow_passes == 0);
    CHECK_FALSE(neither.ao_needed);
    CHECK(neither.ao_passes == 0);
    CHECK(neither.prepasses + neither.depth_prepasses == 0);
}

namespace {

// Shaders whose parameter says it uses a pass it cannot, or says it with a
// type the host cannot read that way.
template <uint32_t Needs, uint32_t Type, uint32_t Flag>
struct FlagProbe {
    struct Params {
        float value;
    };
    FACET_VARYINGS()
    static constexpr const char* name = "flag_probe";
    static constexpr const char* version = "1";
    static constexpr uint32_t needs = Needs;
    static constexpr facet_param_desc with_flag() {
        facet_param_desc p = sdk::float1("value", 0, 0.0f, 0.0f, 1.0f);
        p.type = Type;
        p.flags = Flag;
        return p;
    }
    static constexpr auto params = sdk::detail::schema(sdk::param::one(with_flag()),
                                                       sdk::param::End{});
    static Varyings vertex(const sdk::VertexIn&, const sdk::Draw&, const Params&, sdk::Vec4& c) {
        c = sdk::Vec4(sdk::splat(0.0f));
        return {};
    }
    static sdk::Vec4 fragment(const Varyings&, sdk::Fragment&, const sdk::Draw&, const Params&) {
        return sdk::Vec4(sdk::splat(1.0f));
    }
};

template <class S>
bool accepted() {
    try {
        ShaderPlugin::from_descriptor(sdk::describe<S>(), "test");
        return true;
    } catch (const Error& e) {
        CHECK(e.code() == ErrorCode::plugin_invalid);
        return false;
    }
}

}  // namespace

TEST_CASE("a parameter that says whether a pass is used must be of a type the host reads, for "
          "a pass the shader needs",
          "[shadow][ao][plugin]") {
    CHECK(accepted<FlagProbe<FACET_NEED_SHADOW_MAP, FACET_PARAM_BOOL, FACET_PARAM_USES_SHADOWS>>());
    CHECK(accepted<FlagProbe<FACET_NEED_AO, FACET_PARAM_FLOAT, FACET_PARAM_USES_AO>>());
    CHECK(accepted<FlagProbe<FACET_NEED_AO, FACET_PARAM_BOOL, FACET_PARAM_USES_AO>>());
    CHECK_FALSE(
        accepted<FlagProbe<FACET_NEED_SHADOW_MAP, FACET_PARAM_FLOAT, FACET_PARAM_USES_SHADOWS>>());
    CHECK_FALSE(
        accepted<FlagProbe<FACET_NEED_LIGHTS, FACET_PARAM_BOOL, FACET_PARAM_USES_SHADOWS>>());
    CHECK_FALSE(accepted<FlagProbe<FACET_NEED_AO, FACET_PARAM_INT, FACET_PARAM_USES_AO>>());
    CHECK_FALSE(accepted<FlagProbe<FACET_NEED_LIGHTS, FACET_PARAM_FLOAT, FACET_PARAM_USES_AO>>());
}

TEST_CASE("a light's shadow_map_size is checked, and a point light's cube is six maps",
          "[shadow][config]") {
    ShadowAoDir sd;
    const std::string objects =
        "objects:\n  - {mesh: ground.obj, material: " + std::string(kShadowed) + "}\n";
    try {
        sd.load(camera(64, 48) +
                "lights:\n  - {type: point, position: [0, 2, 0], casts_shadow: true,\n"
                "     shadow_map_size: 8}\n" + objects);
        FAIL("a shadow map of 8 texels was accepted");
    } catch (const Error& e) {
        CHECK(e.code() == ErrorCode::out_of_range);
        CHECK(e.line() == 5);
        CHECK(std::string(e.what()).find("shadow_map_size") != std::string::npos);
    }
    Scene scene = sd.load(camera(64, 48) +
                          "lights:\n  - {type: point, position: [0, 2, 0], casts_shadow: true, "
                          "shadow_map_size: 64}\n" + objects);
    Renderer renderer;
    Framebuffer fb;
    CHECK(renderer.render(scene, fb).shadow_passes == 6);
    CHECK(renderer.render(scene, fb).shadow_maps_reused == 6);  // with its planes (ABI 1.6)
    Framebuffer fresh;
    Renderer().render(scene, fresh);
    CHECK(test::same_image(fb, fresh));
    scene.lights[0].position.x += 0.1f;  // every face sees it move
    CHECK(renderer.render(scene, fb).shadow_passes == 6);
}

TEST_CASE("AO reads the main pass's depth pre-pass, and the image is the one its own gives",
          "[ao][depth]") {
    PluginRegistry registry;
    for (const char* name : {"scenes/ao.yaml", "scenes/showcase.yaml"})
        for (bool half : {true, false}) {
            INFO(name << (half ? ", half-size AO" : ", full-size AO"));
            Scene scene = test::small_demo_scene(registry, name);
            REQUIRE(scene.settings.msaa == 1);
            REQUIRE(scene.settings.depth_compare == DepthCompare::greater_equal);
            scene.settings.ao_half_resolution = half;
            Framebuffer shared, own;
            const FrameStats a = Renderer(2).render(scene, shared);
            CHECK(a.ao_passes == 1);
            CHECK(a.depth_prepasses == 1);
            CHECK(a.prepasses == 0);
            // A strict depth test cannot take a pre-pass (the compare-equal
            // pass would find nothing), so AO draws its own; no two surfaces
            // of these scenes are at the same depth, so the image is the same.
            scene.settings.depth_compare = DepthCompare::greater;
            const FrameStats b = Renderer(2).render(scene, own);
            CHECK(b.ao_passes == 1);
            CHECK(b.depth_prepasses == 0);
            CHECK(b.prepasses == 1);
            CHECK(test::same_image(shared, own));
            CHECK(a.fragments_shaded < b.fragments_shaded);  // hidden ones shaded only without
        }
    // With MSAA the frame's depth is per sample, and AO keeps its own.
    Scene scene = test::small_demo_scene(registry, "scenes/ao.yaml");
    scene.settings.msaa = 4;
    Framebuffer fb;
    const FrameStats c = Renderer(2).render(scene, fb);
    CHECK(c.depth_prepasses == 0);
    CHECK(c.prepasses == 1);
}

TEST_CASE("with AO's pre-pass shared, a blended part that writes depth is drawn in the main "
          "pass alone, and resized buffers give what new ones give",
          "[ao][depth]") {
    PluginRegistry registry;
    Scene scene = test::small_demo_scene(registry, "scenes/ao.yaml");
    Framebuffer plain;
    Renderer(2).render(scene, plain);
    {
        // A glass pane in front of the objects: through the pre-pass it
        // would vanish (shaded only where its depth equals the opaque depth).
        auto pane = std::make_shared<Mesh>(test::make_mesh(
            {{-1, 0.2f, 1}, {1, 0.2f, 1}, {1, 1.2f, 1}, {-1, 1.2f, 1}}, {0, 1, 2, 0, 2, 3}));
        pane->normals.assign(4, glm::vec3(0, 0, 1));
        auto glass = std::make_shared<Material>(*scene.objects.front().material);
        glass->blend = BlendMode::alpha;
        glass->depth_write = true;
        glass->cull = CullMode::none;
        Scene glazed = scene;
        glazed.objects.push_back({"pane", pane, {}, glass, true});
        Framebuffer with_pane, strict;
        const FrameStats d = Renderer(2).render(glazed, with_pane);
        CHECK(d.depth_prepasses == 1);
        glazed.settings.depth_compare = DepthCompare::greater;  // AO's own pre-pass
        const FrameStats e = Renderer(2).render(glazed, strict);
        CHECK(e.prepasses == 1);
        CHECK(test::same_image(with_pane, strict));
        CHECK(!test::same_image(with_pane, plain));  // the pane is there
    }
    {
        Renderer renderer(2);
        Framebuffer first, second, fresh;
        renderer.render(scene, first);
        scene.settings.width = 131;
        scene.settings.height = 77;
        renderer.render(scene, second);
        Renderer(2).render(scene, fresh);
        CHECK(test::same_image(second, fresh));
        scene.settings.ao_half_resolution = !scene.settings.ao_half_resolution;
        renderer.render(scene, second);
        Renderer(2).render(scene, fresh);
        CHECK(test::same_image(second, fresh));
    }
}

TEST_CASE("the half-size AO upsample weighs the four nearest texels by likeness in depth, a "
          "tile at a time, the same on every path",
          "[ao][isa]") {
    // A 150x70 target (tiles of 64 with ragged right and bottom ones; an
    // AO grid of 75x35) under a perspective projection: a near plane over
    // the left part, a far one behind it, a post one pixel wide in an odd
    // column (so no texel sees it: its pixels take the texel nearest in
    // depth), nothing drawn in a corner. The texels' view z are the
    // surfaces' at their pixels, and their blurred visibility random, with
    // a region all open.
    const int tw = 150, th = 70, w = tw / 2, h = th / 2, stride = tw + 18;
    const glm::mat4 proj = facet::perspective(glm::radians(50.0f), float(tw) / float(th), 0.1f,
                                              100.0f, false);
    const glm::dmat4 dproj(proj), inverse = glm::inverse(dproj);
    // View z of pixel (px, py) and its window depth (1, the background,
    // where nothing was drawn).
    const auto view_z = [&](int px, int py) {
        if (px > 120 && py > 50) return 0.0;
        if (px == 101) return -2.0;
        return px < 60 ? -3.0 - 0.01 * px : -9.0 + 0.02 * py;
    };
    const auto window = [&](double z) {
        return z == 0.0 ? 1.0 : (dproj[2][2] * z + dproj[3][2]) / -z;
    };
    std::vector<float> depth(size_t(stride) * size_t(th) + 32, 1.0f);
    for (int py = 0; py < th; ++py)
        for (int px = 0; px < tw; ++px)
            depth[size_t(py * stride + px)] = float(window(view_z(px, py)));
    std::vector<float> z(size_t(w * h) + 2 * size_t(w + 16)), blurred(size_t(w * h));
    uint32_t seed = 5;
    const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            z[size_t(w + 16 + j * w + i)] = float(view_z(2 * i, 2 * j));
            const bool open = i >= 30 && i < 50 && j < 20;
            blurred[size_t(j * w + i)] =
                open || next() % 4 == 0 ? 1.0f : float(next() % 1000) / 1000.0f;
        }
    AoFrame f;
    f.scale = 2, f.width = w, f.height = h, f.target_width = tw, f.target_height = th;
    f.z = z.data() + (w + 16);
    f.blurred = blurred.data();
    f.target_depth = depth.data();
    f.target_stride = stride;
    f.background = 1.0f;
    f.z_row = {inverse[0][2], inverse[1][2], inverse[2][2], inverse[3][2]};
    f.w_row = {inverse[0][3], inverse[1][3], inverse[2][3], inverse[3][3]};
    // The rule in double: bilinear weights times 1 / (1 + 2500 r^2) for a
    // relative difference r in view z; the nearest in depth where the
    // weights sum to 1e-4 or less. Pixels near that edge are not compared.
    const auto reference = [&](int px, int py, bool& clear, bool& alike) {
        clear = true, alike = true;
        const double d = depth[size_t(py * stride + px)];
        if (d == 1.0) return 1.0;
        const glm::dvec4 ndc((px + 0.5) * 2.0 / tw - 1.0, 1.0 - (py + 0.5) * 2.0 / th, d, 1.0);
        const glm::dvec4 p = inverse * ndc;
        const double pz = p.z / p.w;
        double sum = 0.0, weight = 0.0, nearest = 1.0, closest = INFINITY;
        for (int k = 0; k < 4; ++k) {
            const int i = std::min(px / 2 + (k & 1), w - 1), j = std::min(py / 2 + (k >> 1), h - 1);
            const double zt = z[size_t(w + 16 + j * w + i)], a = blurred[size_t(j * w + i)];
            if (zt == 0.0) continue;
            const double wx = k & 1 ? (px & 1) * 0.5 : 1.0 - (px & 1) * 0.5;
            const double wy = k & 2 ? (py & 1) * 0.5 : 1.0 - (py & 1) * 0.5;
            const double r = (zt - pz) / pz, wk = wx * wy / (1.0 + 2500.0 * r * r);
            sum += wk * a, weight += wk;
            if (r * r < closest) closest = r * r, nearest = a;
        }
        clear = std::abs(weight - 1e-4) > 0.5e-4;
        alike = weight > 1e-4;
        return alike ? sum / weight : nearest;
    };
    std::vector<float> first;  // the first path's image
    for (Isa isa : supported_isas()) {
        INFO("path " << isa_name(isa));
        std::vector<float> image(size_t(tw * th), std::nanf(""));
        for (int ty = 0; ty < th; ty += kTileSize)
            for (int tx = 0; tx < tw; tx += kTileSize) {
                std::vector<float> tile(size_t(kTileSize * kTileSize), std::nanf(""));
                const int rows = std::min(kTileSize, th - ty);
                const int columns = std::min(kTileSize, tw - tx);
                kernels(isa).ao_upsample_rows(f, ty, rows, tx, (columns + 15) / 16 * 16,
                                              tile.data(), kTileSize / 4);
                for (int y = 0; y < rows; ++y)  // 4x4 blocks of 16, in lane order
                    for (int x = 0; x < columns; ++x)
                        image[size_t((ty + y) * tw + tx + x)] = tile[size_t(
                            (y / 4 * (kTileSize / 4) + x / 4) * 16 + y % 4 * 4 + x % 4)];
            }
        int compared = 0, blended = 0, unlike = 0;
        for (int py = 0; py < th; ++py)
            for (int px = 0; px < tw; ++px) {
                INFO("pixel " << px << ", " << py);
                bool clear, alike;
                const double want = reference(px, py, clear, alike);
                const float got = image[size_t(py * tw + px)];
                REQUIRE(got >= 0.0f);  // not NaN: every pixel written
                if (!clear) continue;
                REQUIRE(std::abs(got - want) < 1e-4);  // float against double
                ++compared;
                blended += want != 1.0 && want != std::floor(want * 1000.0) / 1000.0;
                unlike += !alike;
            }
        CHECK(compared > tw * th * 9 / 10);
        CHECK(blended > tw * th / 4);  // most pixels mix texels
        CHECK(unlike > th / 2);  // the post's pixels
        if (first.empty()) first = image;
        else CHECK(image == first);
    }
}
