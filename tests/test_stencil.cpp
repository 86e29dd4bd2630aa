// The stencil buffer: GL's test and operations on one value, against their
// definitions; whole draws, where the stencil is tested per sample, after a
// shader's discards, and with the routes that skip the shader (each image
// against the one the same coverage gives drawn directly); the YAML that
// names them. llvmpipe's images hold the rest (bench/llvmpipe/tests.cpp).
#include "support.hpp"

#include "pipeline/stencil_ops.hpp"

#include <facet/renderer.hpp>

#include <catch2/catch.hpp>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <string>
#include <vector>

using namespace facet;
using namespace facet::test;

TEST_CASE("the stencil test compares the masked reference with the masked value",
          "[stencil]") {
    using C = StencilCompare;
    for (int r = 0; r < 256; r += 5)
        for (int s = 0; s < 256; s += 3)
            for (const int mask : {0xFF, 0x0F, 0xA5, 0x00}) {
                const int a = r & mask, b = s & mask;  // GL: (ref & mask) op (stencil & mask)
                const auto passes = [&](C c) {
                    return stencil_passes(c, uint8_t(r), uint8_t(s), uint8_t(mask));
                };
                INFO("ref " << r << ", stored " << s << ", mask " << mask);
                CHECK(passes(C::never) == false);
                CHECK(passes(C::always) == true);
                CHECK(passes(C::less) == (a < b));
                CHECK(passes(C::less_equal) == (a <= b));
                CHECK(passes(C::greater) == (a > b));
                CHECK(passes(C::greater_equal) == (a >= b));
                CHECK(passes(C::equal) == (a == b));
                CHECK(passes(C::not_equal) == (a != b));
            }
}

TEST_CASE("the stencil operations saturate or wrap, and change only the write mask's bits",
          "[stencil]") {
    using O = StencilOp;
    CHECK(stencil_after(O::keep, 17, 99, 0xFF) == 17);
    CHECK(stencil_after(O::zero, 17, 99, 0xFF) == 0);
    CHECK(stencil_after(O::replace, 17, 99, 0xFF) == 99);
    CHECK(stencil_after(O::increment, 17, 0, 0xFF) == 18);
    CHECK(stencil_after(O::increment, 255, 0, 0xFF) == 255);
    CHECK(stencil_after(O::increment_wrap, 255, 0, 0xFF) == 0);
    CHECK(stencil_after(O::decrement, 0, 0, 0xFF) == 0);
    CHECK(stencil_after(O::decrement, 17, 0, 0xFF) == 16);
    CHECK(stencil_after(O::decrement_wrap, 0, 0, 0xFF) == 255);
    CHECK(stencil_after(O::invert, 0x5A, 0, 0xFF) == 0xA5);
    // Masked: the bits outside the mask keep their value.
    CHECK(stencil_after(O::replace, 0xF0, 0x3C, 0x0F) == 0xFC);
    CHECK(stencil_after(O::invert, 0xF0, 0, 0x0F) == 0xFF);
    CHECK(stencil_after(O::increment_wrap, 0x0F, 0, 0x0F) == 0x00);  // 0x10 masked to 0x0
    CHECK(stencil_after(O::zero, 0xFF, 0, 0x00) == 0xFF);
}

namespace {

const std::string kPlane = std::string(FACET_SOURCE_DIR) + "/assets/plane/plane.obj";
const std::string kSphere = std::string(FACET_SOURCE_DIR) + "/assets/sphere/sphere.obj";

// A scene of `objects` (YAML list items) at `msaa` samples, over black.
std::string scene_text(const std::string& objects, int msaa, const std::string& extra = "") {
    return "camera: {position: [0, 0, 3], target: [0, 0, 0], fov_y: 50}\n"
           "render: {size: [61, 47], color_format: rgba32f, clear_color: [0, 0, 0, 1], msaa: " +
           std::to_string(msaa) + extra + "}\n"
           "objects:\n" + objects;
}

// The frame, drawn on `isa`.
std::vector<glm::vec4> rendered(const Scene& scene, Isa isa) {
    Framebuffer fb;
    Renderer(2, isa).render(scene, fb);
    return fb.linear();
}

// Writes an 8x8 white texture whose columns alternate alpha 0 and 1 into
// the scene's folder; its path.
std::string columns_texture(SceneDir& sd) {
    std::vector<uint8_t> rgba;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) rgba.insert(rgba.end(), {255, 255, 255, uint8_t(x % 2 ? 255 : 0)});
    const std::string texture = (sd.dir / "columns.png").string();
    REQUIRE(stbi_write_png(texture.c_str(), 8, 8, 4, rgba.data(), 8 * 4));
    return texture;
}

// `scene` drawn on every path gives `want`.
void check_every_path(const Scene& scene, const std::vector<glm::vec4>& want) {
    for (const Isa isa : supported_isas()) {
        INFO("path " << isa_name(isa));
        CHECK(rendered(scene, isa) == want);
    }
}

// Pixels of `image` that are exactly `c`.
int count_of(const std::vector<glm::vec4>& image, glm::vec4 c) {
    return int(std::count(image.begin(), image.end(), c));
}

// A mask (writes stencil 1 where `shape` covers, no colour, no depth),
// then a white quad over the frame where the stencil is 1.
std::string masked(const std::string& shape) {
    return shape +
           "    material: {shader: unlit, color_write: false, depth_write: false,\n"
           "               stencil: {test: always, ref: 1, pass: replace}}\n"
           "  - mesh: " + kPlane + "\n    rotation: [90, 0, 0]\n    scale: 4\n"
           "    position: [0, 0, -0.5]\n"
           "    material: {shader: unlit, stencil: {test: equal, ref: 1}}\n";
}

}  // namespace

TEST_CASE("the stencil holds the coverage of a draw, sample by sample, on every route",
          "[stencil][msaa]") {
    // A sphere of small triangles as the mask: at one sample its narrow
    // triangles would take the depth-only loop, which knows no stencil. The
    // white quad then shows exactly the sphere's coverage.
    SceneDir sd;
    const std::string sphere = "  - mesh: " + kSphere + "\n    scale: 0.8\n";
    for (const int msaa : {1, 4})
        for (const char* prepass : {"", ", depth_prepass: true"}) {
            INFO(msaa << " samples" << prepass);
            const Scene mask = sd.load(scene_text(masked(sphere), msaa, prepass));
            const Scene direct = sd.load(scene_text(sphere + "    material: {shader: unlit}\n", msaa));
            const std::vector<glm::vec4> want = rendered(direct, default_isa());
            CHECK(count_of(want, glm::vec4(1.0f)) > 200);
            check_every_path(mask, want);
        }
}

TEST_CASE("a fragment the shader discards, or whose alpha covers no sample, writes no stencil",
          "[stencil][cutout]") {
    // Columns of alpha 0 and 1 across the texture: the cutout removes every
    // other column (alpha_cutoff at one sample, alpha to coverage at four).
    SceneDir sd;
    const std::string texture = columns_texture(sd);
    for (const int msaa : {1, 4}) {
        INFO(msaa << " samples");
        const std::string cut = msaa == 1 ? "alpha_cutoff: 0.5" : "alpha_cutoff: 0";
        const std::string coverage = msaa == 1 ? "" : "alpha_to_coverage: true, ";
        const std::string quad = "  - mesh: " + kPlane + "\n    rotation: [90, 0, 0]\n";
        const std::string params =
            "params: {base_texture: {file: " + texture + ", filter: nearest}, " + cut + "}";
        const Scene mask = sd.load(scene_text(
            quad + "    material: {shader: unlit, color_write: false, depth_write: false, " +
                coverage + "stencil: {test: always, ref: 1, pass: replace}, " + params + "}\n" +
                "  - mesh: " + kPlane + "\n    rotation: [90, 0, 0]\n    scale: 4\n"
                "    position: [0, 0, -0.5]\n"
                "    material: {shader: unlit, stencil: {test: equal, ref: 1}}\n",
            msaa));
        const Scene direct = sd.load(
            scene_text(quad + "    material: {shader: unlit, " + coverage + params + "}\n", msaa));
        const std::vector<glm::vec4> want = rendered(direct, default_isa());
        CHECK(count_of(want, glm::vec4(1.0f)) > 100);
        CHECK(count_of(want, glm::vec4(0, 0, 0, 1)) > 100);
        check_every_path(mask, want);
    }
}

TEST_CASE("the stencil's YAML: every test and operation, back faces, and bad values at their line",
          "[stencil][material]") {
    SceneDir sd;
    const auto material = [&](const std::string& stencil) {
        const Scene s = sd.load("objects:\n  - mesh: " + kPlane +
                                "\n    material: {shader: unlit, color_write: false,\n"
                                "               stencil: " + stencil + "}\n");
        return *s.objects.at(0).material;
    };
    const Material m = material(
        "{test: not_equal, ref: 3, read_mask: 0x0F, write_mask: 254, fail: increment_wrap,\n"
        "                        depth_fail: invert, pass: decrement, back: {test: less, pass: zero}}");
    CHECK_FALSE(m.color_write);
    REQUIRE(m.stencil.enabled);
    const StencilFace& f = m.stencil.front;
    CHECK(f.compare == StencilCompare::not_equal);
    CHECK(int(f.reference) == 3);
    CHECK(int(f.read_mask) == 0x0F);
    CHECK(int(f.write_mask) == 254);
    CHECK(f.fail == StencilOp::increment_wrap);
    CHECK(f.depth_fail == StencilOp::invert);
    CHECK(f.pass == StencilOp::decrement);
    // The back faces take the front's state, then their own keys.
    const StencilFace& b = m.stencil.back;
    CHECK(b.compare == StencilCompare::less);
    CHECK(b.pass == StencilOp::zero);
    CHECK(b.fail == StencilOp::increment_wrap);
    CHECK(int(b.reference) == 3);
    CHECK_FALSE(material("{}").stencil.front.compare != StencilCompare::always);

    const auto error = [&](const std::string& stencil) {
        return sd.error("objects:\n  - mesh: " + kPlane +
                        "\n    material: {shader: unlit, stencil: " + stencil + "}\n");
    };
    CHECK_THAT(error("{test: lequal}"),
               Catch::Contains("'lequal' (expected one of: never, less, less_equal") &&
                   Catch::Contains("scene.yaml:3:"));
    CHECK_THAT(error("{pass: incr}"), Catch::Contains("'incr' (expected one of: keep, zero"));
    CHECK_THAT(error("{ref: 256}"), Catch::Contains("0 to 255"));
    CHECK_THAT(error("{write_mask: -1}"), Catch::Contains("0 to 255"));
    CHECK_THAT(error("{read_mask: 0x100}"), Catch::Contains("0x00 to 0xFF"));
    CHECK_THAT(error("{read_mask: 0xG1}"), Catch::Contains("0x00 to 0xFF"));
    CHECK_THAT(error("{test: equal, func: less}"), Catch::Contains("'func'"));
    CHECK_THAT(error("{back: {back: {}}}"), Catch::Contains("'back'"));
    CHECK_THAT(sd.error("render: {clear_stencil: 300}\nobjects: []\n"), Catch::Contains("0 to 255"));
}

TEST_CASE("with a sky shown, a part that writes colour and no depth still draws where the "
          "stencil lets it",
          "[stencil][environment]") {
    // The sky fills what is still at the far depth. A stencil frame keeps
    // its parts in order, so the sky comes before the part that writes no
    // depth, not over it.
    SceneDir sd;
    const std::string sky = "environment: {file: " + std::string(FACET_SOURCE_DIR) +
                            "/assets/environments/sky.hdr, use: background, size: 32}\n";
    const std::string quad = "  - mesh: " + kPlane + "\n    rotation: [90, 0, 0]\n    scale: 0.5\n";
    const Scene s = sd.load(
        sky + scene_text(quad +
                             "    material: {shader: unlit, color_write: false, depth_write: false,\n"
                             "               stencil: {test: always, ref: 1, pass: replace}}\n"
                             "  - mesh: " + kPlane + "\n    rotation: [90, 0, 0]\n    scale: 4\n"
                             "    material: {shader: unlit, depth_write: false,\n"
                             "               stencil: {test: equal, ref: 1},\n"
                             "               params: {base_color: [1, 0, 1, 1]}}\n",
                         1));
    for (const Isa isa : supported_isas()) {
        INFO("path " << isa_name(isa));
        Framebuffer fb;
        Renderer(1, isa).render(s, fb);
        CHECK(fb.pixel(30, 23) == glm::vec4(1, 0, 1, 1));  // the quad, inside the mask
        CHECK(fb.pixel(2, 2) != glm::vec4(1, 0, 1, 1));    // the sky, outside it
        CHECK(fb.pixel(2, 2) != glm::vec4(0, 0, 0, 1));
    }
}

TEST_CASE("a part that writes no colour writes depth only where its alpha covers", "[cutout][msaa]") {
    // color_write: false with alpha to coverage: its depth hides a white
    // quad behind it exactly where the same part drawn in black would.
    SceneDir sd;
    const std::string texture = columns_texture(sd);
    const std::string behind = "  - mesh: " + kPlane + "\n    rotation: [90, 0, 0]\n    scale: 4\n"
                               "    position: [0, 0, -0.5]\n    material: {shader: unlit}\n";
    const auto front = [&](const std::string& colour) {
        return "  - mesh: " + kPlane + "\n    rotation: [90, 0, 0]\n"
               "    material: {shader: unlit, alpha_to_coverage: true, " + colour +
               "params: {base_color: [0, 0, 0, 1], base_texture: {file: " + texture +
               ", filter: nearest}}}\n";
    };
    for (const int msaa : {1, 4}) {
        INFO(msaa << " samples");
        const Scene masked = sd.load(scene_text(front("color_write: false, ") + behind, msaa));
        const Scene black = sd.load(scene_text(front("") + behind, msaa));
        const std::vector<glm::vec4> want = rendered(black, default_isa());
        CHECK(count_of(want, glm::vec4(1.0f)) > 100);
        check_every_path(masked, want);
    }
}
