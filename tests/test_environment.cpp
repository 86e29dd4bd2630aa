// Environments (facet/environment_map.hpp, <facet/environment.hpp>): HDR
// images read and prefiltered, each map held to what it is defined as in
// double precision (a constant, a linear sky whose irradiance is known in
// closed form, the GGX convolution by quadrature, the split-sum integral);
// the SDK's lookup held to the scalar one; the scene block, its errors,
// hot reload, and the sky pass drawing only where nothing was drawn.
#include "support.hpp"

#include <facet/environment.hpp>
#include <facet/environment_map.hpp>
#include <facet/error.hpp>
#include <facet/hot_reload.hpp>
#include <facet/memory.hpp>
#include <facet/renderer.hpp>

#include <catch2/catch.hpp>
#include <spdlog/spdlog.h>

#include <stb/stb_image_write.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <thread>
#include <string>
#include <vector>

using namespace facet;
using facet::test::TempDir;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The unit direction of the centre of equirectangular pixel (x, y) of a
// w x h image (facet/texture.hpp, load_cube: the middle column looks
// along -Z, +X a quarter to its right; +Y the top row).
glm::dvec3 equirect_direction(double x, double y, int w, int h) {
    const double phi = ((x + 0.5) / w - 0.5) * 2.0 * kPi, theta = (y + 0.5) / h * kPi;
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

// A w x h Radiance HDR of radiance(direction), in `dir`.
std::filesystem::path hdr(const TempDir& dir, const std::string& name, int w, int h,
                          const std::function<glm::vec3(glm::dvec3)>& radiance) {
    std::vector<float> rgb;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec3 c = radiance(equirect_direction(x, y, w, h));
            rgb.insert(rgb.end(), {c.r, c.g, c.b});
        }
    const std::filesystem::path file = dir.path / name;
    REQUIRE(stbi_write_hdr(file.string().c_str(), w, h, 3, rgb.data()));
    return file;
}

std::shared_ptr<const EnvironmentMaps> maps_of(const std::filesystem::path& file, int size,
                                               int samples) {
    EnvironmentSettings s;
    s.files = {file};
    s.size = size;
    s.samples = samples;
    return load_environment(s, 2);
}

const glm::vec3 kDirections[] = {{1, 0, 0},     {0, 1, 0},         {0, 0, -1},
                                 {-0.6f, 0.8f, 0}, {0.3f, -0.5f, 0.81f}, {-0.57f, -0.57f, -0.57f}};

double relative(const glm::vec3& got, const glm::vec3& want) {
    return double(glm::length(got - want) / glm::length(want));
}

}  // namespace

TEST_CASE("an environment of one radiance is that radiance at every level and in irradiance",
          "[environment]") {
    const TempDir dir("env_constant");
    const glm::vec3 c(0.5f, 1.0f, 2.0f);
    const auto maps = maps_of(hdr(dir, "c.hdr", 64, 32, [&](glm::dvec3) { return c; }), 16, 16);
    REQUIRE(maps->levels == 2);  // 16, 8
    for (const glm::vec3& d : kDirections) {
        INFO("direction " << d.x << " " << d.y << " " << d.z);
        CHECK(relative(environment_irradiance(*maps, glm::normalize(d)), c) < 1e-3);
        for (int l = 0; l < maps->levels; ++l) CHECK(relative(sample_environment(*maps, l, d), c) < 1e-5);
    }
}

TEST_CASE("the irradiance of a linear sky is its closed form", "[environment]") {
    // L(d) = 1 + d.y (red), 1 + d.x (green), 1 - d.z (blue): irradiance / pi
    // at n is 1 + 2/3 n.y, and so on (the cosine lobe's first band).
    const TempDir dir("env_linear");
    const auto linear = [](glm::dvec3 d) { return glm::vec3(1 + d.y, 1 + d.x, 1 - d.z); };
    const auto maps = maps_of(hdr(dir, "l.hdr", 256, 128, linear), 64, 16);
    for (const glm::vec3& d : kDirections) {
        const glm::vec3 n = glm::normalize(d);
        const glm::vec3 want(1 + n.y * 2 / 3.0f, 1 + n.x * 2 / 3.0f, 1 - n.z * 2 / 3.0f);
        INFO("normal " << n.x << " " << n.y << " " << n.z);
        CHECK(relative(environment_irradiance(*maps, n), want) < 0.01);
    }
}

TEST_CASE("each prefiltered level is the GGX convolution of its roughness", "[environment]") {
    // A soft sun over a dim sky; the reference integrates it against the
    // lobe the split sum prefilters with (n = v = r: weight D(h) n.l over
    // the directions l) by quadrature, in double.
    const TempDir dir("env_ggx");
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.3, 0.8, -0.5));
    const auto sky = [&](glm::dvec3 d) {
        return glm::dvec3(0.1, 0.15, 0.3) + glm::dvec3(4.0, 3.5, 3.0) * std::exp(12.0 * (glm::dot(d, sun) - 1.0));
    };
    const auto maps = maps_of(hdr(dir, "s.hdr", 512, 256, [&](glm::dvec3 d) { return glm::vec3(sky(d)); }), 64,
                              256);
    REQUIRE(maps->levels == 4);  // 64, 32, 16, 8
    const auto reference = [&](glm::dvec3 n, double roughness) {
        const double a2 = std::pow(roughness, 4.0);
        glm::dvec3 sum(0.0);
        double weights = 0.0;
        const int h = 512, w = 1024;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const glm::dvec3 l = equirect_direction(x, y, w, h);
                const double n_l = glm::dot(n, l);
                if (n_l <= 0.0) continue;
                const double n_h = glm::dot(n, glm::normalize(n + l));
                const double k = n_h * n_h * (a2 - 1.0) + 1.0;
                const double weight = a2 / (k * k) * n_l * std::sin((y + 0.5) / h * kPi);
                sum += sky(l) * weight;
                weights += weight;
            }
        return glm::vec3(sum / weights);
    };
    for (int l = 1; l < maps->levels; ++l)
        for (const glm::dvec3 n : {sun, glm::normalize(sun + glm::dvec3(0.3, 0.0, 0.2)),
                                   glm::dvec3(0, -1, 0)}) {
            const double roughness = double(l) / (maps->levels - 1);
            INFO("level " << l << ", direction " << n.x << " " << n.y << " " << n.z);
            CHECK(relative(sample_environment(*maps, l, glm::vec3(n)), reference(n, roughness)) < 0.04);
        }
}

TEST_CASE("the split-sum table holds its integral", "[environment]") {
    const BrdfTable& t = brdf_table();
    REQUIRE(t.size >= 16);
    for (int j = 0; j < t.size; j += 5)
        for (int i = 0; i < t.size; i += 5) {
            const double n_v = double(i) / (t.size - 1), roughness = double(j) / (t.size - 1);
            const glm::dvec2 want = split_sum_brdf(n_v, roughness, 1 << 16);
            const float* cell = &t.cells[size_t(j * t.size + i) * 4];
            INFO("n.v " << n_v << ", roughness " << roughness);
            CHECK(std::abs(cell[0] - want.x) < 0.01);
            CHECK(std::abs(cell[1] - want.y) < 0.01);
        }
    // A mirror reflects all the light: A + B = 1 at roughness 0, and the
    // last cell of a row repeats itself as its own neighbour.
    const float* mirror = &t.cells[size_t(t.size - 1) * 4];
    CHECK(mirror[0] + mirror[1] == Approx(1.0f).margin(1e-4));
    CHECK(mirror[2] == mirror[0]);
}

TEST_CASE("the SDK's lookup reads the maps as the scalar one does", "[environment][sdk]") {
    const TempDir dir("env_sdk");
    const auto maps = maps_of(hdr(dir, "g.hdr", 128, 64,
                                  [](glm::dvec3 d) {
                                      return glm::vec3(0.5 + 0.5 * d.x, 0.5 + 0.5 * d.y,
                                                       0.5 + 0.5 * d.z * d.x);
                                  }),
                              16, 8);
    Environment env;
    env.settings.rotation = {10.0f, 70.0f, -20.0f};
    env.settings.intensity = 1.5f;
    env.maps = maps;
    const facet_environment record = env.record();
    const glm::mat3 to_env = env.to_environment();
    const sdk::Environment lookup(&record);
    for (const glm::vec3& d : kDirections) {
        const sdk::Vec3 lanes{sdk::splat(d.x), sdk::splat(d.y), sdk::splat(d.z)};
        const glm::vec3 local = to_env * d;
        for (int l = 0; l < maps->levels; ++l) {
            const sdk::Vec3 got = lookup.radiance(lanes, l);
            const glm::vec3 want = sample_environment(*maps, l, local) * 1.5f;
            CHECK(glm::length(glm::vec3(got.x[0], got.y[0], got.z[0]) - want) < 1e-5f);
        }
        const float rough = 0.3f;  // between levels 0 and 1 of 2
        const sdk::Vec3 mixed = lookup.specular(lanes, sdk::splat(rough));
        const glm::vec3 want = glm::mix(sample_environment(*maps, 0, local), sample_environment(*maps, 1, local),
                                        rough) * 1.5f;
        CHECK(glm::length(glm::vec3(mixed.x[0], mixed.y[0], mixed.z[0]) - want) < 1e-5f);
        const glm::vec3 n = glm::normalize(d);
        const sdk::Vec3 e = lookup.irradiance({sdk::splat(n.x), sdk::splat(n.y), sdk::splat(n.z)});
        const glm::vec3 e_want = environment_irradiance(*maps, to_env * n) * 1.5f;
        CHECK(glm::length(glm::vec3(e.x[0], e.y[0], e.z[0]) - e_want) < 1e-4f);
    }
    // The table, bilinear: at a cell's corner, the cell.
    const BrdfTable& t = brdf_table();
    const sdk::Vec2 ab = lookup.brdf(sdk::splat(1.0f), sdk::splat(0.0f));
    CHECK(ab.x[0] == Approx(t.cells[size_t(t.size - 1) * 4]).margin(1e-6));
    CHECK(ab.y[0] == Approx(t.cells[size_t(t.size - 1) * 4 + 1]).margin(1e-6));
    // NaN or no direction reads something finite, never outside the maps.
    const sdk::Vec3 nan{sdk::splat(NAN), sdk::splat(0.0f), sdk::splat(0.0f)};
    const sdk::Vec3 none{sdk::splat(0.0f), sdk::splat(0.0f), sdk::splat(0.0f)};
    CHECK(std::isfinite(lookup.radiance(nan, 0).x[0]));
    CHECK(std::isfinite(lookup.specular(none, sdk::splat(NAN)).x[0]));
    // A NaN beside a finite major component, an infinite one, a subnormal:
    // read somewhere on the maps, never outside them.
    const float inf = std::numeric_limits<float>::infinity();
    for (const glm::vec3 d : {glm::vec3(NAN, 1, 0), glm::vec3(inf, 0, 0), glm::vec3(inf, inf, 0),
                              glm::vec3(1e-39f, 0, 0), glm::vec3(-inf, 1, NAN)}) {
        const sdk::Vec3 lanes{sdk::splat(d.x), sdk::splat(d.y), sdk::splat(d.z)};
        CHECK(std::isfinite(lookup.radiance(lanes, 0).x[0]));
        CHECK(std::isfinite(lookup.specular(lanes, sdk::splat(0.5f)).y[0]));
    }
}

TEST_CASE("bad environment files are clear errors naming the file", "[environment][errors]") {
    const TempDir dir("env_bad");
    const auto good = hdr(dir, "good.hdr", 64, 32, [](glm::dvec3 d) { return glm::vec3(1 + float(d.y)); });
    const std::string bytes = test::read_file(good);
    const auto refused = [&](const std::string& name, const std::string& text, const std::string& says,
                             ErrorCode code = ErrorCode::texture_load_failed) {
        const auto file = dir.write(name, text);
        INFO(name);
        try {
            maps_of(file, 16, 4);
            FAIL("loaded");
        } catch (const Error& e) {
            CHECK(e.code() == code);
            CHECK(e.file() == file.string());
            CHECK_THAT(e.what(), Catch::Contains(says));
        }
    };
    refused("cut.hdr", bytes.substr(0, bytes.size() / 2), "ends");
    refused("text.hdr", "sky: blue\n", "not an image");
    refused("header.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8\n", "resolution");
    // Cut inside the resolution line: no pixel data at all.
    refused("no-data.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 512 +X 10", "ends");
    // Sizes that wrap 32 bits (stb_image would read 0 x 0).
    refused("wrap.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4294967296 +X 4294967296\n", "pixels");
    {  // within any machine's budget: the header's size is what is refused
        const test::Budget budget(uint64_t(64) << 30);
        refused("tall.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 20000000 +X 8\n", "2^24");
    }
    // A header of 900 million pixels: refused before anything that size is held.
    {
        const test::Budget budget(uint64_t(1) << 30);
        refused("huge.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 30000 +X 30000\n" + std::string(64, '\2'),
                "budget", ErrorCode::over_budget);
    }
    EnvironmentSettings five;
    five.files.assign(5, good);
    CHECK_THROWS_AS(load_environment(five), Error);
}

TEST_CASE("a scene's environment block: forms, ranges and errors at their line",
          "[environment][config]") {
    test::SceneDir s("env_scene");
    hdr(s.folder, "sky.hdr", 64, 32, [](glm::dvec3 d) { return glm::vec3(1 + float(d.y)); });
    const std::string head = "camera: {position: [0, 0, 3], target: [0, 0, 0]}\n";
    const Scene short_form = s.load(head + "environment: sky.hdr\n");
    REQUIRE(short_form.environment);
    CHECK(short_form.environment.settings.use == EnvironmentUse::both);
    const Scene full = s.load(head + "environment: {file: sky.hdr, rotation: [0, 90, 0], intensity: 2,\n"
                                     "  use: lighting, blur: 0.5, size: 16, samples: 8}\n");
    CHECK(full.environment.settings.intensity == 2.0f);
    CHECK(full.environment.maps->size[0] == 16);
    CHECK_FALSE(full.environment.settings.shows());
    CHECK_THAT(s.error(head + "environment: {file: sky.hdr, colour: 1}\n"), Catch::Contains("colour"));
    CHECK_THAT(s.error(head + "environment: {file: sky.hdr, use: sometimes}\n"),
               Catch::Contains("background"));
    CHECK_THAT(s.error(head + "environment: {file: sky.hdr, size: 100}\n"), Catch::Contains("power of two"));
    CHECK_THAT(s.error(head + "environment: {file: sky.hdr,\n  intensity: -1}\n"), Catch::Contains(":3:"));
    CHECK_THAT(s.error(head + "environment: missing.hdr\n"), Catch::Contains("missing.hdr"));
    CHECK_THAT(s.error(head + "environment: {faces: [a, b]}\n"), Catch::Contains("six"));
}

TEST_CASE("the sky fills what nothing covers, each sample on its own", "[environment][sky]") {
    test::SceneDir s("env_sky");
    hdr(s.folder, "sky.hdr", 128, 64, [](glm::dvec3 d) {
        return glm::vec3(0.2f + 0.3f * float(d.y + 1), 0.4f, 0.3f + 0.2f * float(d.x + 1));
    });
    std::filesystem::copy_file(std::string(FACET_SOURCE_DIR) + "/assets/sphere/sphere.obj",
                               s.dir / "sphere.obj");
    const std::string scene = "camera: {position: [0, 0.5, 3], target: [0, 0, 0], fov_y: 50}\n"
                              "render: {size: [96, 64], clear_color: [0, 0, 0, 1], msaa: MSAA}\n"
                              "objects: [{mesh: sphere.obj, material: {shader: pbr}}]\n"
                              "environment: {file: sky.hdr, size: 16, samples: 8, use: USE}\n";
    const auto with = [&](const std::string& use, int msaa) {
        std::string text = scene;
        text.replace(text.find("USE"), 3, use);
        text.replace(text.find("MSAA"), 4, std::to_string(msaa));
        return s.load(text);
    };
    for (int msaa : {1, 4}) {
        INFO("msaa " << msaa);
        const Scene lit = with("lighting", msaa), both = with("both", msaa);
        Framebuffer a, b;
        Renderer renderer(2);
        renderer.render(lit, a);
        renderer.render(both, b);
        const glm::mat4 view = both.camera.view();
        const glm::mat4 to_world = glm::inverse(both.camera.projection(96.0f / 64.0f, both.settings.reversed_z) * view);
        int sky = 0, covered = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 96; ++x) {
                const bool background = a.pixel(x, y) == glm::vec4(0, 0, 0, 1);
                if (!background) {  // geometry: the same with or without the sky
                    if (msaa == 1) CHECK(a.pixel(x, y) == b.pixel(x, y));
                    ++covered;
                    continue;
                }
                ++sky;
                const glm::vec4 far = to_world * glm::vec4(2.0f * (x + 0.5f) / 96 - 1, 1 - 2.0f * (y + 0.5f) / 64, 0.5f, 1);
                const glm::vec3 d = glm::vec3(far) / far.w - both.camera.position;
                const glm::vec3 want = sample_environment(*both.environment.maps, 0, d);
                const glm::vec4 got = b.pixel(x, y);
                CHECK(std::abs(got.r - want.r) < 0.01f);
                CHECK(std::abs(got.b - want.b) < 0.01f);
            }
        CHECK(sky > 1000);
        CHECK(covered > 500);
    }
}

TEST_CASE("an opaque part that writes no depth is drawn over the sky", "[environment][sky]") {
    test::SceneDir s("env_no_depth");
    hdr(s.folder, "sky.hdr", 32, 16, [](glm::dvec3) { return glm::vec3(0.0f, 0.0f, 1.0f); });
    std::filesystem::copy_file(std::string(FACET_SOURCE_DIR) + "/assets/sphere/sphere.obj",
                               s.dir / "sphere.obj");
    const Scene scene = s.load(
        "camera: {position: [0, 0, 3], target: [0, 0, 0], fov_y: 50}\n"
        "render: {size: [32, 32], color_format: rgba32f}\n"
        "objects: [{mesh: sphere.obj, material: {shader: unlit, depth_write: false,\n"
        "                                        params: {base_color: [1, 0, 0, 1]}}}]\n"
        "environment: {file: sky.hdr, size: 8, samples: 4}\n");
    Framebuffer fb;
    Renderer(2).render(scene, fb);
    CHECK(fb.pixel(16, 16) == glm::vec4(1, 0, 0, 1));  // the sphere, not the sky
    CHECK(fb.pixel(0, 0).b > 0.9f);                    // the sky around it
}

TEST_CASE("a changed environment file is prefiltered again; a bad one keeps the last good",
          "[environment][reload]") {
    test::SceneDir s("env_reload");
    const auto file = hdr(s.folder, "sky.hdr", 32, 16, [](glm::dvec3) { return glm::vec3(1.0f); });
    const std::filesystem::path scene_file = s.dir / "scene.yaml";
    test::write(scene_file, "camera: {position: [0, 0, 3], target: [0, 0, 0]}\n"
                            "environment: {file: sky.hdr, size: 8, samples: 4}\n");
    Scene scene = load_scene(scene_file, s.registry);
    HotReload::Options options;
    options.settle = std::chrono::milliseconds(30);
    HotReload reload(s.registry, scene, options);
    const auto irradiance = [&] { return environment_irradiance(*scene.environment.maps, {0, 1, 0}).g; };
    CHECK(irradiance() == Approx(1.0f).epsilon(1e-3));
    const auto wait_for = [&](bool want_refused) {
        for (int i = 0; i < 200; ++i) {
            reload.update();
            for (const ReloadEvent& e : reload.take_events())
                if (e.refused() == want_refused) return e.message;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return std::string("no event");
    };
    hdr(s.folder, "sky.hdr", 32, 16, [](glm::dvec3) { return glm::vec3(3.0f); });
    CHECK_THAT(wait_for(false), Catch::Contains("environment"));
    CHECK(irradiance() == Approx(3.0f).epsilon(1e-3));
    const std::string bytes = test::read_file(file);
    test::write(file, bytes.substr(0, bytes.size() - 40));
    CHECK_THAT(wait_for(true), Catch::Contains("keeping the previous environment"));
    CHECK(irradiance() == Approx(3.0f).epsilon(1e-3));
}

namespace {

// FACET_CACHE_DIR set to `dir` while it lives, and as it was after.
struct CacheDir {
    explicit CacheDir(const std::filesystem::path& dir) {
        if (const char* was = std::getenv("FACET_CACHE_DIR")) before = was;
        setenv("FACET_CACHE_DIR", dir.c_str(), 1);
    }
    ~CacheDir() { setenv("FACET_CACHE_DIR", before.c_str(), 1); }
    CacheDir(const CacheDir&) = delete;
    CacheDir& operator=(const CacheDir&) = delete;
    std::string before = "off";
};

// The files in `folder` whose name ends in `ending` (none when it does
// not exist).
std::vector<std::filesystem::path> files_in(const std::filesystem::path& folder,
                                            const std::string& ending) {
    std::vector<std::filesystem::path> out;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(folder, ec)) {
        const std::string name = e.path().filename().string();
        if (name.size() >= ending.size() && name.ends_with(ending)) out.push_back(e.path());
    }
    return out;
}

}  // namespace

TEST_CASE("prefiltered maps are kept on disk and read back the same; a bad file is made again",
          "[environment][cache]") {
    const TempDir dir("env_cache");
    const CacheDir cache(dir.path / "cache");
    const auto file = hdr(dir, "sky.hdr", 64, 32, [](glm::dvec3 d) {
        return glm::vec3(1.0 + d.y, 0.5 + 0.25 * d.x, 2.0 - d.z);
    });
    auto first = maps_of(file, 16, 16);
    const EnvironmentMaps want = *first;
    const std::filesystem::path folder = dir.path / "cache" / "environments";
    const auto kept = files_in(folder, ".env");
    REQUIRE(kept.size() == 1);
    CHECK(files_in(folder, ".part").empty());  // no part of one left over
    // Other settings or other bytes: another file.
    maps_of(file, 32, 16);
    maps_of(file, 16, 8);
    CHECK(files_in(folder, ".env").size() == 3);
    const auto same = [&](const EnvironmentMaps& got) {
        CHECK(got.levels == want.levels);
        CHECK(got.size == want.size);
        CHECK(got.offset == want.offset);
        CHECK(got.irradiance == want.irradiance);
        CHECK(got.texels == want.texels);
        CHECK(got.source == want.source);
    };
    // Held by a scene: the process's own, the same object.
    CHECK(maps_of(file, 16, 16) == first);

    // Held by none: read from the file, as the debug log says.
    first.reset();
    const auto level = spdlog::get_level();
    spdlog::set_level(spdlog::level::debug);
    {
        test::LogCapture log;
        same(*maps_of(file, 16, 16));
        CHECK(log.text().find("read from " + kept[0].string()) != std::string::npos);
    }
    spdlog::set_level(level);

    // Cut short, or one byte changed: named, made again, and kept whole.
    const auto size = std::filesystem::file_size(kept[0]);
    for (const char* harm : {"cut short", "its digest does not match"}) {
        INFO(harm);
        std::string bytes = test::read_file(kept[0]);
        if (std::string(harm) == "cut short")
            bytes.resize(bytes.size() / 2);
        else
            bytes[bytes.size() / 2] ^= 0x40;
        test::write(kept[0], bytes);
        test::LogCapture log;
        same(*maps_of(file, 16, 16));
        CHECK(log.text().find(kept[0].string() + ": " + harm) != std::string::npos);
        CHECK(std::filesystem::file_size(kept[0]) == size);
    }

    // A folder that cannot be made: said once, and the maps are made.
    test::write(dir.path / "a file", "not a folder");
    const CacheDir blocked(dir.path / "a file" / "cache");
    test::LogCapture log;
    same(*maps_of(file, 16, 16));
    same(*maps_of(file, 16, 16));
    const std::string text = log.text();
    const size_t said = text.find("cannot keep prefiltered environments in");
    CHECK(said != std::string::npos);
    CHECK(text.find("cannot keep prefiltered environments in", said + 1) == std::string::npos);
}
