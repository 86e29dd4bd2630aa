// Multisampling through Pipeline::draw, against exact and double-precision
// references: per-sample coverage of shared edges, the resolve and
// per-sample depth.
#include "support.hpp"

#include <facet/framebuffer.hpp>

#include <catch2/catch.hpp>

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <vector>

using namespace facet;
using namespace facet::test;

namespace {

constexpr int W = 64, H = 48;

// `mesh` drawn into a fresh W x H target with `samples` samples, cleared
// to black and far depth (reversed-Z).
Framebuffer draw_msaa(const Mesh& mesh, const ShaderPlugin& shader, int samples,
                      BlendMode blend = BlendMode::opaque) {
    Framebuffer fb(W, H, ColorFormat::rgba32f, samples);
    fb.clear(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), 0.0f);
    DrawCall call = clip_space_call(mesh, shader);  // no culling, no depth test
    call.state.blend = blend;
    FrameStats stats;
    Pipeline(1).draw(call, fb, stats);
    fb.resolve();
    return fb;
}

glm::dvec2 sample_position(int x, int y, int n, int s) {
    const glm::ivec2 o = sample_offset(n, s);
    return {x + 0.5 + o.x / 16.0, y + 0.5 + o.y / 16.0};
}

glm::dvec2 to_ndc(glm::dvec2 window) { return {window.x / W * 2 - 1, 1 - window.y / H * 2}; }

}  // namespace

TEST_CASE("MSAA: shared edges cover every sample exactly once", "[msaa][watertight]") {
    static auto shader = plugin<CountShader>();
    for (int n : {2, 4, 8}) {
        for (int step = 0; step < 12; ++step) {
            CAPTURE(n, step);
            const float r = 0.8f;
            const glm::vec2 centre(0.017f * float(step % 5), -0.013f * float(step % 3));
            const int sides = 5 + 3 * step;
            Framebuffer fb = draw_msaa(fan(sides, r, 0.29f * float(step), centre), *shader, n,
                                       BlendMode::additive);
            const double inner = r * std::cos(glm::pi<double>() / sides) - 2.0 / H;
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x)
                    for (int s = 0; s < n; ++s) {
                        const float count = fb.sample(x, y, s).r;
                        REQUIRE(count <= 1.0f);
                        const glm::dvec2 ndc = to_ndc(sample_position(x, y, n, s));
                        if (glm::length(ndc - glm::dvec2(centre)) < inner) REQUIRE(count == 1.0f);
                    }
        }
    }
}

TEST_CASE("MSAA: the resolve gives each pixel its covered fraction", "[msaa]") {
    static auto shader = plugin<CountShader>();
    // One big triangle whose long edge crosses the target at a slope no
    // sample lies on; every other edge is far off screen.
    const glm::dvec2 a(-20.0, -10.0), b(90.0, 40.3);  // window coordinates
    const glm::vec3 pa = window_to_ndc(a, W, H), pb = window_to_ndc(b, W, H);
    const glm::vec3 pc = window_to_ndc({-20.0, 200.0}, W, H);
    const Mesh mesh = make_mesh({pa, pb, pc}, {0, 1, 2});
    for (int n : {2, 4, 8}) {
        CAPTURE(n);
        const Framebuffer fb = draw_msaa(mesh, *shader, n);
        int partial = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                int covered = 0;  // samples below the line a-b (y down)
                for (int s = 0; s < n; ++s) {
                    const glm::dvec2 p = sample_position(x, y, n, s);
                    covered += (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) > 0;
                }
                partial += covered > 0 && covered < n;
                REQUIRE(fb.pixel(x, y).r == float(covered) / float(n));
            }
        CHECK(partial > 10);  // the edge really crossed pixels partly
    }
}

TEST_CASE("MSAA: depth is tested per sample on the exact depth plane", "[msaa][depth]") {
    // Two planes crossing along a slanted line: at every sample the nearer
    // one (larger z, reversed-Z) wins, judged in double precision.
    const glm::vec3 quad[4] = {window_to_ndc({0, 0}, W, H), window_to_ndc({W, 0}, W, H),
                               window_to_ndc({W, H}, W, H), window_to_ndc({0, H}, W, H)};
    auto depth_a = [](glm::dvec2 p) { return 0.2 + 0.6 * p.x / W; };
    auto depth_b = [](glm::dvec2 p) { return 0.7 - 0.3 * p.x / W + 0.2 * p.y / H; };
    auto plane = [&](auto depth, glm::vec4 color) {
        std::vector<glm::vec3> pos;
        const glm::dvec2 window[4] = {{0, 0}, {W, 0}, {W, H}, {0, H}};
        for (int i = 0; i < 4; ++i) pos.push_back({quad[i].x, quad[i].y, float(depth(window[i]))});
        return make_mesh(pos, {0, 1, 2, 0, 2, 3}, std::vector<glm::vec4>(4, color));
    };
    const Mesh red = plane(depth_a, {1, 0, 0, 1}), green = plane(depth_b, {0, 1, 0, 1});
    static auto shader = plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>();
    for (int n : {4, 8}) {
        Framebuffer fb(W, H, ColorFormat::rgba32f, n);
        fb.clear(glm::vec4(0.0f), 0.0f);
        FrameStats stats;
        Pipeline renderer(1);
        for (const Mesh* m : {&red, &green}) {
            DrawCall call = clip_space_call(*m, *shader);
            call.state.depth_compare = DepthCompare::greater_equal;  // reversed-Z
            renderer.draw(call, fb, stats);
        }
        int checked = 0;
        double max_error = 0.0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                for (int s = 0; s < n; ++s) {
                    const glm::dvec2 p = sample_position(x, y, n, s);
                    const double za = depth_a(p), zb = depth_b(p);
                    max_error = std::max(max_error,
                                         std::abs(fb.sample_depth_at(x, y, s) - std::max(za, zb)));
                    if (std::abs(za - zb) < 1e-5) continue;  // too close to call in float
                    REQUIRE(fb.sample(x, y, s).r == (za > zb ? 1.0f : 0.0f));
                    ++checked;
                }
        INFO("max per-sample depth error " << max_error);
        CHECK(max_error < 1e-6);
        CHECK(checked > W * H * n * 9 / 10);
    }
}
