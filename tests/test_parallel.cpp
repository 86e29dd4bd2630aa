// The tiled multi-core path: the same image, bit for bit, at any thread
// count; and no heap allocation in a steady frame.
#include "support.hpp"

#include "base/thread_pool.hpp"
#include "pipeline/framebuffer_access.hpp"

#include <facet/math.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <new>
#include <random>
#include <thread>
#include <vector>

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

// Unindexed triangles of `vertices` random vertices (x and y within
// -spread .. spread, z within z_min .. z_max), each of a random colour of
// alpha `alpha`.
Mesh triangle_soup(std::mt19937& rng, uint32_t vertices, float spread, float z_min, float z_max,
                   float alpha) {
    std::uniform_real_distribution<float> xy(-spread, spread), z(z_min, z_max), c(0.0f, 1.0f);
    std::vector<glm::vec3> pos;
    std::vector<glm::vec4> colors;
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < vertices; ++i) {
        pos.push_back({xy(rng), xy(rng), z(rng)});
        colors.push_back({c(rng), c(rng), c(rng), alpha});
        idx.push_back(i);
    }
    return test::make_mesh(pos, idx, colors);
}

}  // namespace

TEST_CASE("the thread pool runs every item of every loop once, whether its threads wait "
          "spinning or asleep between loops",
          "[parallel]") {
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    for (int threads : {2, 3, cores + 1}) {
        INFO(threads << " threads");
        ThreadPool pool(threads);
        REQUIRE(pool.size() == threads);
        CHECK(pool.spins() == (threads <= cores));  // never when more threads than cores
        // Plain ints, one per item: what the items wrote must be seen once
        // the loop returns (ThreadSanitizer checks the ordering).
        std::vector<int> runs(64), worker_of(64);
        for (int loop = 0; loop < 600; ++loop) {
            const int n = 1 + loop % 64;
            std::fill(runs.begin(), runs.end(), 0);
            std::fill(worker_of.begin(), worker_of.end(), -1);
            // Now and then an item a worker takes outlasts the spin, so that
            // the caller sleeps until the worker wakes it.
            const bool slow = loop % 40 == 39;
            pool.parallel_for(n, [&](int i, int worker) {
                ++runs[size_t(i)];
                worker_of[size_t(i)] = worker;
                if (slow && worker != 0) std::this_thread::sleep_for(ThreadPool::kSpin * 3);
            });
            for (int i = 0; i < 64; ++i) {
                REQUIRE(runs[size_t(i)] == (i < n ? 1 : 0));
                if (i < n) REQUIRE((worker_of[size_t(i)] >= 0 && worker_of[size_t(i)] < threads));
            }
            // Now and then a pause past the spin, so that the workers sleep
            // and the next loop wakes them.
            if (loop % 50 == 49) std::this_thread::sleep_for(ThreadPool::kSpin * 5);
        }
    }
}

TEST_CASE("every demo scene renders bit for bit the same at any thread count", "[parallel]") {
    PluginRegistry registry;
    for (const char* name : test::kDemoScenes) {
        INFO(name);
        const Scene scene = test::small_demo_scene(registry, name);
        Framebuffer one;
        Renderer(1).render(scene, one);
        for (int threads : {2, 3, 5}) {
            Framebuffer many;
            Renderer renderer(threads);
            REQUIRE(renderer.threads() == threads);
            renderer.render(scene, many);
            CHECK(test::same_image(one, many));
        }
    }
}

TEST_CASE("a depth pre-pass renders the same image, shading each pixel once", "[parallel][depth]") {
    PluginRegistry registry;
    // The demo scenes (shadows, AO, blending, toon), with and without MSAA.
    for (const char* name : test::kDemoScenes)
        for (int msaa : {1, 4}) {
            INFO(name << ", msaa " << msaa);
            Scene scene = test::small_demo_scene(registry, name);
            scene.settings.msaa = msaa;
            scene.settings.depth_prepass = false;  // as some demo scenes ask
            Framebuffer plain, prepassed;
            const FrameStats a = Renderer(2).render(scene, plain);
            scene.settings.depth_prepass = true;
            const FrameStats b = Renderer(2).render(scene, prepassed);
            CHECK(test::same_image(plain, prepassed));
            // A frame whose materials use the stencil has none: the
            // stencil's operations see the depth the parts before them left.
            bool stencil = false;
            for (const Object& o : scene.objects)
                for (const Material* m : o.materials()) stencil |= m->stencil.enabled;
            CHECK(b.depth_prepasses == (stencil ? 0u : 1u));
            // The main pass shades the pre-pass's triangles (the opaque
            // parts' vertex stage, setup and binning run once), unless AO
            // drew a pre-pass of its own (with MSAA) in between.
            CHECK((b.draws_redrawn > 0) == (b.prepasses == 0 && !stencil));
            // Without it, a single-sampled frame with AO draws it all the same,
            // for the AO to read (below).
            CHECK(a.depth_prepasses == (a.ao_passes && msaa == 1 ? 1u : 0u));
            CHECK(b.fragments_shaded <= a.fragments_shaded);
        }
    // Four screen-filling quads drawn far to near: every layer passes the
    // depth test without the pre-pass, only the nearest with it.
    Scene scene = test::small_demo_scene(registry, "scenes/phong.yaml");
    scene.settings.depth_prepass = false;
    std::vector<Object> layers;
    for (int k = 0; k < 4; ++k) {
        const float z = -1.5f + 0.5f * float(k);
        auto quad = std::make_shared<Mesh>(test::make_mesh(
            {{-9, -9, z}, {9, -9, z}, {9, 9, z}, {-9, 9, z}}, {0, 1, 2, 0, 2, 3}));
        quad->normals.assign(4, glm::vec3(0, 0, 1));
        layers.push_back({"layer", quad, {}, scene.objects.front().material, true});
    }
    scene.objects = layers;
    const int pixels = scene.settings.width * scene.settings.height;
    Framebuffer plain, prepassed;
    const FrameStats a = Renderer(2).render(scene, plain);
    scene.settings.depth_prepass = true;
    const FrameStats b = Renderer(2).render(scene, prepassed);
    CHECK(test::same_image(plain, prepassed));
    CHECK(a.fragments_shaded == uint64_t(4 * pixels));
    CHECK(b.fragments_shaded == uint64_t(pixels));
}

TEST_CASE("MSAA and wireframe render bit for bit the same at any thread count", "[parallel][msaa]") {
    PluginRegistry registry;
    for (const char* name : {"default.yaml", "scenes/shadow.yaml"}) {
        INFO(name);
        Scene scene = test::small_demo_scene(registry, name);
        scene.settings.msaa = 4;
        scene.settings.wireframe = true;
        Framebuffer one;
        Renderer(1).render(scene, one);
        REQUIRE(one.samples() == 4);
        for (int threads : {2, 3}) {
            Framebuffer many;
            Renderer(threads).render(scene, many);
            CHECK(test::same_image(one, many));
        }
    }
}

TEST_CASE("a triangle soup with clipping renders the same at any thread count", "[parallel]") {
    // Overlapping triangles of every size, many crossing the near plane and
    // leaving the screen, blended so that draw order matters.
    std::mt19937 rng(7);
    const Mesh mesh = triangle_soup(rng, 3 * 1200, 3.0f, -6.0f, 0.5f, 0.5f);
    auto shader = test::plugin<test::ColorShader<FACET_INTERP_PERSPECTIVE>>();
    auto draw = [&](int threads) {
        Framebuffer fb(301, 203);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = test::clip_space_call(mesh, *shader);
        call.projection = perspective(glm::radians(70.0f), 301.0f / 203.0f, 0.2f, 50.0f, true);
        call.state.blend = BlendMode::alpha;
        FrameStats stats;
        Pipeline(threads).draw(call, fb, stats);
        CHECK(stats.triangles_clipped > 100);
        return fb;
    };
    const Framebuffer one = draw(1);
    for (int threads : {2, 5}) CHECK(test::same_image(one, draw(threads)));
}

TEST_CASE("queued draws render what one draw() at a time renders", "[parallel][queue]") {
    // 400 blended meshes of three triangles (more than the renderer queues
    // at once), some crossing the near plane, alternating between two
    // targets part of the way through.
    std::mt19937 rng(11);
    std::vector<Mesh> meshes;
    for (int m = 0; m < 400; ++m) meshes.push_back(triangle_soup(rng, 9, 2.0f, -4.0f, 0.3f, 0.5f));
    auto shader = test::plugin<test::ColorShader<FACET_INTERP_PERSPECTIVE>>();
    auto render = [&](bool queued, Framebuffer (&fb)[2], FrameStats& stats) {
        Pipeline renderer(2);
        for (Framebuffer& f : fb) {
            f.resize(157, 93);
            f.clear(glm::vec4(0.0f), 0.0f);
        }
        for (size_t m = 0; m < meshes.size(); ++m) {
            DrawCall call = test::clip_space_call(meshes[m], *shader);
            call.projection = perspective(glm::radians(60.0f), 157.0f / 93.0f, 0.2f, 50.0f, true);
            // Each draw's own state must reach its triangles.
            call.state.blend = m % 3 ? BlendMode::alpha : BlendMode::additive;
            Framebuffer& target = fb[m >= 300 && m % 2 ? 1 : 0];
            if (queued) renderer.queue(call, target, stats);
            else renderer.draw(call, target, stats);
        }
        renderer.flush(stats);
    };
    Framebuffer one[2], many[2];
    FrameStats one_stats, many_stats;
    render(false, one, one_stats);
    render(true, many, many_stats);
    CHECK(test::same_image(one[0], many[0]));
    CHECK(test::same_image(one[1], many[1]));
    CHECK(many_stats.draws == 400);
    CHECK(many_stats.triangles_clipped > 50);  // clipped vertices live in the queued chunks
    CHECK(many_stats.triangles_rasterized == one_stats.triangles_rasterized);
    CHECK(many_stats.fragments_shaded == one_stats.fragments_shaded);
    CHECK(many_stats.fragments_shaded > 10000);
}

TEST_CASE("a pre-pass's triangles drawn again with the main pass's state give the image "
          "queueing them again gives, and only calls that make the same triangles take them",
          "[parallel][queue][depth]") {
    // Two overlapping meshes of many triangles, some crossing the near plane.
    std::mt19937 rng(5);
    std::vector<Mesh> meshes;
    for (int m = 0; m < 2; ++m) meshes.push_back(triangle_soup(rng, 600, 2.0f, -4.0f, 0.3f, 1.0f));
    auto shader = test::plugin<test::ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const auto calls = [&](bool prepass) {
        std::vector<DrawCall> out;
        for (const Mesh& mesh : meshes) {
            DrawCall call = test::clip_space_call(mesh, *shader);
            call.projection = perspective(glm::radians(60.0f), 157.0f / 93.0f, 0.2f, 50.0f, true);
            call.state.cull = CullMode::none;
            if (prepass) call.state.color_write = false;
            else call.state.depth_compare = DepthCompare::equal, call.state.depth_write = false;
            out.push_back(call);
        }
        return out;
    };
    const auto cleared = [](Framebuffer& fb) {
        fb.resize(157, 93);
        fb.clear(glm::vec4(0.0f), 0.0f);
    };
    // The pre-pass, then the main pass queued anew, or drawn again.
    Framebuffer queued, redrawn;
    FrameStats queued_stats, redrawn_stats, ignored;
    {
        Pipeline p(2);
        cleared(queued);
        for (const DrawCall& call : calls(true)) p.queue(call, queued, ignored);
        p.flush(ignored, true);
        for (const DrawCall& call : calls(false)) p.queue(call, queued, queued_stats);
        p.flush(queued_stats);
    }
    {
        Pipeline p(2);
        cleared(redrawn);
        for (const DrawCall& call : calls(true)) p.queue(call, redrawn, ignored);
        p.flush(ignored, true);
        REQUIRE(p.redraw(calls(false), redrawn, redrawn_stats));
    }
    CHECK(test::same_image(queued, redrawn));
    CHECK(redrawn_stats.draws_redrawn == 2);
    CHECK(queued_stats.draws_redrawn == 0);
    CHECK(redrawn_stats.draws == queued_stats.draws);
    CHECK(redrawn_stats.vertices_shaded == queued_stats.vertices_shaded);
    CHECK(redrawn_stats.triangles_clipped == queued_stats.triangles_clipped);
    CHECK(redrawn_stats.triangles_clipped > 0);
    CHECK(redrawn_stats.triangles_rasterized == queued_stats.triangles_rasterized);
    CHECK(redrawn_stats.fragments_shaded == queued_stats.fragments_shaded);
    CHECK(redrawn_stats.fragments_shaded > 1000);

    // Calls that would make other triangles (moved, culled otherwise, another
    // mesh, one call fewer), another target, or nothing kept: nothing is
    // drawn and false returned.
    Framebuffer other;
    cleared(other);
    using Change = std::function<void(std::vector<DrawCall>&)>;
    const Change changes[] = {
        [](std::vector<DrawCall>& c) { c[1].model[3][0] += 0.01f; },
        [](std::vector<DrawCall>& c) { c[0].state.cull = CullMode::back; },
        [](std::vector<DrawCall>& c) { std::swap(c[0].mesh, c[1].mesh); },
        [](std::vector<DrawCall>& c) { c.pop_back(); },
        [](std::vector<DrawCall>& c) { c[0].state.subpixel_bits = 4; },
        [](std::vector<DrawCall>& c) { c[1].time = 1.0f; },
    };
    for (const Change& change : changes) {
        Pipeline p(2);
        Framebuffer fb;
        cleared(fb);
        for (const DrawCall& call : calls(true)) p.queue(call, fb, ignored);
        p.flush(ignored, true);
        const Framebuffer before = fb;
        std::vector<DrawCall> main = calls(false);
        change(main);
        FrameStats stats;
        CHECK_FALSE(p.redraw(main, fb, stats));
        CHECK(test::same_image(before, fb));
        CHECK(stats.draws == 0);
        CHECK_FALSE(p.redraw(calls(false), fb, stats));  // nothing is kept after that
    }
    Pipeline p(2);
    Framebuffer fb;
    cleared(fb);
    for (const DrawCall& call : calls(true)) p.queue(call, fb, ignored);
    p.flush(ignored, true);
    CHECK_FALSE(p.redraw(calls(false), other, ignored));
    // The same target, resized (the kept triangles' boxes and bins are the
    // old size's).
    for (const DrawCall& call : calls(true)) p.queue(call, fb, ignored);
    p.flush(ignored, true);
    fb.resize(120, 70);
    fb.clear(glm::vec4(0.0f), 0.0f);
    CHECK_FALSE(p.redraw(calls(false), fb, ignored));
    cleared(fb);
    // Draws queued and not yet flushed are not dropped: the next flush draws them.
    {
        Framebuffer waiting, direct;
        cleared(waiting), cleared(direct);
        FrameStats stats;
        DrawCall call = calls(false)[0];
        call.state.depth_compare = DepthCompare::greater_equal;  // reversed z, cleared to 0
        call.state.depth_write = true;
        p.queue(call, waiting, stats);
        CHECK_FALSE(p.redraw(calls(false), waiting, stats));
        p.flush(stats);
        Pipeline q(2);
        FrameStats direct_stats;
        q.draw(call, direct, direct_stats);
        CHECK(stats.fragments_shaded == direct_stats.fragments_shaded);
        CHECK(stats.fragments_shaded > 0);
        CHECK(test::same_image(waiting, direct));
    }
    for (const DrawCall& call : calls(true)) p.queue(call, fb, ignored);
    p.flush(ignored);  // not kept
    CHECK_FALSE(p.redraw(calls(false), fb, ignored));
    for (const DrawCall& call : calls(true)) p.queue(call, fb, ignored);
    p.flush(ignored, true);
    p.queue(calls(true)[0], fb, ignored);  // drops what was kept
    p.flush(ignored);
    CHECK_FALSE(p.redraw(calls(false), fb, ignored));

    // A mesh too large to queue at once is rasterized part way as it is
    // queued: the queue then holds only its last triangles, and keeps nothing.
    std::uniform_real_distribution<float> xy(-2.0f, 2.0f), c(0.0f, 1.0f);
    std::vector<glm::vec3> pos;
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < 3 * 40000; ++i) {
        pos.push_back({xy(rng), xy(rng), -1.0f - 0.1f * c(rng)});
        idx.push_back(i);
    }
    const Mesh large = test::make_mesh(pos, idx);
    DrawCall call = test::clip_space_call(large, *shader);
    call.state.color_write = false;
    p.queue(call, fb, ignored);
    p.flush(ignored, true);
    call.state.color_write = true;
    CHECK_FALSE(p.redraw({call}, fb, ignored));
}

namespace {

// Every byte of fb's storage, padding and samples included.
std::vector<uint8_t> storage(const Framebuffer& fb) {
    const size_t pixels = size_t(fb.stride()) * size_t(fb.rows()), n = size_t(fb.samples());
    const size_t bytes = size_t(bytes_per_pixel(fb.format()));
    std::vector<uint8_t> out;
    const auto add = [&](const void* p, size_t size) {
        const auto* b = static_cast<const uint8_t*>(p);
        out.insert(out.end(), b, b + size);
    };
    add(fb.depth(), pixels * 4);
    add(fb.color_data(), pixels * bytes);
    if (n > 1) {
        add(fb.sample_depth(), pixels * n * 4);
        add(fb.sample_color_data(), pixels * n * bytes);
    }
    return out;
}

// Bytes of the two framebuffers' storage that differ (a count prints
// shorter than the storage itself).
size_t bytes_differing(const Framebuffer& a, const Framebuffer& b) {
    const std::vector<uint8_t> x = storage(a), y = storage(b);
    if (x.size() != y.size()) return std::max(x.size(), y.size());
    size_t n = 0;
    for (size_t i = 0; i < x.size(); ++i) n += x[i] != y[i];
    return n;
}

}  // namespace

TEST_CASE("a pipeline's clear, waiting for the draws, leaves every byte Framebuffer::clear "
          "leaves", "[parallel][queue][clear]") {
    // 150 x 70: tiles cut by both edges, and padding past them. The draws
    // touch some tiles (cleared as they are drawn), not others (cleared when
    // the clear completes).
    std::mt19937 rng(9);
    const Mesh soup = triangle_soup(rng, 30, 0.5f, -3.0f, 0.5f, 1.0f);
    auto shader = test::plugin<test::ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const glm::vec4 clear(0.25f, 0.5f, 0.75f, 1.0f), garbage(7.0f, -3.0f, 0.5f, 0.0f);
    DrawCall call = test::clip_space_call(soup, *shader);
    call.projection = perspective(glm::radians(60.0f), 150.0f / 70.0f, 0.2f, 50.0f, true);
    call.state.depth_compare = DepthCompare::greater;
    call.state.cull = CullMode::none;
    for (Isa isa : supported_isas())
        for (ColorFormat format : {ColorFormat::srgb8, ColorFormat::rgba32f, ColorFormat::none})
            for (int samples : {1, 4}) {
                INFO(isa_name(isa) << ", " << color_format_name(format) << ", " << samples
                                   << " samples");
                Framebuffer want(150, 70, format, samples), got(150, 70, format, samples);
                want.clear(garbage, 0.75f);
                got.clear(garbage, 0.75f);
                Pipeline p(2, isa);
                FrameStats stats;
                want.clear(clear, 0.0f);
                p.draw(call, want, stats);
                p.clear(got, clear, 0.0f);
                p.queue(call, got, stats);
                p.flush(stats);
                CHECK(bytes_differing(got, want) == 0);

                // With no draw, each way of completing it.
                want.clear(clear, 0.0f);
                Framebuffer resolved = want;
                resolved.resolve();
                for (int way = 0; way < 4; ++way) {
                    const char* ways[] = {"flush", "resolve", "resolve_srgb8", "cancel"};
                    INFO("completed by " << ways[way]);
                    got.clear(garbage, 0.75f);
                    p.clear(got, clear, 0.0f);
                    std::vector<uint8_t> rgba;
                    if (way == 0) p.flush(stats);
                    if (way == 1) p.resolve(got);
                    if (way == 2) p.resolve_srgb8(got, rgba);
                    if (way == 3) p.cancel();
                    CHECK(bytes_differing(got, way == 1 ? resolved : want) == 0);
                    if (way == 2) CHECK(rgba == want.resolve_srgb8());
                }
            }
    // A target resized while its clear waits is left alone, not written past
    // its new end (the sanitizer build would see it), and a clear after that
    // clears it.
    Pipeline p(2);
    FrameStats stats;
    Framebuffer shrunk(150, 70);
    p.clear(shrunk, clear, 0.0f);
    shrunk.resize(20, 10);
    p.queue(call, shrunk, stats);
    p.flush(stats);
    Framebuffer want(20, 10), got(20, 10);
    want.clear(clear, 0.0f);
    p.draw(call, want, stats);
    p.clear(shrunk, clear, 0.0f);
    p.queue(call, shrunk, stats);
    p.flush(stats);
    got = shrunk;
    CHECK(bytes_differing(got, want) == 0);
}

TEST_CASE("a clear writes again only the tiles that no longer hold its values",
          "[parallel][queue][clear]") {
    std::mt19937 rng(9);
    const Mesh soup = triangle_soup(rng, 30, 0.5f, -3.0f, 0.5f, 1.0f);
    auto shader = test::plugin<test::ColorShader<FACET_INTERP_PERSPECTIVE>>();
    const glm::vec4 clear(0.25f, 0.5f, 0.75f, 1.0f), other(0.5f, 0.25f, 0.0f, 1.0f);
    DrawCall call = test::clip_space_call(soup, *shader);
    call.projection = perspective(glm::radians(60.0f), 150.0f / 70.0f, 0.2f, 50.0f, true);
    call.state.depth_compare = DepthCompare::greater;
    call.state.cull = CullMode::none;
    for (Isa isa : supported_isas())
        for (ColorFormat format : {ColorFormat::srgb8, ColorFormat::rgba32f})
            for (int samples : {1, 4}) {
                INFO(isa_name(isa) << ", " << color_format_name(format) << ", " << samples
                                   << " samples");
                Framebuffer got(150, 70, format, samples), want(150, 70, format, samples),
                    want_other(150, 70, format, samples);
                want.clear(clear, 0.0f);
                want_other.clear(other, 0.0f);
                Pipeline p(2, isa);
                FrameStats stats;
                const auto clear_to = [&](const glm::vec4& color) {
                    p.clear(got, color, 0.0f);
                    p.flush(stats);
                };
                clear_to(clear);
                // Draws after the clear completed mark the tiles they touch.
                p.queue(call, got, stats);
                p.flush(stats);
                REQUIRE(bytes_differing(got, want) > 0);
                clear_to(clear);
                CHECK(bytes_differing(got, want) == 0);
                // A tile that holds the values is not written again: a byte
                // changed behind the pipeline's back (as only this test can)
                // stays.
                FramebufferAccess::depth(got)[0] = 0.5f;
                clear_to(clear);
                CHECK(got.depth_at(0, 0) == 0.5f);
                // Other values: every tile.
                clear_to(other);
                CHECK(bytes_differing(got, want_other) == 0);
                // The framebuffer's own writes, and an MSAA resolve, forget
                // what was known.
                for (int way = 0; way < 4; ++way) {
                    INFO("way " << way);
                    if (way == 0) got.set_pixel(0, 0, glm::vec4(1.0f));
                    if (way == 1) got.clear(clear, 0.0f);
                    if (way == 2) got.resize(150, 70, format, samples);
                    if (way == 3) p.resolve(got);
                    FramebufferAccess::depth(got)[0] = 0.5f;
                    clear_to(other);
                    if (way == 3 && samples == 1) {  // nothing to resolve, nothing written
                        CHECK(got.depth_at(0, 0) == 0.5f);
                        FramebufferAccess::depth(got)[0] = 0.0f;
                    }
                    CHECK(bytes_differing(got, want_other) == 0);
                }
                // A caller's pointer to writable storage, asked for before,
                // may be written at any time: from then on, every tile.
                float* const depth = got.depth();
                clear_to(other);
                depth[0] = 0.5f;
                clear_to(other);
                CHECK(bytes_differing(got, want_other) == 0);
                // So does an assignment to it, which may keep its storage.
                Framebuffer known(150, 70, format, samples), assigned(150, 70, format, samples);
                p.clear(known, other, 0.0f);
                p.flush(stats);
                float* const into = assigned.depth();
                assigned = known;
                into[0] = 0.5f;
                p.clear(assigned, other, 0.0f);
                p.flush(stats);
                CHECK(bytes_differing(assigned, want_other) == 0);
            }
}

namespace {

// A demo scene looking up, away from its objects: every tile is left to the
// clear, the sky and the post chain.
Scene looking_up(PluginRegistry& registry, const std::string& name) {
    Scene scene = test::small_demo_scene(registry, name);
    scene.camera.target = scene.camera.position + glm::vec3(0.0f, 1.0f, 0.3f);
    return scene;
}

}  // namespace

TEST_CASE("the sky and the post chain leave no tile a later clear skips",
          "[parallel][clear]") {
    PluginRegistry registry;
    // The same frame (`second`) from a renderer that drew `first` into the
    // target a frame before, and from a new one.
    const auto after = [&](const Scene& first, const Scene& second) {
        Renderer renderer(2);
        Framebuffer fb;
        renderer.render(second, fb);  // what a clear to the same values may keep
        renderer.render(first, fb);
        renderer.render(second, fb);
        Renderer fresh(2);
        Framebuffer want;
        fresh.render(second, want);
        return bytes_differing(fb, want);
    };
    Scene sky = looking_up(registry, "scenes/environment.yaml");
    REQUIRE(sky.environment);
    sky.settings.post = false;  // the sky into the target itself
    Scene no_sky = looking_up(registry, "scenes/environment.yaml");
    no_sky.settings.post = false;
    no_sky.environment.settings.use = EnvironmentUse::lighting;
    CHECK(after(sky, no_sky) == 0);
    const Scene post = looking_up(registry, "scenes/post.yaml");
    REQUIRE(!post.post.empty());
    Scene no_post = looking_up(registry, "scenes/post.yaml");
    no_post.settings.post = false;
    CHECK(after(post, no_post) == 0);  // the chain's result in the target
    CHECK(after(post, post) == 0);     // the passes' writes to the frame they read
}

#if FACET_COUNT_ALLOCATIONS
TEST_CASE("a steady frame allocates nothing on the heap", "[parallel][memory]") {
    PluginRegistry registry;
    for (const char* name : {"scenes/shadow.yaml", "scenes/ao.yaml", "scenes/phong.yaml"}) {
        INFO(name);
        const Scene scene = test::small_demo_scene(registry, name);
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
