// Plugin loading and the ABI: real .so files, good and deliberately bad, and
// where plugins are searched for.
#include "abi_layout.h"
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/plugin.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <fstream>

#include <cstddef>
#include <fstream>

using namespace facet;
namespace fs = std::filesystem;

extern "C" size_t facet_c_layout(size_t* out);  // abi_c_check.c

namespace {

const fs::path kTestPlugins = FACET_TEST_PLUGIN_DIR;

ErrorCode load_error(const fs::path& path, std::string* message = nullptr) {
    try {
        ShaderPlugin::load(path);
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.code();
    }
    FAIL("plugin " << path << " was accepted");
    return ErrorCode::config_invalid;
}

}  // namespace

TEST_CASE("the ABI header compiles as C with the same layout", "[abi]") {
#define FACET_ABI_PUT(value) value,
    const size_t cpp[] = {FACET_ABI_LAYOUT(FACET_ABI_PUT)};
#undef FACET_ABI_PUT
    size_t c[128];
    REQUIRE(facet_c_layout(c) == std::size(cpp));
    for (size_t i = 0; i < std::size(cpp); ++i) {
        INFO("entry " << i << " of FACET_ABI_LAYOUT");
        CHECK(c[i] == cpp[i]);
    }
}

TEST_CASE("a plugin written in C loads and draws", "[abi][plugin]") {
    auto plugin = ShaderPlugin::load(kTestPlugins / "c_plugin.so", "c_plugin");
    CHECK(plugin->name() == "c_plugin");
    const Mesh mesh = test::make_mesh({{-1, -1, 0.5f}, {1, -1, 0.5f}, {0, 1, 0.5f}}, {0, 1, 2});
    Framebuffer fb(8, 8);
    fb.clear(glm::vec4(0.0f), 0.0f);
    FrameStats stats;
    Pipeline().draw(test::clip_space_call(mesh, *plugin), fb, stats);
    CHECK(fb.pixel(4, 4) == glm::vec4(1.0f, 0.5f, 0.25f, 1.0f));
}

TEST_CASE("plugins with a mismatched ABI are refused, saying why", "[abi][plugin]") {
    std::string why;
    const std::string minor = std::to_string(FACET_ABI_MINOR);
    CHECK(load_error(kTestPlugins / "wrong_major.so", &why) == ErrorCode::plugin_abi_mismatch);
    CHECK_THAT(why, Catch::Contains("built for ABI 3." + minor) &&
                        Catch::Contains("this host speaks ABI 2." + minor) &&
                        Catch::Contains("wrong_major.so"));
    // An ABI 1 plugin: its ABI named, and what to do.
    CHECK(load_error(kTestPlugins / "abi1_plugin.so", &why) == ErrorCode::plugin_abi_mismatch);
    CHECK_THAT(why, Catch::Contains("built for ABI 1.6") &&
                        Catch::Contains("this host speaks ABI 2." + minor) &&
                        Catch::Contains("rebuild the plugin against this facet SDK"));
    CHECK(load_error(kTestPlugins / "short_desc.so", &why) == ErrorCode::plugin_struct_size);
    CHECK_THAT(why, Catch::Contains("the descriptor is 16 bytes"));
    CHECK(load_error(kTestPlugins / "short_shader.so", &why) == ErrorCode::plugin_struct_size);
    CHECK_THAT(why, Catch::Contains("the shader record is 8 bytes"));
    CHECK(load_error(kTestPlugins / "no_baseline.so", &why) == ErrorCode::plugin_invalid);
    CHECK_THAT(why, Catch::Contains("no fragment entry for FACET_ISA_BASELINE"));
    CHECK(load_error(kTestPlugins / "both_kinds.so", &why) == ErrorCode::plugin_invalid);
    CHECK_THAT(why, Catch::Contains("both a shader and a screen pass"));
    CHECK(load_error(kTestPlugins / "no_entry.so", &why) == ErrorCode::plugin_no_entry);
    CHECK_THAT(why, Catch::Contains("facet_plugin_entry"));
    CHECK(load_error(kTestPlugins / "missing_symbol.so", &why) == ErrorCode::plugin_load_failed);
    CHECK_THAT(why, Catch::Contains("facet_test_symbol_nobody_defines"));
}

TEST_CASE("files that are not plugins are refused", "[plugin]") {
    const test::TempDir folder("plugin");
    const fs::path& dir = folder.path;
    std::ofstream(dir / "garbage.so") << "this is not an ELF file";
    CHECK(load_error(dir / "garbage.so") == ErrorCode::plugin_load_failed);
    // A real plugin cut short, as a half-finished compile leaves it.
    const fs::path good = kTestPlugins / "c_plugin.so";
    fs::copy_file(good, dir / "truncated.so");
    fs::resize_file(dir / "truncated.so", fs::file_size(good) / 3);
    CHECK(load_error(dir / "truncated.so") == ErrorCode::plugin_load_failed);
    CHECK(load_error(dir / "absent.so") == ErrorCode::file_not_found);
    // A whole library for another machine, and an object file: the cause
    // named (dlopen's own message does not say it). The ELF header's
    // e_type is at byte 16 and e_machine at 18, little-endian here.
    const auto patched = [&](const char* name, int offset, uint16_t value) {
        fs::copy_file(good, dir / name);
        std::fstream file(dir / name, std::ios::in | std::ios::out | std::ios::binary);
        file.seekp(offset);
        const char bytes[2] = {char(value & 0xFF), char(value >> 8)};
        file.write(bytes, 2);
        return dir / name;
    };
    std::string why;
#if defined(__x86_64__)
    CHECK(load_error(patched("arm.so", 18, 183), &why) == ErrorCode::plugin_load_failed);
    CHECK_THAT(why, Catch::Contains("it is built for AArch64 (ELF machine 183), and "
                                    "this process runs on x86-64"));
#endif
    CHECK(load_error(patched("object.so", 16, 1), &why) == ErrorCode::plugin_load_failed);
    CHECK_THAT(why, Catch::Contains("it is an object file, not a shared library"));
    // EI_DATA (byte 5) says big-endian: named, not taken for a file cut short.
    CHECK(load_error(patched("big.so", 4, 0x0202), &why) == ErrorCode::plugin_load_failed);
    CHECK_THAT(why, Catch::Contains("it is built for a machine of the other byte order"));
}

namespace {

// A descriptor to change field by field: copies of its records, linked.
struct DescCopy {
    facet_plugin_desc plugin;
    facet_shader_desc shader;
    explicit DescCopy(const facet_plugin_desc* d) : plugin(*d), shader(*d->shader) {
        plugin.shader = &shader;
    }
    DescCopy(const DescCopy& o) : DescCopy(&o.plugin) {}
    DescCopy& operator=(const DescCopy& o) {
        plugin = o.plugin, shader = o.shader;
        plugin.shader = &shader;
        return *this;
    }
    // The plugin's error, or "accepted".
    std::string why() const {
        try {
            ShaderPlugin::from_descriptor(&plugin, "test");
        } catch (const Error& e) {
            CHECK(e.code() == ErrorCode::plugin_invalid);
            return e.what();
        }
        return "accepted";
    }
};

const facet_plugin_desc* color_shader() {
    return sdk::describe<test::ColorShader<FACET_INTERP_PERSPECTIVE>>();
}

}  // namespace

TEST_CASE("a descriptor that lies about itself is refused", "[plugin]") {
    const DescCopy real(color_shader());
    DescCopy d = real;
    CHECK(d.why() == "accepted");
    facet_varying_desc bad_varying = {"v", 5, FACET_INTERP_PERSPECTIVE};
    d.shader.varyings = &bad_varying;
    CHECK_THAT(d.why(), Catch::Contains("varying 0 has 5 components"));
    d = real;
    d.shader.vertex = nullptr;
    CHECK_THAT(d.why(), Catch::Contains("no vertex function"));
    // The fragment entries: one at least, each with its function, each
    // instruction set once, the baseline among them; a later one's unknown
    // instruction set is let be.
    d = real;
    facet_fragment_entry entries[3] = {{FACET_ISA_BASELINE, real.shader.fragments[0].fragment},
                                       {FACET_ISA_X86_64_V3, nullptr},
                                       {FACET_ISA_BASELINE, real.shader.fragments[0].fragment}};
    d.shader.fragments = entries;
    d.shader.fragment_count = 0;
    CHECK_THAT(d.why(), Catch::Contains("the shader has 0 fragment entries"));
    d.shader.fragment_count = 2;
    CHECK_THAT(d.why(), Catch::Contains("fragment entry 1 has no function"));
    entries[1] = {FACET_ISA_BASELINE, real.shader.fragments[0].fragment};
    CHECK_THAT(d.why(), Catch::Contains("two fragment entries for instruction set 0"));
    entries[1].isa = 77;
    CHECK(d.why() == "accepted");
    // Needs this host cannot serve (yet) are refused, not silently unmet.
    for (uint32_t need : {1u << 12, 1u << 30}) {
        d = real;
        d.shader.needs |= need;
        CHECK_THAT(d.why(), Catch::Contains("needs inputs this host cannot provide"));
    }
    // A second UV set (ABI 2.1) names a varying of two components that is
    // not conditional, and comes with FACET_NEED_UV1.
    d = real;
    d.shader.second_uv = d.shader.varying_count + 1;
    d.shader.needs |= FACET_NEED_UV1;
    CHECK_THAT(d.why(), Catch::Contains("second_uv names no varying"));
    d.shader.second_uv = 1;
    d.shader.needs &= ~uint32_t(FACET_NEED_UV1);
    CHECK_THAT(d.why(), Catch::Contains("does not need FACET_NEED_UV1"));
    // A plugin built against ABI 2.0 has a shorter shader record: what lies
    // past it is never read.
    d.shader.struct_size = uint32_t(offsetof(facet_shader_desc, second_uv));
    d.plugin.abi_minor = 0;
    CHECK(d.why() == "accepted");
    // Neither a shader nor a pass.
    d = real;
    d.plugin.shader = nullptr;
    CHECK_THAT(d.why(), Catch::Contains("neither a shader nor a screen pass"));
    // A parameter whose offset wraps around the block is refused.
    facet_param_desc wrap = sdk::float1("x", 0, 0.0f);
    wrap.offset = 0xFFFFFFFCu;
    d = real;
    d.plugin.schema = {1, 16, &wrap, nullptr};
    CHECK_THAT(d.why(), Catch::Contains("lies outside the parameter block"));
}

TEST_CASE("conditional varyings: read only under their parameter, and checked at load",
          "[plugin]") {
    PluginRegistry registry;
    const std::shared_ptr<ShaderPlugin> phong = registry.get("phong");
    // phong's last three varyings (its Gouraud terms and its tangent, 10
    // floats) serve only its normal map or its Gouraud mode (ABI 2.1's
    // second condition).
    const facet_shader_desc& shader = phong->shader_desc();
    const facet_schema& schema = phong->schema();
    REQUIRE(shader.conditional_varyings == 3);
    REQUIRE(std::string(schema.params[shader.varyings_condition].name) == "normal_texture");
    REQUIRE(shader.varyings_condition_also > 0);
    REQUIRE(std::string(schema.params[shader.varyings_condition_also - 1].name) == "gouraud");
    for (const char* name : {"normal_texture", "gouraud"}) {
        INFO(name);
        ParamBlock block;
        CHECK(phong->read_floats(block.bytes) == phong->varying_floats() - 10);
        const int32_t set = 1;
        std::memcpy(block.bytes + phong->find_param(name)->offset, &set, sizeof set);
        CHECK(phong->read_floats(block.bytes) == phong->varying_floats());
    }

    const DescCopy real(&phong->desc());
    DescCopy d = real;
    CHECK(d.why() == "accepted");
    d.shader.conditional_varyings = d.shader.varying_count + 1;
    CHECK_THAT(d.why(), Catch::Contains("conditional varyings of"));
    d = real;
    d.shader.varyings_condition = uint32_t(phong->find_param("diffuse") - schema.params);
    CHECK_THAT(d.why(), Catch::Contains("not a texture or bool parameter"));
    d = real;
    d.shader.varyings_condition = schema.param_count;
    CHECK_THAT(d.why(), Catch::Contains("not a texture or bool parameter"));
    d = real;
    d.shader.varyings_condition_also = uint32_t(phong->find_param("shininess") - schema.params) + 1;
    CHECK_THAT(d.why(), Catch::Contains("second condition is not a texture or bool parameter"));
    // With the UV conditional too, base_texture would be sampled at zeros.
    d = real;
    d.shader.conditional_varyings = 4;
    CHECK_THAT(d.why(), Catch::Contains("texture 'base_texture' reads its UV from a conditional"));
}

TEST_CASE("a parameter schema that overlaps, has bad ranges or runs past its table is refused",
          "[plugin]") {
    DescCopy d(color_shader());
    facet_param_desc params[2] = {sdk::float1("a", 0, 0.5f, 0.0f, 1.0f),
                                  sdk::float1("b", 4, 0.5f, 0.0f, 1.0f)};
    d.plugin.schema = {2, 16, params, nullptr};
    const auto why = [&] { return d.why(); };
    CHECK(why() == "accepted");
    params[1].type = FACET_PARAM_VEC2;
    params[1].offset = 0;  // on top of "a"
    CHECK_THAT(why(), Catch::Contains("parameter 1 ('b') overlaps parameter 0 ('a')"));
    params[1] = sdk::float1("b", 4, 0.5f, 2.0f, 1.0f);
    CHECK_THAT(why(), Catch::Contains("min above max, or NaN"));
    params[1] = sdk::float1("b", 4, 0.5f, 0.0f, std::nanf(""));
    CHECK_THAT(why(), Catch::Contains("min above max, or NaN"));
    params[1] = sdk::float1("b", 4, 3.0f, 0.0f, 1.0f);
    CHECK_THAT(why(), Catch::Contains("default 3.0") && Catch::Contains("outside its range"));

    // A plugin whose param_count runs past its table: refused before the
    // host reads a name that is not there.
    const test::TempDir folder("params");
    REQUIRE(test::compile_plugin(folder.path / "liar.so", "liar", "-DWITH_GAIN -DTOO_MANY_PARAMS"));
    std::string message;
    CHECK(load_error(folder.path / "liar.so", &message) == ErrorCode::plugin_invalid);
    CHECK_THAT(message, Catch::Contains("param_count (24) runs past the end of its table"));
}

TEST_CASE("a plugin shadowed by another of the same name is named in a warning", "[plugin]") {
    const test::TempDir folder("shadowed");
    for (const char* dir : {"first", "second"}) {
        fs::create_directories(folder.path / dir);
        REQUIRE(test::compile_plugin(folder.path / dir / "twin.so", "twin", ""));
    }
    PluginRegistry registry({folder.path / "first", folder.path / "second"});
    const test::LogCapture log;
    CHECK(registry.get("twin")->origin() == (folder.path / "first" / "twin.so").string());
    CHECK_THAT(log.text(), Catch::Contains("shader 'twin': " + (folder.path / "first/twin.so").string() +
                                           " is used; " + (folder.path / "second/twin.so").string() +
                                           ", of the same name and later on the search path, is not"));
    CHECK(registry.shadowed("twin") == std::vector<fs::path>{folder.path / "second" / "twin.so"});
}

TEST_CASE("the registry finds plugins on its search path, by name", "[plugin]") {
    PluginRegistry registry({kTestPlugins});
    CHECK(registry.get("c_plugin")->name() == "c_plugin");
    CHECK(registry.get("c_plugin") == registry.get("c_plugin"));  // loaded once
    try {
        registry.get("no_such_shader");
        FAIL("unknown shader accepted");
    } catch (const Error& e) {
        CHECK(e.code() == ErrorCode::unknown_shader);
        CHECK_THAT(e.what(), Catch::Contains(kTestPlugins.string()));
    }
    // The file name and the shader's own name must agree.
    const test::TempDir folder("rename");
    const fs::path& dir = folder.path;
    fs::copy_file(kTestPlugins / "c_plugin.so", dir / "renamed.so");
    registry.add_scene_path(dir);
    CHECK_THROWS_AS(registry.get("renamed"), Error);
}

TEST_CASE("the default scene renders through the unlit plugin .so", "[plugin][scene]") {
    PluginRegistry registry;
    const Scene scene = load_scene(default_scene_path(), registry);
    REQUIRE_FALSE(scene.objects.empty());
    const ShaderPlugin& unlit = *scene.objects[0].material->plugin;
    CHECK(unlit.name() == "unlit");
    CHECK(fs::path(unlit.origin()).filename() == "unlit.so");
    Framebuffer fb;
    const FrameStats stats = Renderer().render(scene, fb);
    CHECK(stats.triangles_rasterized > 1000);
    // The cow is there: many pixels differ from the clear colour.
    int drawn = 0;
    const std::vector<uint8_t> px = fb.resolve_srgb8();
    uint8_t clear[4];
    encode_pixel(ColorFormat::srgb8, scene.settings.clear_color, clear);
    for (int i = 0; i < fb.width() * fb.height(); ++i)
        drawn += std::memcmp(&px[4 * size_t(i)], clear, 4) != 0;
    CHECK(drawn > fb.width() * fb.height() / 20);
}

TEST_CASE("FACET_PLUGIN_PATH is searched after the built-in plugins' folders", "[plugin]") {
    const std::string dir = FACET_TEST_PLUGIN_DIR;
    setenv("FACET_PLUGIN_PATH", ("/nonexistent:" + dir).c_str(), 1);
    PluginRegistry registry;
    unsetenv("FACET_PLUGIN_PATH");
    const auto path = registry.search_path();
    // Found beside the test program (tests/../plugins), not baked in: then
    // where an install puts them, then the variable's two folders.
    REQUIRE(path.size() == 4);
    // (Compared as files: the program's path has its symbolic links resolved.)
    CHECK(std::filesystem::equivalent(path[0], FACET_BUILD_PLUGIN_DIR));
    CHECK(path[1] == path[0].parent_path() / "lib/facet/plugins");
    CHECK(path[3].string() == dir);
    CHECK(registry.get("c_plugin")->name() == "c_plugin");
    CHECK(std::filesystem::equivalent(registry.get("unlit")->origin(),
                                      std::string(FACET_BUILD_PLUGIN_DIR) + "/unlit.so"));
}

TEST_CASE("a 2.0 host, which does not know a second condition, leaves those varyings zero",
          "[plugin][abi]") {
    // phong's Gouraud terms are conditional varyings under its second
    // condition (ABI 2.1). A 2.0 host interpolates them under the first
    // alone: with gouraud and no normal map it leaves them out, and the SDK
    // must hand the fragment function zeros, not whatever the rows held.
    PluginRegistry registry;
    const std::shared_ptr<ShaderPlugin> phong = registry.get("phong");
    MaterialParam gouraud;
    gouraud.name = "gouraud";
    gouraud.kind = MaterialParam::Kind::boolean;
    gouraud.flag = true;
    TextureCache cache;
    const BoundParams bound = bind_params({gouraud}, *phong, "test", cache);
    constexpr int N = FACET_BLOCK_LANES;
    const uint32_t floats = phong->varying_floats();
    // Unconditional rows: a point in front of the camera facing it; the rest NaN.
    std::vector<float> varyings(size_t(floats) * N, std::nanf(""));
    const float unconditional[] = {0, 0, 0, 0, 0, 1, 0.5f, 0.5f};
    REQUIRE(phong->read_floats(bound.block->bytes) == floats);  // 2.1: all of them
    for (int k = 0; k < 8; ++k) std::fill_n(varyings.begin() + k * N, N, unconditional[k]);
    const auto colour = [&](uint16_t host_minor) {
        static const auto no_service = [](const char*, uint32_t) -> const void* { return nullptr; };
        const facet_host host = {FACET_ABI_MAJOR, host_minor, sizeof(facet_host), nullptr,
                                 +no_service};
        facet_draw d{};
        d.host = &host;
        d.params = bound.block->bytes;
        const glm::mat4 identity(1.0f);
        for (float* m : {d.model, d.view, d.projection, d.view_projection, d.model_view_projection,
                         d.normal_matrix})
            std::memcpy(m, &identity[0][0], sizeof(float) * 16);
        d.camera_position[2] = 5.0f, d.camera_position[3] = 1.0f;
        std::vector<float> depth(N, 0.5f), color(4 * N, -1.0f);
        facet_fragment_batch b{};
        b.mask = 0xFFFFu;
        b.front_facing = 1;
        b.varyings = varyings.data();
        b.depth = depth.data();
        b.color = color.data();
        phong->fragment_for(Isa::portable)(&d, &b);
        return glm::vec4(color[0], color[N], color[2 * N], color[3 * N]);
    };
    // A 2.1 host interpolated them: the NaN rows are what it gave.
    CHECK(std::isnan(colour(1).r));
    // A 2.0 host did not: zeros, so emission + ambient alone.
    CHECK(colour(0) == glm::vec4(0.02f, 0.02f, 0.02f, 1.0f));
}
