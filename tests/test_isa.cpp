// Instruction-set paths (facet/isa.hpp): choosing one, and every path
// drawing the same image as the others, bit for bit; and packed fragment
// batches (core/src/pipeline/fragment.hpp) drawing what block batches draw.
//
// CTest also runs the raster, pipeline, MSAA and shader tests once per path
// with FACET_ISA set (tests/CMakeLists.txt); this file compares the paths
// with one another within one run.
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/isa.hpp>
#include <facet/math.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <deque>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <optional>
#include <random>
#include <string>

using namespace facet;

namespace {

// Sets FACET_ISA for one scope, and restores what was there.
class ForcedIsa {
public:
    explicit ForcedIsa(const char* value) {
        if (const char* old = std::getenv("FACET_ISA")) old_ = old;
        if (value) setenv("FACET_ISA", value, 1);
        else unsetenv("FACET_ISA");
    }
    ~ForcedIsa() {
        if (old_) setenv("FACET_ISA", old_->c_str(), 1);
        else unsetenv("FACET_ISA");
    }

private:
    std::optional<std::string> old_;
};

ErrorCode error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.code();
    }
    FAIL("no error");
    return ErrorCode::config_invalid;
}

}  // namespace

TEST_CASE("paths: FACET_ISA chooses one, a name that is none is an error", "[isa]") {
    const std::vector<Isa> paths = supported_isas();
    REQUIRE_FALSE(paths.empty());
    CHECK(paths.front() == Isa::portable);
    CHECK(best_isa() == paths.back());
    for (Isa isa : {Isa::portable, Isa::avx2, Isa::avx512}) {
        CHECK(parse_isa(isa_name(isa)) == isa);
        if (isa_supported(isa)) CHECK(Renderer(1, isa).isa() == isa);
        else CHECK(error_of([&] { Renderer(1, isa); }) == ErrorCode::isa_unavailable);
    }
    CHECK(parse_isa("portable") == Isa::portable);
    CHECK_FALSE(parse_isa("avx3"));
    {
        const ForcedIsa forced(nullptr);
        CHECK(default_isa() == best_isa());
        CHECK(Renderer(1).isa() == best_isa());
    }
    {
        const ForcedIsa forced(std::string(isa_name(Isa::portable)).c_str());
        CHECK(default_isa() == Isa::portable);
        CHECK(Renderer(1).isa() == Isa::portable);
    }
    {
        const ForcedIsa forced("avx3");
        CHECK(error_of([] { default_isa(); }) == ErrorCode::config_invalid);
        CHECK(error_of([] { Renderer(1); }) == ErrorCode::config_invalid);
    }
    CHECK_FALSE(cpu_name().empty());
}

TEST_CASE("every demo scene renders bit for bit the same on every path", "[isa]") {
    PluginRegistry registry;
    for (const char* name : test::kDemoScenes)
        for (int variant = 0; variant < 3; ++variant) {
            Scene scene = test::small_demo_scene(registry, name);
            if (variant == 1) {  // MSAA with the wireframe over it, half floats
                scene.settings.msaa = 4;
                scene.settings.wireframe = true;
                scene.settings.color_format = ColorFormat::rgba16f;
            } else if (variant == 2) {  // and AO at half resolution
                scene.settings.color_format = ColorFormat::rgba32f;
                scene.settings.ao_half_resolution = true;
            }
            INFO(name << ", variant " << variant);
            Framebuffer first;
            CHECK(Renderer(2, Isa::portable).render(scene, first).fragments_shaded > 1000);
            for (Isa isa : supported_isas()) {
                if (isa == Isa::portable) continue;  // `first` is its image
                INFO("path " << isa_name(isa));
                Framebuffer other;
                Renderer(2, isa).render(scene, other);
                CHECK(test::same_image(first, other));
            }
        }
}

namespace {

// Colour from the interpolated normal and depth and the pixel's position: a
// smooth function of the varyings, so a fragment shaded with another
// fragment's inputs shows, and a pattern over the screen, so one shaded at
// another pixel's coordinates does.
struct Shade {
    FACET_VARYINGS((sdk::Vec3, normal), (sdk::Vec4, color))
    FACET_PARAMS()
    static constexpr const char* name = "test_shade";
    static constexpr const char* version = "test";
    static constexpr uint32_t needs = FACET_NEED_COLORS;
    static Varyings vertex(const sdk::VertexIn& in, const sdk::Draw& d, const Params&,
                           sdk::Vec4& clip) {
        clip = d.model_view_projection() * sdk::Vec4(in.position, 1.0f);
        return {in.position * 0.3f, in.color};
    }
    static sdk::Vec4 fragment(const Varyings& v, sdk::Fragment& f, const sdk::Draw&,
                              const Params&) {
        const float facing = f.front_facing ? 1.0f : 0.25f;
        const sdk::Float pattern = sdk::fract(0.1234f * f.coord.x + 0.0567f * f.coord.y);
        return {v.color.x * facing, 0.5f + 0.5f * v.normal.y, 0.5f * (f.depth + pattern),
                sdk::splat(1.0f)};
    }
};

// The same shader, shaded a block at a time.
struct ShadeBlocks : Shade {
    static constexpr const char* name = "test_shade_blocks";
    static constexpr bool packable = false;
};

}  // namespace

TEST_CASE("AO at full and half resolution on images narrower than a register, on every path",
          "[isa][ao]") {
    PluginRegistry registry;
    Scene scene = test::small_demo_scene(registry, "scenes/ao.yaml");
    scene.settings.color_format = ColorFormat::rgba32f;
    for (const glm::ivec2 size : {glm::ivec2(5, 3), glm::ivec2(17, 9), glm::ivec2(33, 20)})
        for (bool half : {false, true}) {
            INFO(size.x << "x" << size.y << (half ? ", half" : ", full"));
            scene.settings.width = size.x;
            scene.settings.height = size.y;
            scene.settings.ao_half_resolution = half;
            Framebuffer first;
            Renderer(1, Isa::portable).render(scene, first);
            for (int y = 0; y < size.y; ++y)
                for (int x = 0; x < size.x; ++x) {
                    const glm::vec4 c = first.pixel(x, y);
                    REQUIRE((std::isfinite(c.r) && c.r >= 0.0f && c.r <= 2.0f));
                }
            for (Isa isa : supported_isas()) {
                INFO("path " << isa_name(isa));
                Framebuffer other;
                Renderer(2, isa).render(scene, other);
                CHECK(test::same_image(first, other));
            }
        }
}

// The AO pass's marches count their steps in 16.16 fixed point from the
// start texel's corner (from the grid's corner, a grid 32768 wide or tall
// would not fit 32 bits), and on SSE2 find a step's row with a 16-bit
// multiply (simd::mul_short) where the key's stride fits in 16 bits: up to
// 32688 texels wide, not at 32768 (with the 16-bit product forced there,
// the SSE2 image differs from the others).
TEST_CASE("AO on images up to 32768 wide or tall, on every path", "[isa][ao]") {
    const std::vector<Isa> isas = supported_isas();
    if (isas.size() < 2) {
        WARN("one path: nothing to compare it with");
        return;
    }
    PluginRegistry registry;
    Scene scene = test::small_demo_scene(registry, "scenes/ao.yaml");
    scene.settings.color_format = ColorFormat::rgba32f;
    scene.settings.ao_half_resolution = false;
    constexpr int kMax = Framebuffer::kMaxSize;
    for (const glm::ivec2 size :
         {glm::ivec2(kMax, 48), glm::ivec2(32688, 48), glm::ivec2(2, kMax)}) {
        INFO(size.x << "x" << size.y);
        scene.settings.width = size.x;
        scene.settings.height = size.y;
        Framebuffer first;
        const FrameStats stats = Renderer(1, isas.back()).render(scene, first);
        REQUIRE(stats.ao_passes == 1);
        for (Isa isa : isas) {
            INFO("path " << isa_name(isa));
            Framebuffer other;
            Renderer(2, isa).render(scene, other);
            CHECK(test::same_image(first, other));
        }
    }
}

TEST_CASE("packed fragment batches draw what block batches draw", "[isa][packing]") {
    // Many small triangles of both facings, overlapping in depth, in three
    // draws: the middle one's shader cannot be packed, so the packed
    // fragments of the first must be written before it writes its own.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> centre(-1.0f, 1.0f), z(0.05f, 0.95f),
        offset(-0.04f, 0.04f), c(0.0f, 1.0f);
    std::vector<Mesh> meshes;
    for (int m = 0; m < 3; ++m) {
        std::vector<glm::vec3> pos;
        std::vector<glm::vec4> colors;
        std::vector<uint32_t> idx;
        for (uint32_t t = 0; t < 3000; ++t) {
            const glm::vec3 at(centre(rng), centre(rng), z(rng));
            for (int k = 0; k < 3; ++k) {
                idx.push_back(uint32_t(pos.size()));
                pos.push_back(at + glm::vec3(offset(rng), offset(rng), 0.05f * offset(rng)));
                colors.push_back({c(rng), c(rng), c(rng), 1.0f});
            }
        }
        meshes.push_back(test::make_mesh(pos, idx, colors));
    }
    const auto packable = test::plugin<Shade>(), blocks = test::plugin<ShadeBlocks>();
    REQUIRE(packable->shader_desc().flags & FACET_SHADER_PACKABLE);
    REQUIRE_FALSE(blocks->shader_desc().flags & FACET_SHADER_PACKABLE);
    auto draw = [&](Isa isa, ColorFormat format, bool pack, FrameStats& stats) {
        Framebuffer fb(203, 117, format);
        fb.clear(glm::vec4(0.1f, 0.2f, 0.3f, 1.0f), 0.0f);
        Pipeline renderer(2, isa);
        for (size_t m = 0; m < meshes.size(); ++m) {
            DrawCall call = test::clip_space_call(meshes[m], pack && m != 1 ? *packable : *blocks);
            call.state.depth_compare = DepthCompare::greater_equal;
            renderer.queue(call, fb, stats);
        }
        renderer.flush(stats);
        return fb;
    };
    for (Isa isa : supported_isas())
        for (ColorFormat format : {ColorFormat::srgb8, ColorFormat::rgba32f}) {
            INFO("path " << isa_name(isa) << ", " << color_format_name(format));
            FrameStats packed_stats, block_stats;
            const Framebuffer packed = draw(isa, format, true, packed_stats);
            const Framebuffer blocked = draw(isa, format, false, block_stats);
            CHECK(test::same_image(packed, blocked));
            CHECK(packed_stats.fragments_shaded == block_stats.fragments_shaded);
            CHECK(packed_stats.fragments_depth_rejected > 1000);
            // The packed draws need fewer shader calls for the same fragments.
            CHECK(packed_stats.blocks_shaded * 3 < block_stats.blocks_shaded * 2);
        }
}

TEST_CASE("a block whose every lane passes is shaded after the fragments packed before it",
          "[isa][packing]") {
    // One draw on a 64x64 target: a small triangle inside block (8, 8),
    // then a large one in front of it whose first block, (8, 8), is whole.
    // That block is shaded on its own while the small triangle's fragments
    // still wait in the packed batch: they must be written first, or they
    // would cover it.
    const auto at = [](float x, float y, float z) {
        glm::vec3 p = test::window_to_ndc({x, y}, 64, 64);
        p.z = z;
        return p;
    };
    const Mesh mesh = test::make_mesh(
        {at(9, 9, 0.5f), at(11.5f, 9, 0.5f), at(9, 11.5f, 0.5f),  //
         at(8, 8, 0.9f), at(60, 8, 0.9f), at(8, 60, 0.9f)},
        {0, 1, 2, 3, 4, 5},
        {{1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}, {0, 1, 0, 1}, {0, 1, 0, 1}});
    const auto packable = test::plugin<Shade>(), blocks = test::plugin<ShadeBlocks>();
    for (Isa isa : supported_isas()) {
        INFO("path " << isa_name(isa));
        const auto draw = [&](const ShaderPlugin& shader) {
            Framebuffer fb(64, 64, ColorFormat::rgba32f);
            fb.clear(glm::vec4(0.0f), 0.0f);
            Pipeline pipeline(1, isa);
            DrawCall call = test::clip_space_call(mesh, shader);
            call.state.depth_compare = DepthCompare::greater_equal;
            FrameStats stats;
            pipeline.draw(call, fb, stats);
            return fb;
        };
        const Framebuffer packed = draw(*packable), blocked = draw(*blocks);
        CHECK(test::same_image(packed, blocked));
        CHECK(packed.pixel(9, 9).r == 0.0f);  // the large triangle's (no red in its colour)
    }
}

namespace {

// The pixel's window coordinates as its colour.
struct Coordinates {
    FACET_VARYINGS((sdk::Vec4, color))
    FACET_PARAMS()
    static constexpr const char* name = "test_coordinates";
    static constexpr const char* version = "test";
    static constexpr uint32_t needs = FACET_NEED_COLORS;
    static Varyings vertex(const sdk::VertexIn& in, const sdk::Draw&, const Params&,
                           sdk::Vec4& clip) {
        clip = sdk::Vec4(in.position, 1.0f);
        return {in.color};
    }
    static sdk::Vec4 fragment(const Varyings&, sdk::Fragment& f, const sdk::Draw&,
                              const Params&) {
        return {f.coord.x, f.coord.y, sdk::splat(0.0f), sdk::splat(1.0f)};
    }
};

}  // namespace

TEST_CASE("packed fragments are shaded at their own pixel centres", "[isa][packing]") {
    // Small triangles all over the target, all facing one way (a batch
    // holds one facing), packed many blocks to a batch.
    std::vector<glm::vec3> pos;
    std::vector<uint32_t> idx;
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> centre(-1.0f, 1.0f), size(0.01f, 0.04f),
        turn(0.0f, 6.2831853f);
    for (uint32_t t = 0; t < 2000; ++t) {
        const glm::vec3 at(centre(rng), centre(rng), 0.5f);
        const float r = size(rng), a = turn(rng);
        for (int k = 0; k < 3; ++k) {  // counter-clockwise
            const float angle = a + 2.0943951f * float(k);
            idx.push_back(uint32_t(pos.size()));
            pos.push_back(at + r * glm::vec3(std::cos(angle), std::sin(angle), 0.0f));
        }
    }
    const Mesh mesh = test::make_mesh(pos, idx);
    const auto shader = test::plugin<Coordinates>();
    REQUIRE(shader->shader_desc().flags & FACET_SHADER_PACKABLE);
    for (Isa isa : supported_isas()) {
        INFO("path " << isa_name(isa));
        Framebuffer fb(203, 117, ColorFormat::rgba32f);
        fb.clear(glm::vec4(-1.0f), 0.0f);
        Pipeline renderer(2, isa);
        DrawCall call = test::clip_space_call(mesh, *shader);
        call.state.cull = CullMode::none;
        FrameStats stats;
        renderer.draw(call, fb, stats);
        REQUIRE(stats.fragments_shaded > 2000);
        REQUIRE(stats.blocks_shaded * 2 < stats.fragments_shaded / 16 * 3);  // packed
        int drawn = 0;
        for (int y = 0; y < fb.height(); ++y)
            for (int x = 0; x < fb.width(); ++x) {
                const glm::vec4 c = fb.pixel(x, y);
                if (c.x == -1.0f) continue;
                ++drawn;
                INFO("pixel " << x << ", " << y);
                REQUIRE(c == glm::vec4(float(x) + 0.5f, float(y) + 0.5f, 0.0f, 1.0f));
            }
        CHECK(uint64_t(drawn) <= stats.fragments_shaded);
        CHECK(drawn > 1500);
    }
}

TEST_CASE("shipped wide shaders draw the same packed as a block at a time, on every path",
          "[isa][packing]") {
    // Each plugin's own per-path fragment entries,
    // called with packed batches and, through a copy of its descriptor
    // that does not allow packing, with blocks.
    PluginRegistry registry;
    for (const char* name : test::kDemoScenes) {
        Scene scene = test::small_demo_scene(registry, name);
        scene.settings.msaa = 1;  // fragments are packed only at one sample a pixel
        struct Copy {
            facet_plugin_desc plugin;
            facet_shader_desc shader;
        };
        std::deque<Copy> copies;  // never moved: plugins point into it
        test::PluginSwap blocks(scene, [&](const Material& m) -> std::shared_ptr<ShaderPlugin> {
            const facet_shader_desc& shader = m.plugin->shader_desc();
            if (!(shader.flags & FACET_SHADER_PACKABLE)) return nullptr;
#if FACET_SHADERS_WIDE
            // A plugin built with facet_add_shader has the fragment function
            // of every wide path this build of facet runs (a sanitizer
            // build: none, tests/CMakeLists.txt).
            const auto has = [&](uint32_t isa) {
                for (uint32_t i = 0; i < shader.fragment_count; ++i)
                    if (shader.fragments[i].isa == isa) return true;
                return false;
            };
            for (Isa isa : supported_isas()) {
                if (isa == Isa::avx2) REQUIRE(has(FACET_ISA_X86_64_V3));
                if (isa == Isa::avx512) REQUIRE(has(FACET_ISA_X86_64_V4));
            }
#endif
            Copy& c = copies.emplace_back(Copy{m.plugin->desc(), shader});
            c.shader.flags &= ~uint32_t(FACET_SHADER_PACKABLE);
            c.plugin.shader = &c.shader;
            return ShaderPlugin::from_descriptor(&c.plugin, "test");
        });
        REQUIRE_FALSE(blocks.empty());
        for (Isa isa : supported_isas()) {
            INFO(name << ", path " << isa_name(isa));
            Framebuffer packed, blocked;
            const FrameStats packed_stats = Renderer(2, isa).render(scene, packed);
            blocks.swap();
            const FrameStats block_stats = Renderer(2, isa).render(scene, blocked);
            blocks.swap();
            CHECK(test::same_image(packed, blocked));
            CHECK(packed_stats.fragments_shaded == block_stats.fragments_shaded);
            CHECK(packed_stats.blocks_shaded < block_stats.blocks_shaded);
        }
    }
}
