// Math conventions, framebuffer output, the guard band, what the core hands a
// shader, plugin search, and the unlit plugin against its formula.
#include "support.hpp"

#include <facet/command_line.hpp>
#include <facet/error.hpp>
#include <facet/math.hpp>
#include <facet/plugin.hpp>

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

using namespace facet;
using namespace facet::test;

namespace {

float depth_of(const glm::mat4& proj, float view_z) {
    const glm::vec4 c = proj * glm::vec4(0.0f, 0.0f, view_z, 1.0f);
    return c.z / c.w;
}

}  // namespace

TEST_CASE("projections map near and far to the configured depth range", "[math]") {
    const glm::mat4 rev = perspective(glm::radians(60.0f), 1.5f, 0.5f, 40.0f, true);
    CHECK(depth_of(rev, -0.5f) == Approx(1.0f));
    CHECK(depth_of(rev, -40.0f) == Approx(0.0f).margin(1e-6));
    const glm::mat4 fwd = perspective(glm::radians(60.0f), 1.5f, 0.5f, 40.0f, false);
    CHECK(depth_of(fwd, -0.5f) == Approx(0.0f).margin(1e-6));
    CHECK(depth_of(fwd, -40.0f) == Approx(1.0f));
    const glm::mat4 ortho = orthographic(4.0f, 2.0f, 1.0f, 11.0f, true);
    CHECK(depth_of(ortho, -1.0f) == Approx(1.0f));
    CHECK(depth_of(ortho, -6.0f) == Approx(0.5f));
    CHECK((ortho * glm::vec4(4.0f, 2.0f, -3.0f, 1.0f)).x == Approx(1.0f));
    // Field of view: a point on the top edge of the frustum lands at y = 1.
    const float t = std::tan(glm::radians(30.0f));
    const glm::vec4 top = rev * glm::vec4(0.0f, 2.0f * t, -2.0f, 1.0f);
    CHECK(top.y / top.w == Approx(1.0f));
}

TEST_CASE("look_at and model matrices follow the conventions", "[math]") {
    const glm::mat4 view = look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
    CHECK((view * glm::vec4(0, 0, 0, 1)).z == Approx(-5.0f));   // target straight ahead
    CHECK((view * glm::vec4(1, 0, 0, 1)).x == Approx(1.0f));    // +X to the right
    Transform tr;
    tr.translation = {1, 2, 3};
    tr.rotation = euler_degrees({0, 90, 0});
    tr.scale = {2, 1, 1};
    const glm::vec4 p = tr.matrix() * glm::vec4(1, 0, 0, 1);   // scale, then rotate, then move
    CHECK(p.x == Approx(1.0f).margin(1e-6));
    CHECK(p.z == Approx(1.0f));
    // Normals stay perpendicular to surfaces under non-uniform scale.
    const glm::mat4 squash = glm::scale(glm::mat4(1.0f), glm::vec3(4, 1, 1));
    const glm::vec3 tangent = glm::vec3(squash * glm::vec4(1, -1, 0, 0));
    const glm::vec3 normal = normal_matrix(squash) * glm::vec3(1, 1, 0);
    CHECK(glm::dot(tangent, normal) == Approx(0.0f).margin(1e-6));
}

TEST_CASE("sRGB resolve matches the transfer function, and PNGs round-trip", "[framebuffer]") {
    for (int code = 0; code < 256; ++code) {
        const double encoded = code / 255.0;
        const double linear = encoded <= 0.04045 ? encoded / 12.92
                                                 : std::pow((encoded + 0.055) / 1.055, 2.4);
        REQUIRE(linear_to_srgb8(float(linear)) == code);
    }
    CHECK(linear_to_srgb8(-1.0f) == 0);
    CHECK(linear_to_srgb8(7.0f) == 255);
    // Against the transfer function in double precision, rounded: every
    // float in a dense sweep of 0..1 and on both sides of each code's edge.
    auto reference = [](float v) {
        const double l = v, e = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
        return int(std::floor(e * 255.0 + 0.5));
    };
    for (int i = 0; i <= 1 << 20; ++i) {
        const float v = float(i) / float(1 << 20);
        REQUIRE(int(linear_to_srgb8(v)) == reference(v));
    }
    for (int code = 1; code < 256; ++code) {
        const double e = (code - 0.5) / 255.0;
        const float edge = float(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
        for (float v = std::nextafter(edge, 0.0f), k = 0; k < 3; ++k, v = std::nextafter(v, 2.0f))
            REQUIRE(int(linear_to_srgb8(v)) == reference(v));
    }
    CHECK(linear_to_srgb8(std::nanf("")) == 0);

    Framebuffer fb(5, 3);
    fb.clear({0.2f, 0.5f, 1.0f, 0.5f}, 0.0f);
    fb.set_pixel(4, 2, {1.0f, 0.0f, 0.0f, 1.0f});
    const TempDir folder("png");
    const std::filesystem::path& dir = folder.path;
    fb.write_png(dir / "out.png");
    int w = 0, h = 0, n = 0;
    unsigned char* px = stbi_load((dir / "out.png").c_str(), &w, &h, &n, 4);
    REQUIRE(px);
    CHECK((w == 5 && h == 3));
    CHECK(int(px[0]) == linear_to_srgb8(0.2f));
    CHECK(int(px[3]) == 128);
    CHECK(int(px[(2 * 5 + 4) * 4]) == 255);
    stbi_image_free(px);
    CHECK_THROWS_AS(fb.write_png(dir / "no-such-dir" / "x.png"), Error);
    CHECK_THROWS_AS(fb.resize(0, 10), Error);
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
    facet_shader_desc desc = {FACET_ABI_MAJOR, FACET_ABI_MINOR, sizeof(facet_shader_desc),
                              "probe", "test", 0, 0, nullptr, 0, nullptr, 0,
                              probe_vertex, probe_fragment, nullptr, nullptr, 0};
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

    desc.needs = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_LIGHTS;
    desc.varying_count = 1;
    desc.varyings = &uv;
    Seen some = run();
    CHECK((some.normal && some.uv && !some.color));
    CHECK(some.varying_floats == 2);
    CHECK(some.lights == 1);
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

TEST_CASE("unlit.so computes vertex colour x base colour x texture", "[shader][unlit]") {
    PluginRegistry registry;
    auto unlit = registry.get("unlit");
    // A 2x2 texture, sampled with nearest filtering at texel centres.
    auto tex = std::make_shared<Texture>();
    tex->width = tex->height = 2;
    tex->texels = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {0.5f, 0.5f, 0.5f, 0.5f}};
    const TextureBinding bindings[1] = {{tex, Filter::nearest, Wrap::clamp}};
    struct Block {
        glm::vec4 base_color;
        int32_t base_texture;
    } params{{1.0f, 0.5f, 0.25f, 1.0f}, 1};
    const glm::vec4 vertex_color(0.5f, 1.0f, 1.0f, 1.0f);
    // A full-screen quad whose UVs run 0..1 across it.
    Mesh quad = make_mesh({{-1, -1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}, {-1, 1, 0.5f}},
                          {0, 1, 2, 0, 2, 3}, std::vector<glm::vec4>(4, vertex_color));
    quad.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    for (bool textured : {false, true}) {
        params.base_texture = textured;
        Framebuffer fb(8, 8);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(quad, *unlit);
        call.params = &params;
        call.textures = textured ? bindings : nullptr;
        call.texture_count = textured ? 1 : 0;
        FrameStats stats;
        Pipeline().draw(call, fb, stats);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const glm::vec4 texel = textured ? tex->texels[(y / 4) * 2 + x / 4] : glm::vec4(1);
                const glm::vec4 expected = vertex_color * params.base_color * texel;
                REQUIRE(glm::all(glm::equal(fb.pixel(x, y), expected)));
            }
    }
}

TEST_CASE("mipmaps: generated by box filter, down to 1x1", "[texture][mipmap]") {
    Texture t;
    t.width = 5;
    t.height = 2;
    for (int i = 0; i < 10; ++i) t.texels.push_back(glm::vec4(float(i)));
    generate_mipmaps(t);
    REQUIRE(t.levels() == 3);  // 5x2, 2x1, 1x1
    CHECK((t.mips[0].width == 2 && t.mips[0].height == 1));
    CHECK(t.mips[0].texels[0].r == Approx((0 + 1 + 5 + 6) / 4.0));
    CHECK(t.mips[1].texels[0].r == Approx(((0 + 1 + 5 + 6) / 4.0 + (2 + 3 + 7 + 8) / 4.0) / 2));
}

TEST_CASE("trilinear filtering picks the analytic level of detail at a grazing angle",
          "[texture][mipmap]") {
    // A 256x256 texture whose level k holds the value k, so what a pixel
    // samples is the level of detail the sampler chose (blended between
    // levels). The reference is the analytic LOD, log2 of the longer axis of
    // the UV footprint from the exact Jacobian of the plane's UV mapping.
    auto tex = std::make_shared<Texture>();
    tex->width = tex->height = 256;
    tex->texels.assign(256 * 256, glm::vec4(0.0f));
    generate_mipmaps(*tex);
    for (int k = 1; k < tex->levels(); ++k)
        for (glm::vec4& t : tex->mips[size_t(k - 1)].texels) t = glm::vec4(float(k));
    const TextureBinding binding{tex, Filter::trilinear, Wrap::repeat};

    // The plane y = 0, x in [-1, 1], z in [-40, 0], with uv = (x, -z / 2):
    // seen from just above, it recedes to a grazing angle.
    const int W = 128, H = 96;
    Mesh plane =
        make_mesh({{-1, 0, 0}, {1, 0, 0}, {1, 0, -40}, {-1, 0, -40}}, {0, 1, 2, 0, 2, 3});
    plane.uvs = {{-1, 0}, {1, 0}, {1, 20}, {-1, 20}};
    const glm::vec3 eye(0.0f, 0.25f, 1.0f);
    const glm::mat4 view = look_at(eye, {0.0f, 0.0f, -6.0f}, {0, 1, 0});
    const glm::mat4 proj = perspective(glm::radians(50.0f), float(W) / H, 0.05f, 100.0f, true);
    PluginRegistry registry;
    auto unlit = registry.get("unlit");
    struct {
        glm::vec4 base_color{1.0f};
        int32_t base_texture = 1;
    } params;
    Framebuffer fb(W, H);
    fb.clear(glm::vec4(-1.0f), 0.0f);
    DrawCall call = clip_space_call(plane, *unlit);
    call.view = view;
    call.projection = proj;
    call.params = &params;
    call.textures = &binding;
    call.texture_count = 1;
    FrameStats stats;
    Pipeline().draw(call, fb, stats);

    // uv at window point p (pixels), from the ray through it.
    const glm::dmat4 inv = glm::inverse(glm::dmat4(proj) * glm::dmat4(view));
    auto uv_at = [&](glm::dvec2 p) {
        const glm::dvec2 ndc(p.x / W * 2 - 1, 1 - p.y / H * 2);
        const glm::dvec4 a = inv * glm::dvec4(ndc, 0.0, 1.0);
        const glm::dvec3 far = glm::dvec3(a) / a.w, o(eye);
        const glm::dvec3 hit = o + (far - o) * (o.y / (o.y - far.y));
        return glm::dvec2(hit.x, -hit.z / 2);
    };
    double max_err = 0, min_lod = 99, max_lod = 0;
    for (int qy = 0; qy < H; qy += 2)
        for (int qx = 0; qx < W; qx += 2) {
            const float got = fb.pixel(qx, qy).r;
            if (got < 0.0f || fb.pixel(qx + 1, qy + 1).r < 0.0f) continue;  // not on the plane
            const glm::dvec2 c(qx + 1.0, qy + 1.0);  // centre of the 2x2 quad
            const double h = 1e-3;
            const glm::dvec2 ex(h, 0), ey(0, h);
            const glm::dvec2 dx = (uv_at(c + ex) - uv_at(c - ex)) / (2 * h);
            const glm::dvec2 dy = (uv_at(c + ey) - uv_at(c - ey)) / (2 * h);
            const double lod = std::log2(256.0 * std::max(glm::length(dx), glm::length(dy)));
            if (lod < 0.05 || lod > tex->levels() - 1.05) continue;  // clamped at either end
            max_err = std::max(max_err, std::abs(got - lod));
            min_lod = std::min(min_lod, lod);
            max_lod = std::max(max_lod, lod);
        }
    INFO("LOD range " << min_lod << " .. " << max_lod);
    INFO("max LOD error " << max_err);
    CHECK(max_lod - min_lod > 3.0);  // the plane really spans several levels
    CHECK(max_err < 0.05);
}

TEST_CASE("JPEG textures load through stb_image, decoded from sRGB", "[texture]") {
    // A flat sRGB colour (188, 64, 32), written as a JPEG at full quality.
    const TempDir folder("jpeg");
    const std::filesystem::path& dir = folder.path;
    std::vector<unsigned char> pixels;
    for (int i = 0; i < 64; ++i) pixels.insert(pixels.end(), {188, 64, 32});
    REQUIRE(stbi_write_jpg((dir / "flat.jpg").c_str(), 8, 8, 3, pixels.data(), 100));
    const auto tex = load_texture(dir / "flat.jpg", true);
    REQUIRE((tex->width == 8 && tex->height == 8));
    const glm::vec4 texel = tex->texels[27];
    CHECK(texel.r == Approx(srgb_to_linear(188 / 255.0f)).margin(0.01));
    CHECK(texel.g == Approx(srgb_to_linear(64 / 255.0f)).margin(0.01));
    CHECK(texel.b == Approx(srgb_to_linear(32 / 255.0f)).margin(0.01));
    CHECK(tex->levels() == 4);  // 8x8 down to 1x1
}

TEST_CASE("command-line sizes and cameras parse strictly", "[core][cli]") {
    CHECK(facet::parse_size("1280x720") == glm::ivec2(1280, 720));
    CHECK(facet::parse_size("64X48") == glm::ivec2(64, 48));
    for (const char* bad : {"", "1280", "1280x", "0x720", "12x34y", "x720", "20000x10", "-5x5"})
        CHECK_FALSE(facet::parse_size(bad));
    facet::Camera base;
    base.fov_y = 50.0f;
    const auto c = facet::parse_camera("1,2,3,0,0.5,-1", base);
    REQUIRE(c);
    CHECK(c->position == glm::vec3(1, 2, 3));
    CHECK(c->target == glm::vec3(0, 0.5f, -1));
    CHECK(c->fov_y == 50.0f);  // kept from the base
    CHECK(facet::parse_camera("1,2,3,0,0,0,30", base)->fov_y == 30.0f);
    for (const char* bad : {"1,2,3", "1,2,3,4,5,6,7,8", "1,2,3,1,2,3", "0,5,0,0,0,0",
                            "1,2,3,0,0,nan", "1,2,3,0,0,inf", "1,,3,0,0,0", "1,2,3,0,0,0,180",
                            "a,2,3,0,0,0"})
        CHECK_FALSE(facet::parse_camera(bad, base));
}
