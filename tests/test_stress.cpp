// Numerical stress: a closed mesh seen from every side, extreme depth ranges.
#include "meshes.hpp"
#include "support.hpp"

#include <facet/math.hpp>
#include <facet/mesh.hpp>

#include <catch2/catch.hpp>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>

using namespace facet;
using namespace facet::test;

TEST_CASE("a camera sweeping around a closed mesh sees no crack at any angle", "[stress]") {
    // Spot is closed and watertight: every ray through it crosses its
    // surface an even number of times. Drawn with culling off and additive
    // counting, an odd count anywhere would be a crack (or a double hit).
    const auto spot = load_mesh(std::string(FACET_SOURCE_DIR) + "/assets/spot/spot.obj");
    auto shader = plugin<CountShader>();
    const int W = 160, H = 120;
    const glm::mat4 proj = perspective(glm::radians(40.0f), float(W) / H, 0.05f, 20.0f, true);
    int covered = 0;
    for (int step = 0; step < 48; ++step) {
        const float yaw = float(step) * glm::two_pi<float>() / 48.0f + 0.01f;
        const float pitch = 0.6f * std::sin(float(step) * 0.7f);
        const glm::vec3 eye = 2.4f * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                                               std::cos(pitch) * std::cos(yaw));
        Framebuffer fb(W, H);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(*spot, *shader);
        call.view = look_at(eye, {0.0f, 0.1f, 0.0f}, {0, 1, 0});
        call.projection = proj;
        call.state.blend = BlendMode::additive;
        FrameStats stats;
        Pipeline().draw(call, fb, stats);
        REQUIRE(stats.triangles_clipped == 0);  // the near plane never cuts it open
        for (const glm::vec4& c : fb.linear()) {
            const int count = int(c.r);
            REQUIRE(count % 2 == 0);
            covered += count > 0;
        }
    }
    CHECK(covered > 48 * 2000);
}

TEST_CASE("extreme near/far ratios keep nearby surfaces far away ordered", "[stress]") {
    // near 0.001, far 100000: two quads 1e-4 apart (relative) at distance
    // 1000. Reversed-Z float depth resolves them; drawn in either order, the
    // nearer one wins at every pixel.
    auto shader = plugin<ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const auto quad = [](float z, glm::vec4 c) {
        const float s = 2000.0f;  // wider than the view at that distance
        return make_mesh({{-s, -s, z}, {s, -s, z}, {s, s, z}, {-s, s, z}}, {0, 1, 2, 0, 2, 3},
                         std::vector<glm::vec4>(4, c));
    };
    const Mesh near = quad(-1000.0f, {1, 0, 0, 1}), far = quad(-1000.1f, {0, 0, 1, 1});
    for (bool near_first : {true, false}) {
        Framebuffer fb(64, 48);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(near, *shader);
        call.projection = perspective(glm::radians(60.0f), 64.0f / 48.0f, 0.001f, 1e5f, true);
        call.state.depth_compare = DepthCompare::greater;
        FrameStats stats;
        const Mesh* order[2] = {&near, &far};
        if (!near_first) std::swap(order[0], order[1]);
        for (const Mesh* m : order) {
            call.mesh = m;
            Pipeline().draw(call, fb, stats);
        }
        for (const glm::vec4& c : fb.linear()) REQUIRE(c == glm::vec4(1, 0, 0, 1));
    }
}

TEST_CASE("near-singular and singular model matrices keep normals well defined", "[stress]") {
    // Flattening an object to nothing along one axis (a common end of an
    // animation) must not turn its normals into NaN: they tend to the
    // flattened axis.
    for (float s : {1.0f, 1e-3f, 1e-20f, 1e-40f, 0.0f}) {
        INFO("z scale " << s);
        const glm::mat4 model = glm::scale(glm::mat4(1.0f), glm::vec3(2.0f, 0.5f, s));
        const glm::mat3 n = normal_matrix(model);
        const glm::vec3 tilted = glm::normalize(n * glm::normalize(glm::vec3(1, 1, 1)));
        REQUIRE(std::isfinite(tilted.x));
        REQUIRE(std::isfinite(tilted.z));
        if (s <= 1e-3f) CHECK(tilted.z > 0.99f);
        // Mirroring keeps normals pointing out of the (mirrored) surface.
        const glm::mat3 m = normal_matrix(glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1)));
        CHECK((m * glm::vec3(1, 0, 0)).x < 0.0f);
    }
    // The same direction as the inverse-transpose wherever that exists.
    const glm::mat4 skew = glm::mat4(glm::mat3(1.0f, 0.2f, 0.0f, 0.5f, 1.5f, 0.1f, 0.0f, 0.3f, 0.7f));
    const glm::vec3 a = glm::normalize(normal_matrix(skew) * glm::vec3(0.3f, -0.5f, 0.8f));
    const glm::vec3 b = glm::normalize(glm::transpose(glm::inverse(glm::mat3(skew))) *
                                       glm::vec3(0.3f, -0.5f, 0.8f));
    CHECK(glm::length(a - b) < 1e-6f);
}

namespace {

// Linux: writing 5 to clear_refs resets VmHWM to the current RSS.
bool reset_peak_rss() { return bool(std::ofstream("/proc/self/clear_refs") << "5"); }

}  // namespace

TEST_CASE("a 5M-triangle mesh renders watertight in bounded memory", "[stress][memory]") {
    // Seam columns repeat a position but not an index, and the poles are
    // fans of slivers: still closed, so with culling off every pixel inside
    // the silhouette is covered exactly twice.
    // In clip space (w = 1), flattened in z to stay between the near and
    // far planes.
    const Mesh sphere = uv_sphere(1120, {0.8f, 0.8f, 0.4f}, {0.0f, 0.0f, 0.5f});
    REQUIRE(sphere.triangle_count() > 5'000'000);
    auto shader = plugin<CountShader>();
    const int W = 192, H = 192;
    Framebuffer fb(W, H);
    fb.clear(glm::vec4(0.0f), 0.0f);
    DrawCall call = clip_space_call(sphere, *shader);
    call.state.blend = BlendMode::additive;
    FrameStats stats;
    Pipeline renderer(2);
    const size_t before = test::resident_bytes("VmRSS:");
    const bool measured = reset_peak_rss() && before > 0;
    renderer.draw(call, fb, stats);
    const size_t peak = test::resident_bytes("VmHWM:");
    CHECK(stats.triangles_in == sphere.triangle_count());
    CHECK(stats.triangles_invalid == 0);
    int inside = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const double dx = (x + 0.5) / W * 2.0 - 1.0, dy = 1.0 - (y + 0.5) / H * 2.0;
            const double r = std::sqrt(dx * dx + dy * dy);
            const float count = fb.pixel(x, y).r;
            if (r < 0.8 - 0.02) {
                ++inside;
                if (count != 2.0f) FAIL_CHECK("pixel " << x << "," << y << " covered " << count);
            } else if (r > 0.8 + 0.02) {
                if (count != 0.0f) FAIL_CHECK("pixel " << x << "," << y << " covered " << count);
            }
        }
    CHECK(inside > 10000);
#if !defined(__SANITIZE_ADDRESS__)  // ASan's shadow memory and quarantine inflate RSS
    if (measured) {
        // The draw keeps per-vertex results (a clip position each) and a
        // bounded batch of triangle setups, never per-triangle state for
        // the whole mesh: 5M setups alone would be over 600 MiB.
        const size_t growth = peak > before ? peak - before : 0;
        const size_t bound = (64u << 20) + sphere.vertex_count() * 32;
        INFO("peak growth " << growth / (1 << 20) << " MiB, bound " << bound / (1 << 20) << " MiB");
        CHECK(growth < bound);
    }
#endif
}
