// The wireframe (PipelineState::wireframe, RenderSettings::wireframe) and
// the depth bias under it: the bias against Vulkan's rule in double
// precision; the wire's samples against the exact rectangles of the edges
// its culling keeps, at 1 and 4 samples; its facing against the surface's,
// for triangles with corners behind the eye; and a frame's wire, shown
// over its own sloping surface and hidden behind another.
#include "support.hpp"

#include <facet/renderer.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <utility>
#include <vector>

using namespace facet;
using namespace facet::test;

namespace {

constexpr int W = 64, H = 48;

glm::dvec2 to_window(glm::dvec2 ndc) {
    return {(ndc.x + 1.0) / 2.0 * W, (1.0 - ndc.y) / 2.0 * H};
}

// The largest of the depth's slopes per pixel in x and y, of the plane
// through three window positions and their depths.
double depth_slope(const glm::dvec3 p[3]) {
    const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    const double det = e1.x * e2.y - e2.x * e1.y;
    const double dzdx = (e1.z * e2.y - e2.z * e1.y) / det;
    const double dzdy = (e2.z * e1.x - e1.z * e2.x) / det;
    return std::max(std::abs(dzdx), std::abs(dzdy));
}

Framebuffer draw_depth(const Mesh& mesh, const ShaderPlugin& shader, float constant, float slope) {
    Framebuffer fb(W, H, ColorFormat::rgba32f, 1);
    fb.clear(glm::vec4(0.0f), 0.0f);
    DrawCall call = clip_space_call(mesh, shader);  // depth always passes and is written
    call.state.depth_bias_constant = constant;
    call.state.depth_bias_slope = slope;
    FrameStats stats;
    Pipeline(1).draw(call, fb, stats);
    return fb;
}

// The triangles' edges that `cull` keeps one of the triangles of (corners
// in NDC, w = 1), each once, in window positions.
std::vector<std::pair<glm::dvec2, glm::dvec2>> kept_edges(const std::vector<glm::vec3>& pos,
                                                          const std::vector<uint32_t>& idx,
                                                          CullMode cull) {
    std::map<std::pair<uint32_t, uint32_t>, bool> shown;
    for (size_t t = 0; t < idx.size(); t += 3) {
        const glm::dvec2 a(pos[idx[t]]), b(pos[idx[t + 1]]), c(pos[idx[t + 2]]);
        const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        const bool front = area > 0.0;  // counter-clockwise with y up
        bool finite = true;  // else the triangle is invalid, and has no wire
        for (size_t k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) finite &= std::isfinite(pos[idx[t + k]][i]);
        const bool kept = finite && area != 0.0 &&
                          !(front && cull == CullMode::front) && !(!front && cull == CullMode::back);
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t u = idx[t + k], v = idx[t + (k + 1) % 3];
            shown[{std::min(u, v), std::max(u, v)}] |= kept;
        }
    }
    std::vector<std::pair<glm::dvec2, glm::dvec2>> edges;
    for (const auto& [e, kept] : shown)
        if (kept)
            edges.push_back(
                {to_window(glm::dvec2(pos[e.first])), to_window(glm::dvec2(pos[e.second]))});
    return edges;
}

// A grid of jittered vertices with two triangles a cell, each turned the
// other way at random.
void random_grid(std::mt19937& rng, std::vector<glm::vec3>& pos, std::vector<uint32_t>& idx) {
    std::uniform_real_distribution<float> jitter(-0.12f, 0.12f);
    constexpr int kX = 5, kY = 4;
    pos.clear();
    idx.clear();
    for (int j = 0; j < kY; ++j)
        for (int i = 0; i < kX; ++i)
            pos.push_back({-0.85f + 1.7f * float(i) / (kX - 1) + jitter(rng),
                           -0.85f + 1.7f * float(j) / (kY - 1) + jitter(rng), 0.5f});
    for (int j = 0; j + 1 < kY; ++j)
        for (int i = 0; i + 1 < kX; ++i) {
            const uint32_t a = uint32_t(j * kX + i), b = a + 1, c = a + kX + 1, d = a + kX;
            for (std::vector<uint32_t> tri : {std::vector<uint32_t>{a, b, c}, {a, c, d}}) {
                if (rng() % 3 == 0) std::swap(tri[1], tri[2]);
                idx.insert(idx.end(), tri.begin(), tri.end());
            }
        }
}

}  // namespace

TEST_CASE("depth bias moves each triangle's depth by Vulkan's rule", "[wireframe][depth]") {
    static auto shader = plugin<CountShader>();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> xy(-0.95f, 0.95f), depth(0.1f, 0.9f);
    int checked = 0;
    for (int round = 0; round < 60; ++round) {
        std::vector<glm::vec3> pos(3);
        glm::dvec3 window[3];
        for (int k = 0; k < 3; ++k) {
            pos[size_t(k)] = {xy(rng), xy(rng), depth(rng)};
            window[k] = glm::dvec3(to_window(glm::dvec2(pos[size_t(k)])), pos[size_t(k)].z);
        }
        const glm::dvec3 e1 = window[1] - window[0], e2 = window[2] - window[0];
        if (std::abs(e1.x * e2.y - e2.x * e1.y) < 400.0) continue;  // slivers slope steeply
        const Mesh mesh = make_mesh(pos, {0, 1, 2});
        // Constants alone (their r doubled or halved would show), slopes alone, and both.
        const float constant = round % 4 == 0 ? 256.0f : round % 4 == 1 ? -256.0f : 0.0f;
        const float slope = round % 4 < 2 ? 0.0f : round % 4 == 2 ? 0.75f : -1.5f;
        const Framebuffer plain = draw_depth(mesh, *shader, 0.0f, 0.0f);
        const Framebuffer biased = draw_depth(mesh, *shader, constant, slope);
        const double largest = std::max({window[0].z, window[1].z, window[2].z});
        const double r = std::ldexp(1.0, std::ilogb(float(largest)) - 23);
        const double bias = constant * r + slope * depth_slope(window);
        CAPTURE(round, constant, slope, bias);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                if (plain.depth_at(x, y) == 0.0f) continue;  // not covered
                CAPTURE(x, y);
                // The corners' depths round to float, and the snapped plane
                // slopes within a part in a thousand of the exact one.
                REQUIRE(biased.depth_at(x, y) ==
                        Approx(plain.depth_at(x, y) + bias)
                            .margin(3 * r + 1e-3 * std::abs(slope * depth_slope(window))));
                ++checked;
            }
    }
    CHECK(checked > 5000);

    SECTION("the depth is held inside 0..1") {
        const Mesh mesh =
            make_mesh({{-0.8f, -0.8f, 0.2f}, {0.8f, -0.7f, 0.9f}, {0.1f, 0.8f, 0.5f}}, {0, 1, 2});
        const Framebuffer high = draw_depth(mesh, *shader, 1e9f, 0.0f);
        const Framebuffer low = draw_depth(mesh, *shader, -1e9f, -4.0f);
        const Framebuffer plain = draw_depth(mesh, *shader, 0.0f, 0.0f);
        int covered = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                if (plain.depth_at(x, y) == 0.0f) continue;
                ++covered;
                CHECK(high.depth_at(x, y) == 1.0f - 0x1p-24f);  // not onto an end
                CHECK(low.depth_at(x, y) == std::numeric_limits<float>::min());
            }
        CHECK(covered > 500);
    }
}

namespace {

// The wire of `idx` over `pos` (NDC, w = 1) under `cull` at n samples,
// added in white: each sample counts its lines, which must be those of
// the exact rectangles of kept_edges (check_coverage).
void check_wire(const std::vector<glm::vec3>& pos, const std::vector<uint32_t>& idx,
                CullMode cull, int n, int& covered) {
    static auto shader = plugin<CountShader>();
    const Mesh mesh = make_mesh(pos, idx);
    Framebuffer fb(W, H, ColorFormat::rgba32f, n);
    fb.clear(glm::vec4(0.0f), 0.0f);
    DrawCall call = clip_space_call(mesh, *shader);
    call.state.cull = cull;
    call.state.wireframe = true;
    call.state.wire_color = glm::vec3(1.0f);
    call.state.blend = BlendMode::additive;  // red counts each line over a sample
    FrameStats stats;
    Pipeline(1).draw(call, fb, stats);
    const auto edges = kept_edges(pos, idx, cull);
    CAPTURE(int(cull), n, edges.size());
    CHECK(stats.fragments_shaded == 0);  // no fragment shader runs
    check_coverage(
        fb,
        [&](glm::dvec2 p) {
            std::vector<double> inside;
            for (const auto& [a, b] : edges) inside.push_back(inside_line(p, a, b, 1.0));
            return inside;
        },
        covered);
}

}  // namespace

TEST_CASE("the wire covers the exact rectangles of the edges its culling keeps, each once",
          "[wireframe]") {
    std::mt19937 rng(5);
    int covered = 0;
    for (int round = 0; round < 6; ++round)
        for (CullMode cull : {CullMode::none, CullMode::back, CullMode::front})
            for (int n : {1, 4}) {
                std::vector<glm::vec3> pos;
                std::vector<uint32_t> idx;
                random_grid(rng, pos, idx);
                CAPTURE(round);
                check_wire(pos, idx, cull, n, covered);
            }
    CHECK(covered > 20000);
}

TEST_CASE("an edge of three triangles, or of one with no area, is drawn once, and an edge of "
          "an invalid triangle alone not at all",
          "[wireframe]") {
    // A fin: three triangles on the edge 0-1, one turned away; a triangle
    // with a repeated corner on it; one more on the edge 1-2; and one with
    // a NaN corner (which the vertex shader's matrix spreads to all four
    // coordinates), whose edge 3-4, both ends finite, no other shares.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<glm::vec3> pos = {{-0.6f, -0.1f, 0.5f}, {0.7f, 0.2f, 0.5f}, {0.1f, 0.8f, 0.5f},
                                        {0.0f, -0.8f, 0.5f}, {-0.3f, 0.6f, 0.5f}, {0.8f, 0.9f, 0.5f},
                                        {0.2f, 0.1f, nan}};
    const std::vector<uint32_t> idx = {0, 1, 2, 0, 3, 1, 1, 0, 4, 0, 1, 0, 2, 1, 5, 3, 4, 6};
    int covered = 0;
    for (CullMode cull : {CullMode::none, CullMode::back, CullMode::front})
        for (int n : {1, 4}) check_wire(pos, idx, cull, n, covered);
    CHECK(covered > 1000);
}

TEST_CASE("the wire's facing is its triangles', with corners behind the eye", "[wireframe]") {
    static auto shader = plugin<CountShader>();
    // Clip (x, y, w / 2, w) of position (x, y, w).
    glm::mat4 projection(0.0f);
    projection[0][0] = projection[1][1] = 1.0f;
    projection[2][2] = 0.5f;
    projection[2][3] = 1.0f;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> xy(-2.0f, 2.0f), w(-1.0f, 2.0f);
    int back = 0, shown = 0;
    for (int round = 0; round < 3000; ++round) {
        const Mesh mesh = make_mesh(
            {{xy(rng), xy(rng), w(rng)}, {xy(rng), xy(rng), w(rng)}, {xy(rng), xy(rng), w(rng)}},
            {0, 1, 2});
        Framebuffer fb(W, H, ColorFormat::rgba32f, 1);
        const auto draw = [&](bool wireframe) {
            fb.clear(glm::vec4(0.0f), 0.0f);
            DrawCall call = clip_space_call(mesh, *shader);
            call.projection = projection;
            call.state.cull = CullMode::back;
            call.state.wireframe = wireframe;
            FrameStats stats;
            Pipeline(1).draw(call, fb, stats);
            return stats;
        };
        const FrameStats surface = draw(false);
        const FrameStats wire = draw(true);
        CAPTURE(round);
        if (surface.triangles_culled_backface == 1) {
            ++back;
            CHECK(wire.triangles_culled_backface == 3);
        } else if (surface.triangles_rasterized == 1) {
            ++shown;
            CHECK(wire.triangles_culled_backface == 0);
        }
    }
    CHECK(back > 300);
    CHECK(shown > 300);
}

TEST_CASE("a frame's wire shows over its own sloping surface and hides behind another",
          "[wireframe][renderer]") {
    // Two quads under an orthographic camera of a unit a pixel, each
    // sloping in depth: one at the back, and one in front over its middle,
    // which the back one's diagonal passes under.
    using Quad = std::vector<glm::dvec3>;  // pixel x, y (down) and depth z, top left first
    const Quad back = {{4, 4, -3.0}, {58, 6, -0.1}, {56, 44, -0.2}, {6, 42, -2.9}};
    const Quad front = {{20, 12, 0.6}, {44, 14, 0.5}, {42, 36, 3.3}, {22, 34, 3.0}};
    const auto obj = [](const Quad& q) {
        std::ostringstream out;
        out.precision(17);
        for (const glm::dvec3& p : q)
            out << "v " << p.x - W / 2.0 << ' ' << H / 2.0 - p.y << ' ' << p.z << '\n';
        out << "f 1 4 3\nf 1 3 2\n";  // counter-clockwise as seen: the diagonal 1-3
        return out.str();
    };
    const auto edges = [](const Quad& q) {
        std::vector<std::pair<glm::dvec2, glm::dvec2>> e;
        for (int k = 0; k < 4; ++k)
            e.push_back({glm::dvec2(q[size_t(k)]), glm::dvec2(q[size_t(k + 1) % 4])});
        e.push_back({glm::dvec2(q[0]), glm::dvec2(q[2])});
        return e;
    };
    // How far p lies inside convex quad q (positive inside), in pixels.
    const auto inside_quad = [](glm::dvec2 p, const Quad& q) {
        double d = 1e9;
        for (int k = 0; k < 4; ++k) {
            const glm::dvec2 a(q[size_t(k)]), b(q[size_t(k + 1) % 4]);
            const glm::dvec2 e = glm::normalize(b - a);
            d = std::min(d, e.x * (p.y - a.y) - e.y * (p.x - a.x));
        }
        return d;
    };
    for (int msaa : {1, 4}) {
        SceneDir sd;
        std::ofstream(sd.dir / "back.obj") << obj(back);
        std::ofstream(sd.dir / "front.obj") << obj(front);
        const std::string size = std::to_string(W) + ", " + std::to_string(H);
        const auto scene = [&](bool prepass) {
            return sd.load(
                "camera: {position: [0, 0, 10], target: [0, 0, 0], projection: orthographic, "
                "height: " + std::to_string(H) + "}\n"
                "render: {size: [" + size + "], color_format: rgba32f, clear_color: [0, 0, 0, 1], "
                "wireframe: true, depth_prepass: " + (prepass ? "true" : "false") +
                ", msaa: " + std::to_string(msaa) + "}\n"
                "objects:\n"
                "  - {mesh: back.obj, material: {shader: unlit, params: {base_color: [0, 0, 1, 1]}}}\n"
                "  - {mesh: front.obj, material: {shader: unlit, params: {base_color: [0, 1, 0, 1]}}}\n");
        };
        Framebuffer fb, prepassed;
        Renderer renderer(1);
        renderer.render(scene(false), fb);
        // The pre-pass draws the surfaces' depth with their bias, and the
        // main pass shades them where it is equal: the same frame.
        const FrameStats stats = renderer.render(scene(true), prepassed);
        CHECK(stats.depth_prepasses == 1);
        CHECK(same_image(fb, prepassed));
        const glm::vec3 wire = PipelineState().wire_color;
        int on_front = 0, hidden = 0, on_back = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                for (int s = 0; s < msaa; ++s) {
                    const glm::dvec2 p =
                        glm::dvec2(x + 0.5, y + 0.5) + glm::dvec2(sample_offset(msaa, s)) / 16.0;
                    double near_front = -1e9, near_back = -1e9;
                    for (const auto& [a, b] : edges(front))
                        near_front = std::max(near_front, inside_line(p, a, b, 1.0));
                    for (const auto& [a, b] : edges(back))
                        near_back = std::max(near_back, inside_line(p, a, b, 1.0));
                    const bool is_wire = glm::vec3(fb.sample(x, y, s)) == wire;
                    CAPTURE(msaa, x, y, s, near_front, near_back);
                    if (near_front > 0.02) {  // on a wire of the front quad, diagonal too
                        CHECK(is_wire);
                        ++on_front;
                    } else if (near_front < -0.02 && inside_quad(p, front) > 0.02) {
                        CHECK(!is_wire);  // the front surface, over the back one's wire
                        hidden += near_back > 0.02;
                    } else if (near_back > 0.02 && inside_quad(p, front) < -0.02) {
                        CHECK(is_wire);
                        ++on_back;
                    } else if (near_front < -0.02 && near_back < -0.02) {
                        CHECK(!is_wire);
                    }
                }
        CHECK(on_front > 100 * msaa);
        CHECK(hidden > 15 * msaa);
        CHECK(on_back > 150 * msaa);
    }
}
