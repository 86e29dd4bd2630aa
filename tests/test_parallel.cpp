// The tiled multi-core path: the same image, bit for bit, at any thread
// count; and no heap allocation in a steady frame.
#include "support.hpp"

#include <facet/math.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <new>
#include <random>

// Counts every allocation in this test program, except under
// AddressSanitizer, which must own operator new itself.
#if defined(__SANITIZE_ADDRESS__)
#define FACET_COUNT_ALLOCATIONS 0
#else
#define FACET_COUNT_ALLOCATIONS 1
static std::atomic<long> g_allocations{0};

void* operator new(std::size_t n) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#endif

using namespace facet;

namespace {

bool same_bits(const Framebuffer& a, const Framebuffer& b) {
    const size_t n = size_t(a.width()) * a.height();
    return a.width() == b.width() && a.height() == b.height() &&
           std::memcmp(a.color(), b.color(), n * sizeof(glm::vec4)) == 0 &&
           std::memcmp(a.depth(), b.depth(), n * sizeof(float)) == 0;
}

const char* kScenes[] = {"default.yaml",       "scenes/lit.yaml",    "scenes/phong.yaml",
                         "scenes/toon.yaml",   "scenes/shadow.yaml", "scenes/ao.yaml"};

Scene small_scene(PluginRegistry& registry, const std::string& name) {
    Scene s = load_scene(std::string(FACET_SOURCE_DIR) + "/configs/" + name, registry);
    s.settings.width = 197;  // several tiles; not a multiple of the tile or block size
    s.settings.height = 111;
    return s;
}

}  // namespace

TEST_CASE("every demo scene renders bit for bit the same at any thread count", "[parallel]") {
    PluginRegistry registry;
    for (const char* name : kScenes) {
        INFO(name);
        const Scene scene = small_scene(registry, name);
        Framebuffer one;
        Renderer(1).render(scene, one);
        for (int threads : {2, 3, 5}) {
            Framebuffer many;
            Renderer renderer(threads);
            REQUIRE(renderer.threads() == threads);
            renderer.render(scene, many);
            CHECK(same_bits(one, many));
        }
    }
}

TEST_CASE("MSAA and wireframe render bit for bit the same at any thread count", "[parallel][msaa]") {
    PluginRegistry registry;
    for (const char* name : {"default.yaml", "scenes/shadow.yaml"}) {
        INFO(name);
        Scene scene = small_scene(registry, name);
        scene.settings.msaa = 4;
        scene.settings.wireframe = true;
        Framebuffer one;
        Renderer(1).render(scene, one);
        REQUIRE(one.samples() == 4);
        for (int threads : {2, 3}) {
            Framebuffer many;
            Renderer(threads).render(scene, many);
            CHECK(same_bits(one, many));
        }
    }
}

TEST_CASE("a triangle soup with clipping renders the same at any thread count", "[parallel]") {
    // Overlapping triangles of every size, many crossing the near plane and
    // leaving the screen, blended so that draw order matters.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> xy(-3.0f, 3.0f), z(-6.0f, 0.5f), c(0.0f, 1.0f);
    std::vector<glm::vec3> pos;
    std::vector<glm::vec4> colors;
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < 3 * 1200; ++i) {
        pos.push_back({xy(rng), xy(rng), z(rng)});
        colors.push_back({c(rng), c(rng), c(rng), 0.5f});
        idx.push_back(i);
    }
    const Mesh mesh = test::make_mesh(pos, idx, colors);
    auto shader = test::plugin<test::ColorShader<FACET_INTERP_PERSPECTIVE>>();
    auto draw = [&](int threads) {
        Framebuffer fb(301, 203);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = test::clip_space_call(mesh, *shader);
        call.projection = perspective(glm::radians(70.0f), 301.0f / 203.0f, 0.2f, 50.0f, true);
        call.state.blend = BlendMode::alpha;
        FrameStats stats;
        Renderer(threads).draw(call, fb, stats);
        CHECK(stats.triangles_clipped > 100);
        return fb;
    };
    const Framebuffer one = draw(1);
    for (int threads : {2, 5}) CHECK(same_bits(one, draw(threads)));
}

#if FACET_COUNT_ALLOCATIONS
TEST_CASE("a steady frame allocates nothing on the heap", "[parallel][memory]") {
    PluginRegistry registry;
    for (const char* name : {"scenes/shadow.yaml", "scenes/ao.yaml", "scenes/phong.yaml"}) {
        INFO(name);
        const Scene scene = small_scene(registry, name);
        Renderer renderer(2);
        Framebuffer fb;
        renderer.render(scene, fb);  // the first frames size the buffers
        renderer.render(scene, fb);
        const long before = g_allocations.load();
        const FrameStats stats = renderer.render(scene, fb);
        CHECK(g_allocations.load() - before == 0);
        CHECK(stats.triangles_rasterized > 1000);
    }
}
#endif
