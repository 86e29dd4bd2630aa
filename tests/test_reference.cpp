// The reference renderer (tests/reference/render.hpp) checked against
// closed-form answers, and facet measured against it.
//
// The reference is the ground truth for facet-bench --pareto, so it is held
// to answers worked out here independently of its code: exact pixel
// coverage of a triangle (polygon clipping), a perspective texture ramp
// (ray-plane intersection from the camera's parameters), hard shadows and
// open-sky ambient occlusion.
#include "reference/metrics.hpp"
#include "reference/raycast.hpp"
#include "reference/render.hpp"
#include "support.hpp"

#include <facet/framebuffer.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace facet;
namespace fs = std::filesystem;

namespace {

// Area of the convex polygon `poly` inside the unit square at (x, y)
// (Sutherland-Hodgman against its four sides, then the shoelace formula).
double area_in_pixel(std::vector<glm::dvec2> poly, int x, int y) {
    auto clip = [&](int axis, double bound, bool keep_below) {
        std::vector<glm::dvec2> out;
        for (size_t i = 0; i < poly.size(); ++i) {
            const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
            const bool ina = keep_below ? a[axis] <= bound : a[axis] >= bound;
            const bool inb = keep_below ? b[axis] <= bound : b[axis] >= bound;
            if (ina) out.push_back(a);
            if (ina != inb) out.push_back(a + (b - a) * ((bound - a[axis]) / (b[axis] - a[axis])));
        }
        poly = out;
    };
    clip(0, x, false);
    clip(0, x + 1, true);
    clip(1, y, false);
    clip(1, y + 1, true);
    double area = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        area += a.x * b.y - b.x * a.y;
    }
    return std::abs(area) / 2.0;
}

// The camera ray through window point (x, y), from the camera's position,
// target and vertical field of view (y up, no roll).
glm::dvec3 camera_dir(const Camera& c, int w, int h, double x, double y) {
    const glm::dvec3 forward = glm::normalize(glm::dvec3(c.target) - glm::dvec3(c.position));
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double t = std::tan(glm::radians(double(c.fov_y)) / 2.0);
    return forward + (2.0 * x / w - 1.0) * t * (double(w) / h) * right +
           (1.0 - 2.0 * y / h) * t * up;
}

const char* kUnlitWhite = "{shader: unlit, params: {base_color: [1, 1, 1, 1]}}";

}  // namespace

TEST_CASE("reference: a pixel's value is the triangle's exact area in it", "[reference]") {
    test::SceneDir sd("reference");
    test::write(sd.dir / "tri.obj", "v -0.9 -0.4 0\nv 0.8 -0.7 0.3\nv 0.1 0.9 -0.2\nf 1 2 3\n");
    const Scene scene = sd.load(
        "camera: {position: [0.2, 0.3, 3], target: [0, 0, 0], fov_y: 40}\n"
        "render: {color_format: rgba32f, size: [48, 36], cull: none}\n"
        "objects:\n  - {mesh: tri.obj, material: " + std::string(kUnlitWhite) + "}\n");
    const std::vector<glm::dvec4> image = reference::render(scene);

    // The triangle on screen, projected here in double precision.
    const glm::dmat4 vp = glm::dmat4(scene.camera.projection(48.0f / 36.0f, true)) *
                          glm::dmat4(scene.camera.view());
    std::vector<glm::dvec2> tri;
    for (const glm::vec3& p : scene.objects[0].mesh->positions) {
        const glm::dvec4 c = vp * glm::dvec4(glm::dvec3(p), 1.0);
        tri.push_back({(c.x / c.w + 1.0) * 24.0, (1.0 - c.y / c.w) * 18.0});
    }
    double worst = 0.0, total = 0.0, covered = 0.0;
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 48; ++x) {
            const double exact = area_in_pixel(tri, x, y);
            const double got = image[size_t(y) * 48 + x].r;
            worst = std::max(worst, std::abs(got - exact));
            total += std::abs(got - exact);
            covered += exact;
        }
    CHECK(covered > 300.0);  // a real triangle, many pixels
    // 16 x 16 samples: an edge's error in one pixel is at most about one
    // row of samples (1/16); on average far less.
    CHECK(worst <= 1.0 / 16.0);
    CHECK(total / (48 * 36) < 0.004);
}

TEST_CASE("reference: a perspective texture ramp matches ray-plane intersection",
          "[reference]") {
    test::SceneDir sd("reference");
    // Black and white texels: with clamping and bilinear filtering the
    // texture is clamp(2u - 0.5, 0, 1) in linear light.
    Framebuffer ramp(2, 1);
    ramp.set_pixel(0, 0, {0, 0, 0, 1});
    ramp.set_pixel(1, 0, {1, 1, 1, 1});
    ramp.write_png(sd.dir / "ramp.png");
    // A floor quad from z = -3 to z = 1 with u = (z + 3) / 4: u varies with
    // depth, where perspective matters.
    test::write(sd.dir / "floor.obj",
                "v -1 0 -3\nv 1 0 -3\nv 1 0 1\nv -1 0 1\n"
                "vt 0 0\nvt 1 0\n"
                "f 1/1 3/2 2/1\nf 1/1 4/2 3/2\n");
    const Scene scene = sd.load(
        "camera: {position: [0.3, 1.2, 2.5], target: [0, 0, -1], fov_y: 50}\n"
        "render: {color_format: rgba32f, size: [40, 30], cull: none}\n"
        "objects:\n  - {mesh: floor.obj, material: {shader: unlit, params: {base_texture: "
        "{file: ramp.png, filter: bilinear, wrap: clamp}}}}\n");
    reference::RenderOptions options;
    options.grid = 8;
    const std::vector<glm::dvec4> image = reference::render(scene, options);

    double worst = 0.0, lit = 0.0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            double expected = 0.0;
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) {
                    const glm::dvec3 o(scene.camera.position);
                    const glm::dvec3 d = camera_dir(scene.camera, 40, 30, x + (i + 0.5) / 8,
                                                    y + (j + 0.5) / 8);
                    if (d.y >= 0.0) continue;
                    const glm::dvec3 p = o + d * (-o.y / d.y);
                    if (std::abs(p.x) > 1.0 || p.z < -3.0 || p.z > 1.0) continue;
                    const double u = (p.z + 3.0) / 4.0;
                    expected += std::clamp(2.0 * u - 0.5, 0.0, 1.0) / 64.0;
                }
            lit += expected;
            worst = std::max(worst, std::abs(image[size_t(y) * 40 + x].r - expected));
        }
    CHECK(lit > 100.0);
    CHECK(worst < 1e-4);
}

TEST_CASE("reference: hard shadows and open-sky AO come out exactly", "[reference]") {
    test::SceneDir sd("reference");
    test::write(sd.dir / "ground.obj",
                "v -6 0 -6\nv 6 0 -6\nv 6 0 6\nv -6 0 6\nvn 0 1 0\nf 1//1 3//1 2//1\nf 1//1 4//1 3//1\n");
    fs::copy_file(fs::path(FACET_SOURCE_DIR) / "plugins/template/cube.obj", sd.dir / "cube.obj");
    const std::string camera =
        "camera: {position: [3, 3.5, 4.5], target: [0, 0.2, 0], fov_y: 45}\n"
        "render: {color_format: rgba32f, size: [48, 36]}\n";

    SECTION("a directional light blocked by a cube: the ground is n.l or 0") {
        const Scene scene = sd.load(
            camera +
            "lights: [{type: directional, direction: [0.7, -1, 0.5], intensity: 1, casts_shadow: true}]\n"
            "objects:\n"
            "  - {mesh: ground.obj, material: {shader: shadow, params: {base_color: [1, 1, 1, 1], "
            "ambient: [0, 0, 0]}}}\n"
            "  - {mesh: cube.obj, position: [0, 0.8, 0], material: {shader: shadow, params: "
            "{base_color: [1, 1, 1, 1], ambient: [0, 0, 0]}}}\n");
        reference::RenderOptions options;
        options.grid = 4;
        const std::vector<glm::dvec4> image = reference::render(scene, options);
        const reference::RayCaster rc(scene);
        const Light& l = scene.lights[0];
        const double n_dot_l = -glm::normalize(glm::dvec3(l.direction)).y;
        int lit = 0, shadowed = 0;
        for (int y = 0; y < 36; ++y)
            for (int x = 0; x < 48; ++x) {
                // Pixels whose corners and centre all see the ground and agree
                // on the light.
                int seen = 0, open = 0;
                for (auto [dx, dy] : {std::pair{0.5, 0.5}, {0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, {1.0, 1.0}}) {
                    const auto hit = rc.camera_hit(scene, x + dx, y + dy);
                    if (!hit || hit->object != 0) break;
                    ++seen;
                    open += rc.lit(l, hit->point, hit->normal);
                }
                if (seen < 5 || (open != 0 && open != 5)) continue;
                const double got = image[size_t(y) * 48 + x].r;
                if (open) {
                    ++lit;
                    CHECK(got == Approx(n_dot_l).margin(1e-5));
                } else {
                    ++shadowed;
                    CHECK(got == Approx(0.0).margin(1e-6));
                }
            }
        CHECK(lit > 200);
        CHECK(shadowed > 20);
    }
    SECTION("an open plane has full ambient visibility") {
        const Scene scene = sd.load(
            camera +
            "objects:\n  - {mesh: ground.obj, material: {shader: ao, params: {base_color: [1, 1, 1, 1], "
            "ambient: [1, 1, 1], strength: 1}}}\n");
        reference::RenderOptions options;
        options.grid = 4;
        const std::vector<glm::dvec4> image = reference::render(scene, options);
        const reference::RayCaster rc(scene);
        int checked = 0;
        for (int y = 0; y < 36; ++y)
            for (int x = 0; x < 48; ++x)
                if (rc.camera_hit(scene, x, y) && rc.camera_hit(scene, x + 1, y + 1) &&
                    rc.camera_hit(scene, x + 1, y) && rc.camera_hit(scene, x, y + 1)) {
                    ++checked;
                    CHECK(image[size_t(y) * 48 + x].r == Approx(1.0).margin(1e-5));
                }
        CHECK(checked > 500);
    }
}

TEST_CASE("facet converges to the reference: more MSAA samples, less error", "[reference][msaa]") {
    test::SceneDir sd("reference");
    fs::copy_file(fs::path(FACET_SOURCE_DIR) / "plugins/template/cube.obj", sd.dir / "cube.obj");
    auto scene_with = [&](int msaa) {
        return sd.load(
            "camera: {position: [2.2, 1.6, 3.1], target: [0, 0, 0], fov_y: 40}\n"
            "render: {color_format: rgba32f, size: [64, 48], msaa: " + std::to_string(msaa) + "}\n"
            "lights: [{type: directional, direction: [-0.4, -1, -0.6], intensity: 1}]\n"
            "objects:\n  - {mesh: cube.obj, rotation: [10, 25, 0], material: {shader: lit}}\n");
    };
    const std::vector<glm::dvec4> truth = reference::render(scene_with(1));
    std::vector<reference::ImageError> errors;
    for (int msaa : {1, 4, 8}) {
        Framebuffer fb;
        Renderer(1).render(scene_with(msaa), fb);
        errors.push_back(reference::compare(reference::linear_image(fb), truth, 64, 48));
        CAPTURE(msaa, errors.back().rmse, errors.back().max, errors.back().dssim);
        // Away from the silhouette facet shades what the reference does.
        CHECK(errors.back().rmse < 0.05);
    }
    CHECK(errors[1].rmse < errors[0].rmse);
    CHECK(errors[2].rmse < errors[1].rmse);
    CHECK(errors[2].rmse < 0.5 * errors[0].rmse);
    CHECK(errors[2].dssim < errors[0].dssim);
}

TEST_CASE("image error: identical images score zero, different ones do not", "[reference]") {
    std::vector<glm::dvec4> a(32 * 24), b(32 * 24);
    for (size_t i = 0; i < a.size(); ++i) {
        a[i] = glm::dvec4(double(i % 32) / 31.0, 0.5, double(i / 32) / 23.0, 1.0);
        b[i] = a[i];
    }
    const reference::ImageError same = reference::compare(a, b, 32, 24);
    CHECK(same.rmse == 0.0);
    CHECK(same.max == 0.0);
    CHECK(same.dssim == Approx(0.0).margin(1e-12));
    b[5 * 32 + 7] = glm::dvec4(1.0);
    const reference::ImageError one = reference::compare(a, b, 32, 24);
    CHECK(one.max > 0.3);
    CHECK(std::isfinite(one.rmse));
    CHECK(one.rmse < one.max);
    CHECK(one.dssim > 0.0);
    CHECK_THROWS(reference::compare(a, std::vector<glm::dvec4>(10), 32, 24));
}
