// The whole pipeline (vertex stage, clipping, setup, raster, fragment, depth,
// blend) through Pipeline::draw, against double-precision references; the guard
// band; and what the vertex and fragment stages hand a shader.
#include "meshes.hpp"
#include "support.hpp"

#include <facet/math.hpp>

#include <catch2/catch.hpp>

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstring>
#include <vector>

using namespace facet;
using namespace facet::test;

namespace {

constexpr int W = 96, H = 80;

// `mesh` drawn once into a fresh W x H framebuffer cleared to `clear`.
Framebuffer draw_fresh(const Mesh& mesh, const ShaderPlugin& shader, const glm::mat4& proj,
                       glm::vec4 clear, FrameStats* stats = nullptr,
                       const glm::mat4& view = glm::mat4(1.0f),
                       BlendMode blend = BlendMode::opaque) {
    Framebuffer fb(W, H);
    fb.clear(clear, 0.0f);
    DrawCall call = clip_space_call(mesh, shader);
    call.view = view;
    call.projection = proj;
    call.state.blend = blend;
    FrameStats local;
    Pipeline().draw(call, fb, stats ? *stats : local);
    return fb;
}

// Coverage count per pixel of `mesh` drawn with additive blending.
std::vector<int> coverage(const Mesh& mesh, const glm::mat4& view, const glm::mat4& proj,
                          FrameStats* stats = nullptr) {
    static auto shader = plugin<CountShader>();
    const Framebuffer fb =
        draw_fresh(mesh, *shader, proj, glm::vec4(0.0f), stats, view, BlendMode::additive);
    std::vector<int> counts(W * H);
    const std::vector<glm::vec4> px = fb.linear();
    for (int i = 0; i < W * H; ++i) counts[i] = int(px[size_t(i)].r);
    return counts;
}

// An n x n grid of quads in the z = 0 plane, two triangles each, spanning
// [-1, 1]^2, with alternating diagonals.
Mesh grid(int n) {
    std::vector<glm::vec3> pos;
    std::vector<uint32_t> idx;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            pos.push_back({2.0f * i / n - 1.0f, 2.0f * j / n - 1.0f, 0.0f});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            if ((i + j) % 2) idx.insert(idx.end(), {a, b, d, a, d, c});
            else idx.insert(idx.end(), {a, b, c, b, d, c});
        }
    return make_mesh(pos, idx);
}

glm::dvec2 pixel_centre(int i) { return {i % W + 0.5, i / W + 0.5}; }

}  // namespace

TEST_CASE("a draw snaps vertices to its pipeline state's sub-pixel bits", "[pipeline][subpixel]") {
    // A quad whose left side is at x = 10.6: with 8 bits, column 10's centre
    // (10.5) is outside; with 1 bit the side rounds to 10.5 and, being a
    // left edge, takes that column in.
    const glm::vec3 a = window_to_ndc({10.6, 0.0}, W, H), b = window_to_ndc({30.0, 0.0}, W, H),
                    c = window_to_ndc({30.0, H}, W, H), d = window_to_ndc({10.6, H}, W, H);
    const Mesh quad = make_mesh({a, b, c, d}, {0, 2, 1, 0, 3, 2});
    static auto shader = plugin<CountShader>();
    for (int bits : {8, 1}) {
        Framebuffer fb(W, H);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(quad, *shader);
        call.state.subpixel_bits = bits;
        FrameStats stats;
        Pipeline(1).draw(call, fb, stats);
        CAPTURE(bits);
        CHECK(fb.pixel(10, H / 2).r == (bits == 1 ? 1.0f : 0.0f));
        CHECK(fb.pixel(11, H / 2).r == 1.0f);
    }
}

TEST_CASE("fans are watertight at many rotations", "[pipeline][watertight]") {
    for (int step = 0; step < 90; ++step) {
        const float angle = float(step) * 0.0713f;
        const glm::vec2 centre(0.013f * float(step % 7), -0.021f * float(step % 5));
        const int n = 5 + step % 23;
        const float r = 0.8f;
        const std::vector<int> counts = coverage(fan(n, r, angle, centre), glm::mat4(1), glm::mat4(1));
        const double inner = r * std::cos(glm::pi<double>() / n);  // inscribed circle, NDC
        for (int i = 0; i < W * H; ++i) {
            REQUIRE(counts[i] <= 1);
            const glm::dvec2 ndc(pixel_centre(i).x / W * 2 - 1, 1 - pixel_centre(i).y / H * 2);
            // Inside the inscribed circle (less a pixel): covered exactly once.
            const double px = 2.0 / std::min(W, H);
            if (glm::length(ndc - glm::dvec2(centre)) < inner - px) REQUIRE(counts[i] == 1);
        }
    }
}

TEST_CASE("perspective grids are watertight at many angles, also when clipped",
          "[pipeline][watertight]") {
    const Mesh mesh = grid(9);
    const glm::mat4 proj = perspective(glm::radians(60.0f), float(W) / H, 0.1f, 50.0f, true);
    int clipped_views = 0;
    for (int step = 0; step < 60; ++step) {
        const float yaw = float(step) * 0.37f, pitch = 0.2f + 0.02f * float(step % 13);
        // The camera skims the plane, close enough that the near plane cuts it.
        const float dist = step % 2 ? 0.6f : 2.5f;
        const glm::vec3 eye(dist * std::sin(yaw), dist * std::cos(yaw), dist * pitch);
        const glm::mat4 view = look_at(eye, glm::vec3(0.1f, -0.05f, 0.0f), {0, 0, 1});
        FrameStats stats;
        const std::vector<int> counts = coverage(mesh, view, proj, &stats);
        clipped_views += stats.triangles_clipped > 0;
        for (int i = 0; i < W * H; ++i) REQUIRE(counts[i] <= 1);
        // Every pixel whose ray meets the plane inside the grid is hit once.
        const glm::mat4 inv = glm::inverse(proj * view);
        for (int i = 0; i < W * H; ++i) {
            const glm::dvec2 c = pixel_centre(i);
            const glm::dvec2 ndc(c.x / W * 2 - 1, 1 - c.y / H * 2);
            const glm::dvec4 a = glm::dmat4(inv) * glm::dvec4(ndc, 1.0, 1.0);  // near
            const glm::dvec4 b = glm::dmat4(inv) * glm::dvec4(ndc, 0.0, 1.0);  // far
            const glm::dvec3 p0 = glm::dvec3(a) / a.w, p1 = glm::dvec3(b) / b.w;
            if ((p0.z > 0) == (p1.z > 0)) continue;
            const glm::dvec3 hit = p0 + (p1 - p0) * (p0.z / (p0.z - p1.z));
            if (std::abs(hit.x) < 0.97 && std::abs(hit.y) < 0.97) REQUIRE(counts[i] == 1);
        }
    }
    CHECK(clipped_views > 10);
}

TEST_CASE("near-plane and w = 0 clipping keep the visible part", "[pipeline][clip]") {
    // A triangle in view space, one vertex behind the camera (w < 0), one
    // exactly in the camera plane (w = 0), one in front. Reference: clip
    // the triangle against the near plane in double precision, project it,
    // and test pixel centres against the resulting polygon.
    const float near = 0.5f;
    const glm::mat4 proj = perspective(glm::radians(70.0f), float(W) / H, near, 20.0f, true);
    const std::vector<std::vector<glm::vec3>> cases = {
        {{-1.0f, -0.8f, -3.0f}, {1.5f, -0.6f, 2.0f}, {0.2f, 1.0f, -4.0f}},   // w < 0
        {{-1.0f, -0.8f, -3.0f}, {1.2f, -0.3f, 0.0f}, {0.2f, 1.0f, -4.0f}},   // w = 0
        {{-1.0f, -0.8f, -3.0f}, {1.2f, -0.3f, 1e-7f}, {0.2f, 1.0f, -4.0f}},  // w ~ 0
        {{-2.0f, 0.5f, 1.0f}, {2.0f, 0.4f, 1.0f}, {0.0f, -0.5f, -6.0f}},     // two behind
    };
    for (const auto& tri : cases) {
        const Mesh mesh = make_mesh(tri, {0, 1, 2});
        FrameStats stats;
        const std::vector<int> counts = coverage(mesh, glm::mat4(1), proj, &stats);
        CHECK(stats.triangles_clipped == 1);
        CHECK(stats.triangles_rasterized == 1);
        // Reference polygon in view space, then in window coordinates.
        std::vector<glm::dvec3> poly;
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 a(tri[k]), b(tri[(k + 1) % 3]);
            const double da = -a.z - near, db = -b.z - near;  // >= 0: in front of near
            if (da >= 0) poly.push_back(a);
            if ((da >= 0) != (db >= 0)) poly.push_back(a + (b - a) * (da / (da - db)));
        }
        std::vector<glm::dvec2> win;
        for (const glm::dvec3& p : poly) {
            const glm::dvec4 c = glm::dmat4(proj) * glm::dvec4(p, 1.0);
            win.push_back({(c.x / c.w + 1) * 0.5 * W, (1 - c.y / c.w) * 0.5 * H});
        }
        int covered = 0;
        for (int i = 0; i < W * H; ++i) {
            // Signed distance of the centre to the polygon's edges (in pixels).
            double dmin = 1e30, dmax = -1e30;
            for (size_t k = 0; k < win.size(); ++k) {
                const glm::dvec2 a = win[k], b = win[(k + 1) % win.size()];
                const glm::dvec2 e = b - a, q = pixel_centre(i) - a;
                const double d = (e.x * q.y - e.y * q.x) / glm::length(e);
                dmin = std::min(dmin, d);
                dmax = std::max(dmax, d);
            }
            const bool inside = dmin > 0.01 || dmax < -0.01;  // either winding
            const bool outside = dmin < -0.01 && dmax > 0.01;
            if (inside) REQUIRE(counts[i] == 1);
            if (outside) REQUIRE(counts[i] == 0);
            covered += counts[i];
        }
        CHECK(covered > 100);
    }
}

TEST_CASE("perspective-correct interpolation matches a double-precision reference",
          "[pipeline][interpolation]") {
    // A quad receding from the camera; its colour's red channel holds the
    // vertex's u coordinate, so each pixel should show the u where its ray
    // hits the quad.
    const Mesh mesh = make_mesh({{-1, -1, -1.2f}, {1, -1, -1.2f}, {1, 1, -9.0f}, {-1, 1, -9.0f}},
                                {0, 1, 2, 0, 2, 3},
                                {{0, 0, 0, 1}, {1, 0, 0, 1}, {1, 1, 0, 1}, {0, 1, 0, 1}});
    const glm::mat4 proj = perspective(glm::radians(60.0f), float(W) / H, 0.5f, 20.0f, true);
    const Framebuffer persp = draw_fresh(mesh, *plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>(),
                                         proj, glm::vec4(-1.0f));
    const Framebuffer affine =
        draw_fresh(mesh, *plugin<ColorShader<FACET_INTERP_LINEAR>>(), proj, glm::vec4(-1.0f));
    const glm::dmat4 inv = glm::inverse(glm::dmat4(proj));
    double max_err = 0, max_affine_err = 0;
    int checked = 0;
    const std::vector<glm::vec4> persp_px = persp.linear(), affine_px = affine.linear();
    for (int i = 0; i < W * H; ++i) {
        const glm::vec4 c = persp_px[size_t(i)];
        if (c.a < 0) continue;  // not covered
        const glm::dvec2 ndc(pixel_centre(i).x / W * 2 - 1, 1 - pixel_centre(i).y / H * 2);
        const glm::dvec4 far = inv * glm::dvec4(ndc, 0.0, 1.0);
        const glm::dvec3 dir = glm::dvec3(far) / far.w;  // ray from the eye at the origin
        // Plane of the quad: points (x, y, z) with z = -1.2 - 3.9 (y + 1).
        const double t = -5.1 / (dir.z + 3.9 * dir.y);
        const glm::dvec3 hit = dir * t;
        const double u = (hit.x + 1) / 2, v = (hit.y + 1) / 2;
        if (u < 0.01 || u > 0.99 || v < 0.01 || v > 0.99) continue;  // edge pixels
        max_err = std::max({max_err, std::abs(c.r - u), std::abs(c.g - v)});
        max_affine_err = std::max(max_affine_err, std::abs(double(affine_px[size_t(i)].g) - v));
        ++checked;
    }
    CHECK(checked > 500);
    CHECK(max_err < 2e-3);
    CHECK(max_affine_err > 0.05);  // affine interpolation is visibly wrong here
}

TEST_CASE("depth test keeps the nearest surface in either draw order", "[pipeline][depth]") {
    auto shader = plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const Mesh near_red = make_mesh({{-1, -1, -2}, {1, -1, -2}, {0, 1, -2}}, {0, 1, 2},
                                    std::vector<glm::vec4>(3, {1, 0, 0, 1}));
    const Mesh far_blue = make_mesh({{-1, -1, -2.001f}, {1, -1, -2.001f}, {0, 1, -2.001f}},
                                    {0, 1, 2}, std::vector<glm::vec4>(3, {0, 0, 1, 1}));
    for (bool reversed : {true, false}) {
        const glm::mat4 proj = perspective(glm::radians(60.0f), float(W) / H, 0.1f, 1000.0f,
                                           reversed);
        for (bool red_first : {true, false}) {
            Framebuffer fb(W, H);
            fb.clear(glm::vec4(0.0f), reversed ? 0.0f : 1.0f);
            DrawCall call = clip_space_call(near_red, *shader);
            call.projection = proj;
            call.state.depth_compare = reversed ? DepthCompare::greater : DepthCompare::less;
            FrameStats stats;
            const Mesh* order[2] = {&near_red, &far_blue};
            if (!red_first) std::swap(order[0], order[1]);
            for (const Mesh* m : order) {
                call.mesh = m;
                Pipeline().draw(call, fb, stats);
            }
            const glm::vec4 centre = fb.pixel(W / 2, H / 2);
            CHECK(centre.r == 1.0f);
            CHECK(centre.b == 0.0f);
            if (!red_first) CHECK(stats.fragments_depth_rejected == 0);  // red overwrote blue
            if (red_first) CHECK(stats.fragments_depth_rejected > 100);  // blue was hidden
        }
    }
}

TEST_CASE("a depth-only draw writes the depths a shaded draw writes, and rejects the same "
          "fragments, on every path",
          "[pipeline][depth][isa]") {
    // Two overlapping spheres of small triangles and a large quad behind
    // them, so that blocks are partly and wholly covered, tested and hidden.
    auto shader = plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const Mesh a = uv_sphere(24, glm::vec3(0.9f), glm::vec3(-0.3f, 0.1f, -3.0f));
    const Mesh b = uv_sphere(17, glm::vec3(0.7f), glm::vec3(0.4f, -0.2f, -2.6f));
    const Mesh back = make_mesh({{-3, -3, -4}, {3, -3, -4}, {3, 3, -4.5f}, {-3, 3, -4.5f}},
                                {0, 1, 2, 0, 2, 3});
    for (Isa isa : supported_isas())
        for (bool reversed : {true, false}) {
            INFO(isa_name(isa) << (reversed ? ", reversed depth" : ", standard depth"));
            const glm::mat4 proj =
                perspective(glm::radians(50.0f), float(W) / H, 0.1f, 100.0f, reversed);
            Framebuffer shaded(W, H), depth_only(W, H, ColorFormat::none);
            FrameStats with_shader, without;
            for (Framebuffer* fb : {&shaded, &depth_only}) {
                fb->clear(glm::vec4(0.0f), reversed ? 0.0f : 1.0f);
                Pipeline pipeline(1, isa);
                DrawCall call = clip_space_call(a, *shader);
                call.projection = proj;
                call.state.cull = CullMode::none;
                call.state.depth_compare = reversed ? DepthCompare::greater : DepthCompare::less;
                call.state.color_write = fb == &shaded;
                for (const Mesh* m : {&back, &a, &b}) {
                    call.mesh = m;
                    pipeline.queue(call, *fb, fb == &shaded ? with_shader : without);
                }
                pipeline.flush(fb == &shaded ? with_shader : without);
            }
            CHECK(without.fragments_shaded == 0);
            CHECK(without.fragments_depth_only == with_shader.fragments_shaded);
            CHECK(without.fragments_depth_rejected == with_shader.fragments_depth_rejected);
            CHECK(without.fragments_depth_rejected > 100);
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) REQUIRE(depth_only.depth_at(x, y) == shaded.depth_at(x, y));
        }
}

TEST_CASE("a depth-only draw writes the depths a shaded draw writes where weights are clamped",
          "[pipeline][depth][isa]") {
    // Triangles with corners on pixel centres, so that many covered centres
    // lie exactly on an edge, where a weight's rounding may fall below 0,
    // and corners far apart in depth, so that such weights are held at 0
    // (TriangleSetup::clamp_weights): the depth-only route must hold them
    // too, or a main pass testing for equal depth after a pre-pass would
    // leave those pixels unshaded. Each triangle alone, so that none hides
    // another's pixels.
    auto shader = plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const glm::mat4 proj = perspective(glm::radians(60.0f), float(W) / H, 0.1f, 1000.0f, true);
    std::mt19937 rng(17);
    std::uniform_int_distribution<int> px(0, W - 1), py(0, H - 1);
    std::uniform_real_distribution<float> depth(0.2f, 300.0f);
    const auto corner = [&] {  // a view-space point whose window position is a pixel centre
        const double d = double(depth(rng));
        const double nx = 2.0 * (px(rng) + 0.5) / W - 1.0, ny = 1.0 - 2.0 * (py(rng) + 0.5) / H;
        return glm::vec3(float(nx * d / proj[0][0]), float(ny * d / proj[1][1]), float(-d));
    };
    Framebuffer shaded(W, H), depth_only(W, H, ColorFormat::none);
    int differing = 0;
    for (int n = 0; n < 300; ++n) {
        const Mesh mesh = make_mesh({corner(), corner(), corner()}, {0, 1, 2});
        for (Isa isa : supported_isas()) {
            for (Framebuffer* fb : {&shaded, &depth_only}) {
                fb->clear(glm::vec4(0.0f), 0.0f);
                DrawCall call = clip_space_call(mesh, *shader);
                call.projection = proj;
                call.state.cull = CullMode::none;
                call.state.depth_compare = DepthCompare::greater;
                call.state.color_write = fb == &shaded;
                FrameStats stats;
                Pipeline(1, isa).draw(call, *fb, stats);
            }
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x)
                    differing += depth_only.depth_at(x, y) != shaded.depth_at(x, y);
        }
    }
    CHECK(differing == 0);
}

TEST_CASE("interpenetrating triangles resolve per pixel", "[pipeline][depth]") {
    // Two triangles crossing at x = 0: blue is nearer for x < 0, red for x > 0.
    auto shader = plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const Mesh red = make_mesh({{-1, -1, -2.5f}, {1, -1, -1.5f}, {0, 1, -2}}, {0, 1, 2},
                               std::vector<glm::vec4>(3, {1, 0, 0, 1}));
    const Mesh blue = make_mesh({{-1, -1, -1.5f}, {1, -1, -2.5f}, {0, 1, -2}}, {0, 1, 2},
                                std::vector<glm::vec4>(3, {0, 0, 1, 1}));
    Framebuffer fb(W, H);
    fb.clear(glm::vec4(0.0f), 0.0f);
    DrawCall call = clip_space_call(red, *shader);
    call.projection = perspective(glm::radians(60.0f), float(W) / H, 0.1f, 100.0f, true);
    call.state.depth_compare = DepthCompare::greater;
    FrameStats stats;
    Pipeline().draw(call, fb, stats);
    call.mesh = &blue;
    Pipeline().draw(call, fb, stats);
    const int y = H / 2 + 4;
    CHECK(fb.pixel(W / 2 - 8, y).b == 1.0f);
    CHECK(fb.pixel(W / 2 + 8, y).r == 1.0f);
}

TEST_CASE("blending: source-alpha over and additive", "[pipeline][blend]") {
    auto shader = plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const auto quad = [](glm::vec4 c) {
        return make_mesh({{-1, -1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}, {-1, 1, 0.5f}},
                         {0, 1, 2, 0, 2, 3}, std::vector<glm::vec4>(4, c));
    };
    const Mesh blue = quad({0, 0, 1, 1}), red = quad({1, 0, 0, 0.25f});
    auto draw_pair = [&](BlendMode mode) {
        Framebuffer fb(8, 8);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(blue, *shader);
        FrameStats stats;
        Pipeline().draw(call, fb, stats);
        call.mesh = &red;
        call.state.blend = mode;
        Pipeline().draw(call, fb, stats);
        return fb.pixel(3, 3);
    };
    const glm::vec4 over = draw_pair(BlendMode::alpha);
    CHECK(over.r == Approx(0.25));
    CHECK(over.b == Approx(0.75));
    CHECK(over.a == Approx(1.0));
    const glm::vec4 add = draw_pair(BlendMode::additive);
    CHECK(add.r == Approx(0.25));
    CHECK(add.b == Approx(1.0));
    const glm::vec4 opaque = draw_pair(BlendMode::opaque);
    CHECK(opaque.r == 1.0f);
    CHECK(opaque.b == 0.0f);
}

TEST_CASE("back-face culling follows the winding", "[pipeline][cull]") {
    auto shader = plugin<CountShader>();
    // Counter-clockwise as seen (NDC y up).
    const Mesh ccw = make_mesh({{-0.5f, -0.5f, 0.5f}, {0.5f, -0.5f, 0.5f}, {0, 0.5f, 0.5f}},
                               {0, 1, 2});
    for (CullMode mode : {CullMode::none, CullMode::back, CullMode::front})
        for (bool front_ccw : {true, false}) {
            Framebuffer fb(16, 16);
            fb.clear(glm::vec4(0.0f), 0.0f);
            DrawCall call = clip_space_call(ccw, *shader);
            call.state.cull = mode;
            call.state.front_ccw = front_ccw;
            FrameStats stats;
            Pipeline().draw(call, fb, stats);
            const bool front = front_ccw;
            const bool culled = (mode == CullMode::back && !front) ||
                                (mode == CullMode::front && front);
            CHECK(stats.triangles_culled_backface == (culled ? 1u : 0u));
            CHECK((fb.pixel(8, 8).r > 0) == !culled);
        }
}

TEST_CASE("NaN and Inf vertices are dropped and counted", "[pipeline][robust]") {
    auto shader = plugin<CountShader>();
    const float nan = std::nanf(""), inf = INFINITY;
    const Mesh mesh = make_mesh({{-0.5f, -0.5f, 0.5f}, {0.5f, -0.5f, 0.5f}, {0, 0.5f, 0.5f},
                                 {nan, 0, 0.5f}, {0, inf, 0.5f}},
                                {0, 1, 2, 0, 3, 2, 4, 1, 2});
    Framebuffer fb(16, 16);
    fb.clear(glm::vec4(0.0f), 0.0f);
    DrawCall call = clip_space_call(mesh, *shader);
    FrameStats stats;
    Pipeline().draw(call, fb, stats);
    CHECK(stats.triangles_in == 3);
    CHECK(stats.triangles_invalid == 2);
    CHECK(stats.triangles_rasterized == 1);
}

TEST_CASE("NaN and Inf in matrices drop the draw's triangles and count them",
          "[pipeline][robust]") {
    auto shader = plugin<CountShader>();
    const Mesh mesh = fan(12, 0.6f, 0.1f, {0.0f, 0.0f});
    const float nan = std::nanf(""), inf = INFINITY;
    for (int which = 0; which < 4; ++which) {
        CAPTURE(which);
        Framebuffer fb(W, H);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(mesh, *shader);
        if (which == 0) call.model[3][0] = nan;        // translation
        if (which == 1) call.model[1][1] = inf;        // scale
        if (which == 2) call.projection[2][3] = nan;   // w row
        if (which == 3) call.view[0][0] = -inf;
        FrameStats stats;
        Pipeline().draw(call, fb, stats);
        CHECK(stats.triangles_in == 12);
        CHECK(stats.triangles_invalid + stats.triangles_culled_frustum == 12);
        CHECK(stats.triangles_rasterized == 0);
        for (const glm::vec4& c : fb.linear()) REQUIRE(c.r == 0.0f);
    }
}

TEST_CASE("flat varyings hold the first vertex's value over the whole triangle",
          "[pipeline][interpolation]") {
    // A receding quad of two triangles whose first vertices differ (0 and
    // 2): each shows its first vertex's colour, exactly, on every path.
    const std::vector<glm::vec4> colors = {{0.25f, 0.5f, 0.75f, 1.0f}, {1, 0, 0, 1},
                                           {0.125f, 0.0625f, 1.0f, 1.0f}, {0, 1, 0, 1}};
    const Mesh mesh = make_mesh({{-1, -1, -1.5f}, {1, -1, -1.5f}, {1, 1, -6.0f}, {-1, 1, -6.0f}},
                                {0, 1, 2, 2, 3, 0}, colors);
    const glm::mat4 proj = perspective(glm::radians(60.0f), float(W) / H, 0.5f, 20.0f, true);
    const auto shader = plugin<ColorShader<FACET_INTERP_FLAT>>();
    for (Isa isa : supported_isas()) {
        CAPTURE(isa_name(isa));
        Framebuffer fb(W, H);
        fb.clear(glm::vec4(-1.0f), 0.0f);
        DrawCall call = clip_space_call(mesh, *shader);
        call.projection = proj;
        FrameStats stats;
        Pipeline(1, isa).draw(call, fb, stats);
        // The diagonal from vertex 0 to 2 parts the triangles on screen.
        glm::dvec2 win[3];
        for (int k : {0, 2, 1}) {
            const glm::dvec3 at(mesh.positions[size_t(k)]);
            const glm::dvec4 c = glm::dmat4(proj) * glm::dvec4(at, 1.0);
            win[k] = {(c.x / c.w + 1) * 0.5 * W, (1 - c.y / c.w) * 0.5 * H};
        }
        const glm::dvec2 along = win[2] - win[0];
        const double side1 = along.x * (win[1].y - win[0].y) - along.y * (win[1].x - win[0].x);
        const std::vector<glm::vec4> px = fb.linear();
        int first = 0, second = 0;
        for (int i = 0; i < W * H; ++i) {
            if (px[size_t(i)].a < 0) continue;  // not covered
            const glm::dvec2 p = pixel_centre(i);
            const double side = along.x * (p.y - win[0].y) - along.y * (p.x - win[0].x);
            if (std::abs(side) < 2.0 * glm::length(along)) continue;  // within 2 pixels of it
            const bool in_first = (side > 0) == (side1 > 0);
            CHECK(px[size_t(i)] == colors[in_first ? 0 : 2]);
            ++(in_first ? first : second);
        }
        CHECK(first > 500);
        CHECK(second > 500);
    }
}

TEST_CASE("screen-linear varyings stay screen-linear through near-plane clipping",
          "[pipeline][clip][interpolation]") {
    // All three vertices are in front of the eye (w > 0), one nearer than the
    // near plane, so the triangle is clipped. A `linear` varying must still be
    // the screen-space affine function of the original three vertices.
    const std::vector<glm::vec3> tri = {{-0.1f, -0.1f, -0.2f}, {1.5f, -1.0f, -3.0f},
                                        {-1.0f, 1.2f, -4.0f}};
    const std::vector<glm::vec4> colors = {{0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}};
    const Mesh mesh = make_mesh(tri, {0, 1, 2}, colors);
    const glm::mat4 proj = perspective(glm::radians(70.0f), float(W) / H, 0.5f, 20.0f, true);
    FrameStats stats;
    const Framebuffer fb = draw_fresh(mesh, *plugin<ColorShader<FACET_INTERP_LINEAR>>(), proj,
                                      glm::vec4(-1.0f), &stats);
    REQUIRE(stats.triangles_clipped == 1);
    glm::dvec2 win[3];
    for (int k = 0; k < 3; ++k) {
        const glm::dvec4 c = glm::dmat4(proj) * glm::dvec4(glm::dvec3(tri[k]), 1.0);
        win[k] = {(c.x / c.w + 1) * 0.5 * W, (1 - c.y / c.w) * 0.5 * H};
    }
    const auto cross = [](glm::dvec2 a, glm::dvec2 b, glm::dvec2 p) {
        return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    };
    const double area = cross(win[0], win[1], win[2]);
    double max_err = 0;
    int checked = 0;
    const std::vector<glm::vec4> px = fb.linear();
    for (int i = 0; i < W * H; ++i) {
        const glm::vec4 c = px[size_t(i)];
        if (c.a < 0) continue;
        const glm::dvec2 p = pixel_centre(i);
        const double l1 = cross(win[2], win[0], p) / area, l2 = cross(win[0], win[1], p) / area;
        max_err = std::max({max_err, std::abs(c.r - l1), std::abs(c.g - l2)});
        ++checked;
    }
    CHECK(checked > 200);
    CHECK(max_err < 2e-3);
}

TEST_CASE("a vertex at the clip-space origin drops its triangle cleanly", "[pipeline][robust]") {
    // Shaders "kill" vertices by writing (0, 0, 0, 0). With this projection
    // (w = -z, depth 0.5, no translation) the origin maps there exactly.
    glm::mat4 proj(1.0f);
    proj[2][2] = -0.5f;
    proj[2][3] = -1.0f;
    proj[3][3] = 0.0f;
    const Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, -1}, {0, 1, -1}, {-1, -1, -1}},
                                {0, 1, 2, 3, 1, 2});
    FrameStats stats;
    const Framebuffer fb = draw_fresh(mesh, *plugin<CountShader>(), proj, glm::vec4(0.0f), &stats);
    CHECK(stats.triangles_in == 2);
    CHECK(stats.triangles_rasterized == 1);  // the other triangle is unaffected
    CHECK(stats.triangles_culled_degenerate == 1);
    for (const glm::vec4& c : fb.linear()) REQUIRE(c.r <= 1.0f);
}

TEST_CASE("triangles beyond the guard band are clipped to it, others are not",
          "[pipeline][clip]") {
    auto shader = plugin<CountShader>();
    const int W = 64, H = 48;
    auto draw = [&](float extent) {
        // Two triangles sharing the diagonal of a square `extent` NDC units wide.
        const Mesh quad = make_mesh({{-extent, -extent, 0.5f}, {extent, -extent, 0.5f},
                                     {extent, extent, 0.5f}, {-extent, extent, 0.5f}},
                                    {0, 1, 2, 0, 2, 3});
        Framebuffer fb(W, H);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(quad, *shader);
        call.state.blend = BlendMode::additive;
        FrameStats stats;
        Pipeline().draw(call, fb, stats);
        const std::vector<glm::vec4> px = fb.linear();
        for (int i = 0; i < W * H; ++i) REQUIRE(px[size_t(i)].r == 1.0f);
        return stats;
    };
    CHECK(draw(3.0f).triangles_clipped == 0);       // off screen, inside the guard band
    CHECK(draw(1e4f).triangles_clipped == 0);       // ~3e5 px: still inside
    CHECK(draw(1e5f).triangles_clipped == 2);       // ~3e6 px: clipped to the band
    CHECK(draw(1e12f).triangles_clipped == 2);      // far beyond: still exact
}

namespace {

// Records what the core handed the vertex and fragment functions.
struct Seen {
    bool normal = false, uv = false, color = false, texels = false;
    uint32_t varying_floats = 0, lights = 0;
};
Seen g_seen;

void probe_vertex(const facet_draw* d, const facet_vertex_batch* b) {
    g_seen.normal |= b->normal != nullptr;
    g_seen.uv |= b->uv != nullptr;
    g_seen.color |= b->color != nullptr;
    g_seen.varying_floats = b->varying_floats;
    g_seen.lights = d->light_count;
    for (uint32_t i = 0; i < b->count; ++i) {
        std::memcpy(b->clip_position + 4 * i, b->position + 3 * i, 12);
        b->clip_position[4 * i + 3] = 1.0f;
        for (uint32_t k = 0; k < b->varying_floats; ++k) b->varyings[i * b->varying_floats + k] = 0;
    }
}

void probe_fragment(const facet_draw*, facet_fragment_batch* b) {
    g_seen.texels |= b->texels != nullptr;
    for (int i = 0; i < 4 * FACET_BLOCK_LANES; ++i) b->color[i] = 1.0f;
}

}  // namespace

TEST_CASE("the core provides only what a shader asks for", "[pipeline][abi]") {
    const facet_varying_desc uv = {"uv", 2, FACET_INTERP_PERSPECTIVE};
    const facet_fragment_entry fragment = {FACET_ISA_BASELINE, probe_fragment};
    facet_shader_desc shader = {sizeof(facet_shader_desc), 0, 0, 0, nullptr, 0, 0,
                                probe_vertex, 1, &fragment, 0, 0};
    const facet_plugin_desc desc = {FACET_ABI_MAJOR, FACET_ABI_MINOR, sizeof(facet_plugin_desc),
                                    "probe", "test", {}, &shader, nullptr};
    Mesh mesh = make_mesh({{-1, -1, 0.5f}, {1, -1, 0.5f}, {0, 1, 0.5f}}, {0, 1, 2},
                          std::vector<glm::vec4>(3, glm::vec4(1.0f)));
    mesh.normals.assign(3, {0, 0, 1});
    mesh.uvs.assign(3, {0, 0});
    const facet_light light{};
    auto run = [&] {
        g_seen = {};
        auto shader = ShaderPlugin::from_descriptor(&desc, "probe");
        Framebuffer fb(8, 8);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(mesh, *shader);
        call.lights = &light;
        call.light_count = 1;
        FrameStats stats;
        Pipeline().draw(call, fb, stats);
        return g_seen;
    };
    Seen none = run();
    CHECK_FALSE((none.normal || none.uv || none.color || none.texels));
    CHECK(none.varying_floats == 0);
    CHECK(none.lights == 0);

    shader.needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_LIGHTS;
    shader.varying_count = 1;
    shader.varyings = &uv;
    Seen some = run();
    CHECK((some.normal && some.uv && !some.color));
    CHECK(some.varying_floats == 2);
    CHECK(some.lights == 1);
}
