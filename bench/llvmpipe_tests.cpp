// facet-bench --llvmpipe compares like with like only if llvmpipe draws what
// facet draws. These tests check that on small images: the same pixels
// covered (fill rule, culling and depth order included), and phong and
// unlit colours within a small tolerance of facet's. Built with OSMesa only.
#include "llvmpipe.hpp"

#include <facet/renderer.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace facet;
using facet::bench::LlvmpipeRenderer;
using facet::bench::LlvmpipeTarget;

namespace {

constexpr int kWidth = 64, kHeight = 48;

// `shader` with its defaults; for unlit, `base_color`.
std::shared_ptr<Material> material(const std::string& shader,
                                   glm::vec4 base_color = {1, 1, 1, 1}) {
    static PluginRegistry registry;
    auto m = std::make_shared<Material>();
    m->source = "llvmpipe_tests";
    m->shader = shader;
    if (shader == "unlit") {
        MaterialParam p;
        p.name = "base_color";
        p.kind = MaterialParam::Kind::vector;
        p.numbers = {base_color.r, base_color.g, base_color.b, base_color.a};
        m->params.push_back(p);
    }
    TextureCache cache;
    bind(*m, registry.get(shader), cache);
    return m;
}

// Triangles given by their corners in pixels (x right, y down), at world
// depth z, for a camera whose orthographic view maps one unit to a pixel.
std::shared_ptr<Mesh> pixel_triangles(const std::vector<glm::vec2>& corners, float z = 0.0f) {
    auto m = std::make_shared<Mesh>();
    for (glm::vec2 p : corners) {
        m->positions.push_back({p.x - kWidth / 2.0f, kHeight / 2.0f - p.y, z});
        m->indices.push_back(uint32_t(m->indices.size()));
    }
    m->bounds = compute_bounds(m->positions);
    return m;
}

Scene pixel_scene() {
    Scene s;
    s.settings.width = kWidth;
    s.settings.height = kHeight;
    s.camera.orthographic = true;
    s.camera.ortho_height = float(kHeight);
    s.camera.position = {0.0f, 0.0f, 5.0f};
    return s;
}

Framebuffer render_facet(const Scene& scene) {
    Renderer renderer(1);
    Framebuffer fb;
    renderer.render(scene, fb);
    return fb;
}

std::vector<glm::vec4> render_llvmpipe(const Scene& scene) {
    LlvmpipeRenderer lp(scene.settings.width, scene.settings.height, LlvmpipeTarget::rgba32f);
    lp.upload(scene);
    lp.render(scene);
    return lp.image();
}

// Pixels where one image is background (black) and the other is not.
int coverage_differences(const Framebuffer& facet, const std::vector<glm::vec4>& llvmpipe) {
    int n = 0;
    for (size_t i = 0; i < llvmpipe.size(); ++i)
        n += (glm::vec3(facet.color()[i]) != glm::vec3(0.0f)) !=
             (glm::vec3(llvmpipe[i]) != glm::vec3(0.0f));
    return n;
}

// The largest difference of a channel, over the pixels both cover.
float max_difference(const Framebuffer& facet, const std::vector<glm::vec4>& llvmpipe) {
    float worst = 0.0f;
    for (size_t i = 0; i < llvmpipe.size(); ++i) {
        const bool both = glm::vec3(facet.color()[i]) != glm::vec3(0.0f) &&
                          glm::vec3(llvmpipe[i]) != glm::vec3(0.0f);
        if (!both) continue;
        const glm::vec4 d = glm::abs(facet.color()[i] - llvmpipe[i]);
        worst = std::max({worst, d.r, d.g, d.b, d.a});
    }
    return worst;
}

// A UV sphere of radius 1 (the bench's, smaller).
std::shared_ptr<Mesh> sphere(int rings) {
    auto m = std::make_shared<Mesh>();
    const int segments = 2 * rings;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            const float theta = float(M_PI) * r / rings, phi = 2.0f * float(M_PI) * s / segments;
            const glm::vec3 p(std::sin(theta) * std::cos(phi), std::cos(theta),
                              std::sin(theta) * std::sin(phi));
            m->positions.push_back(p);
            m->normals.push_back(p);
        }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = uint32_t(r * (segments + 1) + s), b = a + 1,
                           c = a + uint32_t(segments + 1), d = c + 1;
            m->indices.insert(m->indices.end(), {a, c, b, b, c, d});
        }
    m->bounds = compute_bounds(m->positions);
    return m;
}

}  // namespace

TEST_CASE("llvmpipe owns the edges through pixel centres that facet owns", "[llvmpipe]") {
    // Every corner on a pixel centre, so every edge runs through centres:
    // only the top-left rule decides those pixels.
    const std::vector<std::vector<glm::vec2>> cases = {
        {{10.5f, 10.5f}, {10.5f, 20.5f}, {20.5f, 20.5f},  // a square of two triangles
         {10.5f, 10.5f}, {20.5f, 20.5f}, {20.5f, 10.5f}},
        {{30.5f, 5.5f}, {30.5f, 15.5f}, {40.5f, 15.5f}},    // edges left, bottom, diagonal
        {{30.5f, 25.5f}, {40.5f, 35.5f}, {40.5f, 25.5f}},   // left, diagonal, top
        {{45.5f, 30.5f}, {50.5f, 40.5f}, {60.5f, 30.5f}},   // flat top
        {{5.5f, 40.5f}, {15.5f, 40.5f}, {10.5f, 30.5f}},    // flat bottom
        {{5.5f, 5.5f}, {15.5f, 5.5f}, {5.5f, 15.5f}},       // clockwise: culled
    };
    for (const auto& corners : cases) {
        Scene s = pixel_scene();
        s.objects.push_back({"t", pixel_triangles(corners), {}, material("unlit"), true});
        const Framebuffer facet = render_facet(s);
        CHECK(coverage_differences(facet, render_llvmpipe(s)) == 0);
    }
}

TEST_CASE("llvmpipe keeps facet's depth order (reversed-Z)", "[llvmpipe]") {
    Scene s = pixel_scene();
    const std::vector<glm::vec2> quad = {{8.5f, 8.5f},   {8.5f, 30.5f}, {40.5f, 30.5f},
                                         {8.5f, 8.5f},   {40.5f, 30.5f}, {40.5f, 8.5f}};
    const std::vector<glm::vec2> shifted = {{20.5f, 16.5f}, {20.5f, 40.5f}, {56.5f, 40.5f},
                                            {20.5f, 16.5f}, {56.5f, 40.5f}, {56.5f, 16.5f}};
    // Near first, then far: the far one must lose where they overlap.
    s.objects.push_back(
        {"near", pixel_triangles(quad, 1.0f), {}, material("unlit", {1, 0, 0, 1}), true});
    s.objects.push_back(
        {"far", pixel_triangles(shifted, -1.0f), {}, material("unlit", {0, 0, 1, 1}), true});
    const Framebuffer facet = render_facet(s);
    const std::vector<glm::vec4> llvmpipe = render_llvmpipe(s);
    CHECK(coverage_differences(facet, llvmpipe) == 0);
    CHECK(max_difference(facet, llvmpipe) == 0.0f);
}

TEST_CASE("llvmpipe's phong and unlit match facet's", "[llvmpipe]") {
    Scene s;
    s.settings.width = 160;
    s.settings.height = 90;
    s.camera.position = {0.0f, 0.35f, 2.6f};
    Light sun;
    sun.direction = glm::normalize(glm::vec3(-0.5f, -1.0f, -0.4f));
    Light point;
    point.type = LightType::point;
    point.position = {1.5f, 1.5f, 2.0f};
    point.attenuation = {1.0f, 0.0f, 0.2f};
    Light spot;
    spot.type = LightType::spot;
    spot.position = {-1.0f, 0.5f, 2.0f};
    spot.direction = glm::normalize(glm::vec3(1.0f, -0.3f, -2.0f));
    spot.color = {1.0f, 0.5f, 0.2f};
    spot.intensity = 3.0f;
    spot.spot_inner = 10.0f;
    Light ranged;
    ranged.type = LightType::point;
    ranged.position = {0.0f, -1.2f, 1.0f};
    ranged.range = 1.6f;
    ranged.color = {0.2f, 0.4f, 1.0f};
    s.lights = {sun, point, spot, ranged};
    for (const char* shader : {"phong", "unlit"}) {
        INFO(shader);
        s.objects = {{"sphere", sphere(40), {}, material(shader), true}};
        const Framebuffer facet = render_facet(s);
        const std::vector<glm::vec4> llvmpipe = render_llvmpipe(s);
        // facet snaps vertices from double window coordinates, llvmpipe from
        // float ones: a pixel centre within ~1/10000 pixel of an edge can
        // fall either way (one pixel here, at 0.015/256 pixel).
        CHECK(coverage_differences(facet, llvmpipe) <= 2);
        CHECK(max_difference(facet, llvmpipe) < 0.01f);  // linear light; float rounding only
    }
}
