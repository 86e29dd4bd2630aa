// facet-bench-environment: image-based lighting's cost and error.
//
//     facet-bench-environment [--scene FILE] [--size WxH] [--runs N]
//                             [--threads N] [--reference-samples N]
//
// On a scene lit by an environment (by default the demo,
// configs/scenes/environment.yaml), measured side by side in one run:
//   - prefilter: load_environment() of a 2048x1024 HDR (the scene's image,
//     resampled) at its own size, median of --runs, on --threads threads;
//   - frames: the scene with no environment (each pbr material's constant
//     ambient), lit by it with no sky, and lit with the sky behind, frames
//     interleaved, medians (the scene's post chain in all three);
//   - error: the lit frame (post chain off, rgba32f) against the Monte
//     Carlo reference in double precision (tests/reference/environment.hpp:
//     pbr's own BRDF against the scene's HDR image itself, unoccluded as
//     facet's lighting is; --reference-samples directions a pixel), and the
//     sky against the image along each pixel's ray. Errors are relative
//     RMSE of linear RGB, and RMSE in 8-bit sRGB codes at the scene's post
//     exposure (2^exposure, clamped).
//   - quality: the same error and frame time for level-0 sizes and sample
//     counts (the prefilter's settings), with the Pareto front marked.
#include "reference/environment.hpp"

#include <facet/command_line.hpp>
#include <facet/environment_map.hpp>
#include <facet/isa.hpp>
#include <facet/paths.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/tool.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

using namespace facet;

namespace {

constexpr double kPi = 3.14159265358979323846;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

struct Frames {
    double none = 0, lighting = 0, both = 0;
};

// The scene with no environment, lit by it, and lit with the sky: frames
// interleaved, medians.
Frames time_frames(const Scene& scene, int threads, int runs) {
    Scene none = scene, lighting = scene;
    none.environment = {};
    lighting.environment.settings.use = EnvironmentUse::lighting;
    Renderer renderer(threads);
    Framebuffer fb;
    std::vector<double> t[3];
    for (int i = 0; i < runs + 1; ++i) {  // the first round warms up
        const Scene* scenes[3] = {&none, &lighting, &scene};
        for (int k = 0; k < 3; ++k) {
            const double ms = renderer.render(*scenes[k], fb).milliseconds;
            if (i > 0) t[k].push_back(ms);
        }
    }
    return {median(t[0]), median(t[1]), median(t[2])};
}

void print_frames(const Frames& f, int runs) {
    std::printf("frames (the scene's post chain in each), median of %d, interleaved:\n"
                "  no environment %.2f ms, lit by it %.2f ms (x%.2f), lit with the sky %.2f ms (x%.2f)\n",
                runs, f.none, f.lighting, f.lighting / f.none, f.both, f.both / f.none);
}

// The scene's image resampled to 2048 x 1024, written to `file`.
void write_2048(const reference::EnvironmentImage& image, const std::filesystem::path& file) {
    const int w = 2048, h = 1024;
    std::vector<float> rgb;
    rgb.reserve(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double phi = ((x + 0.5) / w - 0.5) * 2 * kPi, theta = (y + 0.5) / h * kPi;
            const glm::dvec3 d(std::sin(theta) * std::sin(phi), std::cos(theta),
                               -std::sin(theta) * std::cos(phi));
            const glm::dvec3 c = image.radiance(d);
            rgb.insert(rgb.end(), {float(c.x), float(c.y), float(c.z)});
        }
    if (!stbi_write_hdr(file.string().c_str(), w, h, 3, rgb.data()))
        throw std::runtime_error("cannot write " + file.string());
}

double time_prefilter(const EnvironmentSettings& s, int threads, int runs) {
    std::vector<double> t;
    for (int i = 0; i < runs; ++i) {
        const auto start = std::chrono::steady_clock::now();
        const auto maps = load_environment(s, threads);  // dropped before the next: no cache
        t.push_back(ms_since(start));
    }
    return median(t);
}

// The lit frame, post chain off, in floats.
Framebuffer lit_frame(Scene scene, int threads) {
    scene.settings.post = false;
    scene.settings.color_format = ColorFormat::rgba32f;
    scene.environment.settings.use = EnvironmentUse::both;
    Framebuffer fb;
    Renderer(threads).render(scene, fb);
    return fb;
}

void quality_sweep(Scene scene, const reference::EnvironmentTruth& ref, double exposure, int threads) {
    struct Row {
        int size, samples;
        double prefilter, error, codes;
        bool front = true;
    };
    std::vector<Row> rows;
    for (int size : {32, 64, 128, 256, 512})
        for (int samples : {16, 64, 256}) {
            EnvironmentSettings s = scene.environment.settings;
            s.size = size;
            s.samples = samples;
            scene.environment.settings = s;
            scene.environment.maps.reset();
            const auto start = std::chrono::steady_clock::now();
            scene.environment.maps = load_environment(s, threads);
            const double prefilter = ms_since(start);
            const reference::EnvironmentError e = reference::environment_error(lit_frame(scene, threads), ref, exposure);
            rows.push_back({size, samples, prefilter, e.surface_relative, e.surface_codes});
        }
    for (Row& a : rows)
        for (const Row& b : rows)
            if (b.prefilter <= a.prefilter && b.error <= a.error &&
                (b.prefilter < a.prefilter || b.error < a.error))
                a.front = false;
    std::printf("\nquality: level 0's size and GGX samples a texel (the frame's time does not "
                "depend on them)\n%6s %8s %14s %14s %12s %7s\n", "size", "samples",
                "prefilter ms", "surface RMSE", "sRGB codes", "front");
    for (const Row& r : rows)
        std::printf("%6d %8d %14.1f %13.2f%% %12.2f %7s\n", r.size, r.samples, r.prefilter,
                    100 * r.error, r.codes, r.front ? "*" : "");
}

double post_exposure(const Scene& scene) {
    for (const PostPass& p : scene.post)
        if (p.name == "tonemap")
            for (const MaterialParam& m : p.params)
                if (m.name == "exposure" && !m.numbers.empty()) return m.numbers[0];
    return 0.0;
}

}  // namespace

int main(int argc, char** argv) {
    // Prefilters are timed, not read from where an earlier run kept them.
    setenv("FACET_CACHE_DIR", "off", 1);
    int runs = 7, threads = 2, samples = 256;
    bool frames_only = false;
    std::string size = "960x540", scene_file = (data_dir() / "configs" / "scenes" / "environment.yaml").string();
    CLI::App app{"Image-based lighting: prefilter time, frame cost, and error against Monte Carlo.",
                 "facet-bench-environment"};
    app.add_option("--scene", scene_file, "a scene with an environment and pbr materials")
        ->capture_default_str();
    app.add_option("--size", size, "image size WxH")->capture_default_str();
    app.add_option("--runs", runs, "frames or prefilters per timing (median)")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--threads", threads, "threads, counting the caller")
        ->check(CLI::Range(1, 256))->capture_default_str();
    app.add_option("--reference-samples", samples, "Monte Carlo directions per pixel")
        ->check(CLI::Range(2, 1 << 20))->capture_default_str();
    app.add_flag("--frames-only", frames_only, "time the frames only: no prefilter, reference or sweep");
    Verbosity verbosity;
    add_common_options(app, verbosity);
    if (const std::optional<int> status = parse_command_line(app, argc, argv)) return *status;
    start_logging(verbosity, spdlog::level::warn);
    const std::optional<glm::ivec2> wh = parse_size(size);
    if (!wh) {
        std::fprintf(stderr, "--size: expected WxH, got '%s'\n", size.c_str());
        return 2;
    }
    PluginRegistry registry;
    Scene scene = load_scene(scene_file, registry);
    if (!scene.environment || scene.environment.settings.files.size() != 1) {
        std::fprintf(stderr, "%s: needs an environment of one equirectangular image\n", scene_file.c_str());
        return 2;
    }
    scene.settings.width = wh->x, scene.settings.height = wh->y;
    const reference::EnvironmentImage image(scene.environment.settings.files[0]);
    std::printf("facet-bench-environment: %s, %dx%d, %d threads, %s path on %s\n", scene_file.c_str(),
                wh->x, wh->y, threads, std::string(isa_name(default_isa())).c_str(), cpu_name().c_str());
    std::printf("environment %s: %dx%d, %d levels from %u a side, %d samples\n",
                scene.environment.settings.files[0].string().c_str(), image.width, image.height,
                scene.environment.maps->levels, scene.environment.maps->size[0],
                scene.environment.settings.samples);

    if (frames_only) {
        print_frames(time_frames(scene, threads, runs), runs);
        return 0;
    }
    const std::filesystem::path big = std::filesystem::temp_directory_path() / "facet-bench-2048.hdr";
    write_2048(image, big);
    EnvironmentSettings s2048 = scene.environment.settings;
    s2048.files = {big};
    s2048.size = 0;
    const double prefilter = time_prefilter(s2048, threads, runs);
    std::filesystem::remove(big);
    std::printf("prefilter of a 2048x1024 HDR (its own size, 512): median %.1f ms\n", prefilter);

    print_frames(time_frames(scene, threads, runs), runs);

    const double exposure = post_exposure(scene);
    const auto start = std::chrono::steady_clock::now();
    const reference::EnvironmentTruth ref = reference::environment_truth(scene, image, samples, threads);
    const reference::EnvironmentError e = reference::environment_error(lit_frame(scene, threads), ref, exposure);
    std::printf("error against Monte Carlo (%d directions a pixel, double; its own noise %.2f%%; %.1f s):\n"
                "  surfaces: RMSE %.2f%% of the radiance, %.2f sRGB codes at exposure %g (%d pixels)\n"
                "  sky:      RMSE %.2f%% of the radiance, %.2f sRGB codes (%d pixels)\n",
                samples, 100 * ref.noise, ms_since(start) / 1000, 100 * e.surface_relative,
                e.surface_codes, exposure, e.surface_pixels, 100 * e.sky_relative, e.sky_codes,
                e.sky_pixels);
    std::printf("  by object:");
    for (size_t o = 0; o < e.object_relative.size(); ++o)
        if (e.object_relative[o] > 0.0)
            std::printf("%s %s %.1f%%", o ? "," : "", scene.objects[o].name.c_str(), 100 * e.object_relative[o]);
    std::printf("\n");
    quality_sweep(scene, ref, exposure, threads);
    return 0;
}
