// Lines and points (Topology, facet/render_state.hpp): the samples a line
// of any width and direction covers, and a point of any size, against the
// exact rectangle and square, at 1 and 4 samples; varyings along a line;
// a line through the near plane; the YAML.
#include "support.hpp"

#include <facet/renderer.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace facet;
using namespace facet::test;

namespace {

constexpr int kW = 61, kH = 47;

// OBJ text of triangles whose corners are pixel positions (x right, y
// down) under an orthographic camera of one unit a pixel.
std::string pixel_obj(const std::vector<glm::dvec2>& corners) {
    std::ostringstream obj;
    obj.precision(17);
    for (const glm::dvec2& p : corners) obj << "v " << p.x - kW / 2.0 << ' ' << kH / 2.0 - p.y << " 0\n";
    for (size_t i = 0; i + 2 < corners.size(); i += 3)
        obj << "f " << i + 1 << ' ' << i + 2 << ' ' << i + 3 << '\n';
    return obj.str();
}

// The scene: `mesh` drawn as `draw` (with its width or size), white and
// added, so that a sample's red counts how often it is covered.
Scene primitive_scene(SceneDir& sd, const std::string& mesh, const std::string& draw, int msaa) {
    std::ofstream(sd.dir / "mesh.obj") << mesh;
    return sd.load("camera: {position: [0, 0, 5], target: [0, 0, 0], projection: orthographic, height: " +
                   std::to_string(kH) + "}\n"
                   "render: {size: [" + std::to_string(kW) + ", " + std::to_string(kH) +
                   "], color_format: rgba32f, clear_color: [0, 0, 0, 0], msaa: " +
                   std::to_string(msaa) + "}\n"
                   "objects:\n  - mesh: mesh.obj\n"
                   "    material: {shader: unlit, blend: additive, " + draw + "}\n");
}

double inside_square(glm::dvec2 p, glm::dvec2 c, double size) {
    return size / 2 - std::max(std::abs(p.x - c.x), std::abs(p.y - c.y));
}

// The triangle of corners c drawn as `draw` at `msaa` samples covers the
// samples of the three shapes whose distances inside `inside` gives
// (check_coverage), and some.
void check_drawn(SceneDir& sd, const std::vector<glm::dvec2>& c, const std::string& draw,
                 int msaa, const std::function<std::vector<double>(glm::dvec2)>& inside) {
    const Scene s = primitive_scene(sd, pixel_obj(c), draw, msaa);
    Framebuffer fb;
    Renderer(1).render(s, fb);
    int covered = 0;
    check_coverage(fb, inside, covered);
    CHECK(covered > 0);
}

}  // namespace

TEST_CASE("a line covers the samples of its rectangle, at any width and direction",
          "[lines][msaa]") {
    SceneDir sd;
    std::mt19937 random(31);
    std::uniform_real_distribution<double> x(2.0, kW - 2.0), y(2.0, kH - 2.0), width(0.3, 6.0);
    for (const int msaa : {1, 4})
        for (int k = 0; k < 12; ++k) {
            // A triangle's three edges are three lines.
            const std::vector<glm::dvec2> c = {{x(random), y(random)}, {x(random), y(random)},
                                               {x(random), y(random)}};
            const double w = k % 4 == 0 ? 1.0 : width(random);
            INFO(msaa << " samples, width " << w);
            check_drawn(sd, c, "draw: lines, line_width: " + std::to_string(w), msaa,
                        [&](glm::dvec2 p) {
                            return std::vector<double>{inside_line(p, c[0], c[1], w),
                                                       inside_line(p, c[1], c[2], w),
                                                       inside_line(p, c[2], c[0], w)};
                        });
        }
}

TEST_CASE("a point covers the samples of its square, at any size", "[lines][msaa]") {
    SceneDir sd;
    std::mt19937 random(32);
    std::uniform_real_distribution<double> x(4.0, kW - 4.0), y(4.0, kH - 4.0), size(0.5, 7.0);
    for (const int msaa : {1, 4})
        for (int k = 0; k < 12; ++k) {
            const std::vector<glm::dvec2> c = {{x(random), y(random)}, {x(random), y(random)},
                                               {x(random), y(random)}};
            const double side = size(random);
            INFO(msaa << " samples, size " << side);
            check_drawn(sd, c, "draw: points, point_size: " + std::to_string(side), msaa,
                        [&](glm::dvec2 p) {
                            return std::vector<double>{inside_square(p, c[0], side),
                                                       inside_square(p, c[1], side),
                                                       inside_square(p, c[2], side)};
                        });
        }
}

TEST_CASE("a line's varyings run from one end to the other; one through the near plane keeps "
          "its visible part",
          "[lines]") {
    SceneDir sd;
    // A horizontal line from red to blue across the frame (vertex colours).
    std::ofstream(sd.dir / "line.obj") << "v -25 0 0 1 0 0\nv 25 0 0 0 0 1\nv 25 0 0 0 0 1\nf 1 2 3\n";
    const Scene s = sd.load(
        "camera: {position: [0, 0, 5], target: [0, 0, 0], projection: orthographic, height: 47}\n"
        "render: {size: [61, 47], color_format: rgba32f, clear_color: [0, 0, 0, 1]}\n"
        "objects:\n  - {mesh: line.obj, material: {shader: unlit, draw: lines, line_width: 3}}\n");
    Framebuffer fb;
    Renderer(1).render(s, fb);
    // Pixel 30's centre is at x = 0.0: halfway, in an orthographic view.
    const glm::vec4 mid = fb.pixel(30, 23);
    CHECK(mid.r == Approx(0.5).margin(0.01));
    CHECK(mid.b == Approx(0.5).margin(0.01));
    CHECK(fb.pixel(6, 23).r > 0.9f);  // near the red end
    CHECK(fb.pixel(54, 23).b > 0.9f);

    // From behind the camera to the far distance, in perspective.
    std::ofstream(sd.dir / "deep.obj") << "v 0.2 -0.1 10\nv -0.3 -0.2 -40\nv -0.3 -0.2 -40\nf 1 2 3\n";
    const Scene deep = sd.load(
        "camera: {position: [0, 0, 5], target: [0, 0, 0]}\n"
        "render: {size: [61, 47], color_format: rgba32f, clear_color: [0, 0, 0, 1]}\n"
        "objects:\n  - {mesh: deep.obj, material: {shader: unlit, draw: lines, line_width: 2}}\n");
    Framebuffer d;
    const FrameStats stats = Renderer(1).render(deep, d);
    int lit = 0, bad = 0;
    for (const glm::vec4& p : d.linear()) lit += p.r > 0.5f, bad += !std::isfinite(p.r);
    CHECK(lit > 20);
    CHECK(bad == 0);
    CHECK(stats.triangles_rasterized > 0);
}

TEST_CASE("draw: lines and points in YAML, and their widths at their line", "[lines][material]") {
    SceneDir sd;
    const std::string plane = std::string(FACET_SOURCE_DIR) + "/assets/plane/plane.obj";
    const auto material = [&](const std::string& keys) {
        return *sd.load("objects:\n  - mesh: " + plane + "\n    material: {shader: unlit, " + keys + "}\n")
                    .objects.at(0)
                    .material;
    };
    CHECK(material("draw: lines, line_width: 2.5").draw == Topology::lines);
    CHECK(material("draw: lines, line_width: 2.5").line_width == 2.5f);
    CHECK(material("draw: points, point_size: 4").point_size == 4.0f);
    CHECK(material("draw: triangles").draw == Topology::triangles);
    const auto error = [&](const std::string& keys) {
        return sd.error("objects:\n  - mesh: " + plane + "\n    material: {shader: unlit, " + keys + "}\n");
    };
    CHECK_THAT(error("draw: wires"), Catch::Contains("'wires' (expected one of: triangles, lines, points)"));
    CHECK_THAT(error("line_width: 2"), Catch::Contains("is for 'draw: lines'") && Catch::Contains("scene.yaml:3:"));
    CHECK_THAT(error("draw: points, line_width: 2"), Catch::Contains("is for 'draw: lines'"));
    CHECK_THAT(error("draw: lines, line_width: 0"), Catch::Contains("at most 256"));
    CHECK_THAT(error("draw: points, point_size: 300"), Catch::Contains("at most 256"));
}
