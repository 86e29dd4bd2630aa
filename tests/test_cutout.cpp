// Cutouts and alpha to coverage: a texture's alpha cuts a shape out of a
// quad (alpha_cutoff: discarded fragments write neither colour nor depth,
// in the main pass, the shadow maps and the AO pre-pass), and, under MSAA,
// alpha chooses how many of a pixel's samples a fragment covers
// (alpha_to_coverage), as PipelineState documents.
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace facet;

namespace {

// A 2x2 quad facing +Z with UVs, 0 at the left edge, 1 at the right.
constexpr const char* kUvQuad =
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";

// Renders the scene file `text` (in `dir`) into a float target.
Framebuffer render(const test::TempDir& dir, const std::string& text) {
    dir.write("scene.yaml", text);
    PluginRegistry registry;
    const Scene scene = load_scene(dir.path / "scene.yaml", registry);
    Renderer renderer(2);
    Framebuffer fb;
    renderer.render(scene, fb);
    return fb;
}

// A folder with the quad and a 2x1 texture: left texel transparent, right
// one opaque white.
struct Fixture {
    test::TempDir dir{"cutout"};
    Fixture() {
        dir.write("quad.obj", kUvQuad);
        write_png(dir.path / "half.png", 2, 1, {255, 255, 255, 0, 255, 255, 255, 255});
    }
};

}  // namespace

TEST_CASE("a cutout discards what its alpha leaves below the cutoff, colour and depth",
          "[cutout]") {
    Fixture f;
    // A red quad behind, drawn last: it shows wherever the front one was
    // cut out, and only there (the front one writes depth where it stays).
    const auto scene = [](const std::string& shader, const std::string& front_params) {
        return "render: {size: [32, 32], color_format: rgba32f}\n"
               "camera: {position: [0, 0, 2.4], target: [0, 0, 0]}\n"
               "lights: [{type: directional, direction: [0, 0, -1]}]\n"
               "objects:\n"
               "  - {mesh: quad.obj, position: [0, 0, 0.2], material: {shader: " + shader +
               ", params: {" + front_params + "}}}\n"
               "  - {mesh: quad.obj, scale: 3, material: {shader: unlit, params: "
               "{base_color: [1, 0, 0, 1]}}}\n";
    };
    for (const std::string shader : {"unlit", "lit", "phong"}) {
        CAPTURE(shader);
        const std::string texture = "base_texture: {file: half.png, filter: nearest}";
        const Framebuffer cut = render(f.dir, scene(shader, texture + ", alpha_cutoff: 0.5"));
        CHECK(cut.pixel(8, 16) == glm::vec4(1, 0, 0, 1));  // cut away: the red quad
        CHECK(cut.pixel(24, 16).g > 0.1f);                  // kept: white (lit) over red
        // No cutoff: nothing is discarded, and the transparent half hides the red.
        const Framebuffer whole = render(f.dir, scene(shader, texture));
        CHECK(whole.pixel(8, 16).r == whole.pixel(8, 16).g);
    }
    // A uniform alpha below and above the cutoff.
    CHECK(render(f.dir, scene("unlit", "base_color: [0, 1, 0, 0.4], alpha_cutoff: 0.5"))
              .pixel(16, 16) == glm::vec4(1, 0, 0, 1));
    CHECK(render(f.dir, scene("unlit", "base_color: [0, 1, 0, 0.6], alpha_cutoff: 0.5"))
              .pixel(16, 16) == glm::vec4(0, 1, 0, 0.6f));
}

TEST_CASE("a cutout casts a shadow only where it stays, and is cut out of the AO pre-pass",
          "[cutout][shadow]") {
    Fixture f;
    // A phong floor under the half-transparent quad, lit from straight above.
    const auto scene = [](const std::string& cutoff) {
        return "render: {size: [64, 64], color_format: rgba32f, shadow_map_size: 256}\n"
               "camera: {position: [0, 6, 0.01], target: [0, 0, 0], fov_y: 40}\n"
               "lights: [{type: directional, direction: [0, -1, 0], casts_shadow: true}]\n"
               "objects:\n"
               "  - {mesh: quad.obj, scale: 4, rotation: [-90, 0, 0], material: {shader: "
               "phong, params: {ambient: [0, 0, 0], specular: [0, 0, 0], diffuse: [1, 1, 1]}}}\n"
               "  - {mesh: quad.obj, position: [0, 1, 0], rotation: [-90, 0, 0], "
               "material: {shader: unlit, cull: none, params: {base_color: [0, 0, 1, 1], "
               "base_texture: {file: half.png, filter: nearest}" + cutoff + "}}}\n";
    };
    // From above, x runs right and the quad's left half (u < 0.5) is cut away.
    const Framebuffer cut = render(f.dir, scene(", alpha_cutoff: 0.5"));
    const Framebuffer solid = render(f.dir, scene(""));
    // Beside the quad, on the floor: lit in both. Under its cut-away half:
    // lit only when cut. Under its kept half: the quad itself (blue).
    CHECK(cut.pixel(4, 32).r > 0.5f);
    CHECK(cut.pixel(26, 32).r > 0.5f);     // the floor through the cut-away half, lit
    CHECK(solid.pixel(26, 32).r < 0.02f);  // not cut: the quad (blue, no red)
    CHECK(cut.pixel(38, 32) == glm::vec4(0, 0, 1, 1));
}

TEST_CASE("alpha to coverage covers floor(alpha n + dither) samples of each pixel",
          "[cutout][msaa]") {
    Fixture f;
    static constexpr int kDither[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
    // The share of samples a fragment of `alpha` covers at pixel (x, y).
    const auto covered = [](float alpha, int n, int x, int y) {
        const double d = (kDither[(y % 4) * 4 + x % 4] + 0.5) / 16.0;
        return std::min(n, int(std::floor(double(alpha) * n + d)));
    };
    for (const int n : {1, 2, 4, 8})
        for (const float alpha : {0.0f, 0.3f, 0.5f, 0.8f, 1.0f}) {
            CAPTURE(n, alpha);
            // A green quad with alpha to coverage over a red one drawn after it:
            // the red shows in exactly the samples the green left uncovered.
            const Framebuffer fb = render(
                f.dir,
                "render: {size: [8, 8], color_format: rgba32f, msaa: " + std::to_string(n) +
                    "}\ncamera: {position: [0, 0, 2], target: [0, 0, 0]}\nobjects:\n"
                    "  - {mesh: quad.obj, position: [0, 0, 0.2], scale: 2, material: {shader: "
                    "unlit, alpha_to_coverage: true, params: {base_color: [0, 1, 0, " +
                    std::to_string(alpha) + "]}}}\n"
                    "  - {mesh: quad.obj, scale: 3, material: {shader: unlit, params: "
                    "{base_color: [1, 0, 0, 1]}}}\n");
            double mean = 0.0;
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 8; ++x) {
                    const int k = covered(alpha, n, x, y);
                    const glm::vec4 p = fb.pixel(x, y);
                    CHECK(p.g == Approx(double(k) / n).margin(1e-6));
                    CHECK(p.r == Approx(double(n - k) / n).margin(1e-6));
                    mean += p.g / 64.0;
                }
            CHECK(mean == Approx(alpha).margin(1.0 / n));  // the dither keeps the average
        }
}

TEST_CASE("cutout and alpha-to-coverage settings are checked, with file and line",
          "[cutout][config]") {
    Fixture f;
    const auto error_of = [&](const std::string& material) {
        try {
            render(f.dir, "objects:\n  - {mesh: quad.obj, material: " + material + "}\n");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    using Catch::Matchers::Contains;
    CHECK_THAT(error_of("{shader: unlit, alpha_to_coverage: sometimes}"),
               Contains("scene.yaml:2") && Contains("got 'sometimes'"));
    CHECK_THAT(error_of("{shader: unlit, params: {alpha_cutoff: 1.5}}"),
               Contains("scene.yaml:2") && Contains("outside 0 .. 1"));
    CHECK(error_of("{shader: phong, alpha_to_coverage: true, params: {alpha_cutoff: 0.5}}") ==
          "no error");
}
