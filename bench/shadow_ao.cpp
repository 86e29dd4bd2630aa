// facet-bench-shadow-ao: shadow-map and SSAO error against the exact ray
// caster, with the time each pass takes, on the shadow and ao demo scenes.
//
//     facet-bench-shadow-ao [--size WxH] [--runs N] [--rays N]
//
// Shadows: every object gets a white, unlit-by-ambient `shadow` material and
// each shadow-casting light is rendered alone, with and without its shadow
// map; their ratio is facet's visibility of that light, compared per pixel
// with the ray caster's hard shadow (0 or 1). AO: every object gets an
// `ao` material showing only ambient visibility (radius and samples from
// the demo's ao material), compared with ray-traced AO at the same surface
// point, with the AO computed at every pixel and at half resolution. The
// showcase scene's three lights (directional, spot, and a point light's cube
// map) are measured the same way through a diffuse-only `phong`, the
// visibility every lit shader receives (facet::sdk::Receiving), and its AO
// through phong's ambient term. Image-based lighting: the environment
// demo's pbr spheres and sky against the Monte Carlo reference of
// reference/environment.hpp, its error relative to the radiance. Errors
// are over pixels where both see the same object. Single thread; times are
// medians over --runs frames, each drawing every shadow map it needs.
#include "reference/environment.hpp"
#include "reference/raycast.hpp"

#include <facet/command_line.hpp>
#include <facet/material.hpp>
#include <facet/paths.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/tool.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

using namespace facet;

namespace {

struct Error {
    double rmse = 0, max = 0;
    int pixels = 0;
};

struct Accumulator {
    double sq = 0, max = 0;
    int n = 0;
    void add(double e) {
        sq += e * e;
        max = std::max(max, std::abs(e));
        ++n;
    }
    Error result() const { return {n ? std::sqrt(sq / n) : 0.0, max, n}; }
};

MaterialParam number(const std::string& name, std::vector<double> values) {
    MaterialParam p;
    p.name = name;
    p.kind = values.size() == 1 ? MaterialParam::Kind::number : MaterialParam::Kind::vector;
    p.is_integer = values.size() == 1 && values[0] == std::floor(values[0]);
    p.numbers = std::move(values);
    return p;
}

// Gives every object one material: `shader` with `params`.
void override_materials(Scene& scene, PluginRegistry& registry, const std::string& shader,
                        std::vector<MaterialParam> params) {
    auto m = std::make_shared<Material>();
    m->source = "facet-bench";
    m->shader = shader;
    m->params = std::move(params);
    TextureCache cache;
    bind(*m, registry.get(shader), cache);
    for (Object& o : scene.objects) o.use_material(m);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Timed {
    Framebuffer image;
    double shadow = 0, prepass = 0, ao = 0, main = 0, total = 0;
};

Timed render(const Scene& scene, int runs) {
    Renderer renderer(1);  // the table says one thread: keep it so
    Timed t;
    std::vector<double> shadow, prepass, ao, main, total;
    for (int i = 0; i < runs; ++i) {
        renderer.forget_shadow_maps();  // the time to draw them, not to keep them
        const FrameStats s = renderer.render(scene, t.image);
        shadow.push_back(s.ms_shadow);
        prepass.push_back(s.ms_prepass);
        ao.push_back(s.ms_ao);
        main.push_back(s.ms_main);
        total.push_back(s.milliseconds);
    }
    t.shadow = median(shadow);
    t.prepass = median(prepass);
    t.ao = median(ao);
    t.main = median(main);
    t.total = median(total);
    return t;
}


Error shadow_error(Scene scene, size_t light, int runs, double& ms_shadow) {
    const std::vector<Light> all = scene.lights;
    scene.lights = {all[light]};
    const Timed shadowed = render(scene, runs);
    scene.lights[0].casts_shadow = false;
    const Timed open = render(scene, 1);
    ms_shadow = shadowed.shadow;
    const reference::RayCaster rc(scene);
    Accumulator acc;
    for (int y = 0; y < shadowed.image.height(); ++y)
        for (int x = 0; x < shadowed.image.width(); ++x) {
            const float lit = open.image.pixel(x, y).r;
            const auto hit = rc.camera_hit(scene, x + 0.5, y + 0.5);
            if (lit < 0.01f || !hit) continue;
            const double facet = shadowed.image.pixel(x, y).r / lit;
            acc.add(facet - (rc.lit(scene.lights[0], hit->point, hit->normal) ? 1.0 : 0.0));
        }
    return acc.result();
}

Error ao_error(const Scene& scene, const Timed& t, double radius, int rays) {
    const reference::RayCaster rc(scene);
    Accumulator acc;
    for (int y = 0; y < t.image.height(); ++y)
        for (int x = 0; x < t.image.width(); ++x)
            if (const auto hit = rc.camera_hit(scene, x + 0.5, y + 0.5))
                acc.add(t.image.pixel(x, y).r -
                        rc.ambient_visibility(hit->point, hit->normal, radius, rays));
    return acc.result();
}

void row(const std::string& pass, double ms, const Error& e) {
    if (e.pixels == 0) {
        std::printf("%-44s %10.2f %10s %10s %10s\n", pass.c_str(), ms, "-", "-", "-");
        return;
    }
    std::printf("%-44s %10.2f %10.4f %10.4f %10d\n", pass.c_str(), ms, e.rmse, e.max, e.pixels);
}

const char* light_name(LightType t) {
    switch (t) {
    case LightType::directional: return "directional";
    case LightType::point: return "point, cube";
    case LightType::spot: return "spot";
    }
    return "?";
}

// A row for each shadow-casting light of `scene`.
void shadow_rows(const Scene& scene, const std::string& label, int runs) {
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        if (!l.casts_shadow) continue;
        double ms = 0;
        const Error e = shadow_error(scene, i, runs, ms);
        const int size = l.shadow_map_size ? l.shadow_map_size : scene.settings.shadow_map_size;
        row(label + ": " + light_name(l.type) + " " + std::to_string(size) + "^2", ms, e);
    }
}

}  // namespace

// Image-based lighting: the environment demo (pbr spheres lit by nothing
// but its HDR sky, and the sky behind them), post chain off, against the
// Monte Carlo reference (reference/environment.hpp, `rays` directions a
// pixel, on every hardware thread). Errors are relative to the reference's
// radiance (RMSE over pixels of the per-pixel RMS over RGB); the time is
// the whole frame's.
void environment_rows(const std::string& configs, PluginRegistry& registry, int width,
                      int height, int runs, int rays) {
    Scene scene = load_scene(configs + "environment.yaml", registry);
    scene.settings.width = width;
    scene.settings.height = height;
    scene.settings.color_format = ColorFormat::rgba32f;
    scene.settings.post = false;
    const Timed t = render(scene, runs);
    const reference::EnvironmentImage image(scene.environment.settings.files.at(0));
    const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
    const reference::EnvironmentTruth truth =
        reference::environment_truth(scene, image, rays, threads);
    const reference::EnvironmentError e = reference::environment_error(t.image, truth, 0.0);
    row("image-based lighting: pbr spheres (relative)", t.total,
        {e.surface_relative, e.surface_max, e.surface_pixels});
    row("image-based lighting: the sky (relative)", 0.0, {e.sky_relative, e.sky_max, e.sky_pixels});
}

int main(int argc, char** argv) {
    int runs = 5, rays = 256;
    std::string size = "320x180";
    CLI::App app{"Shadow-map and SSAO error against a ray caster, and their times.",
                 "facet-bench-shadow-ao"};
    app.add_option("--size", size, "image size WxH")->capture_default_str();
    app.add_option("--runs", runs, "frames per timing (median)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    app.add_option("--rays", rays, "reference AO rays, and environment directions, per pixel")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();
    Verbosity verbosity;
    add_common_options(app, verbosity);
    if (const std::optional<int> status = parse_command_line(app, argc, argv)) return *status;
    start_logging(verbosity, spdlog::level::warn);
    const std::optional<glm::ivec2> wh = parse_size(size);
    if (!wh) {
        std::fprintf(stderr, "--size: expected WxH with each side 1..%d, got '%s'\n",
                     Framebuffer::kMaxSize, size.c_str());
        return 2;
    }
    const int width = wh->x, height = wh->y;

    PluginRegistry registry;
    const std::string configs = (data_dir() / "configs" / "scenes").string() + "/";
    std::printf("facet-bench-shadow-ao: %dx%d, 1 thread, median of %d frames, %d AO rays\n",
                width, height, runs, rays);
    std::printf("%-44s %10s %10s %10s %10s\n", "pass", "ms", "RMSE", "max", "pixels");

    Scene shadow = load_scene(configs + "shadow.yaml", registry);
    shadow.settings.width = width;
    shadow.settings.height = height;
    shadow.settings.color_format = ColorFormat::rgba32f;  // light visibility is a float
    override_materials(shadow, registry, "shadow",
                       {number("base_color", {1, 1, 1, 1}), number("ambient", {0, 0, 0})});
    shadow_rows(shadow, "shadow", runs);

    Scene showcase = load_scene(configs + "showcase.yaml", registry);
    showcase.settings.width = width;
    showcase.settings.height = height;
    showcase.settings.color_format = ColorFormat::rgba32f;
    override_materials(showcase, registry, "phong",
                       {number("ambient", {0, 0, 0}), number("diffuse", {1, 1, 1}),
                        number("specular", {0, 0, 0}), number("emission", {0, 0, 0})});
    shadow_rows(showcase, "phong, showcase", runs);
    // Its AO, through phong's ambient term alone.
    override_materials(showcase, registry, "phong",
                       {number("ambient", {1, 1, 1}), number("diffuse", {0, 0, 0}),
                        number("specular", {0, 0, 0}), number("emission", {0, 0, 0}),
                        number("ambient_occlusion", {1})});
    showcase.lights.clear();
    {
        const Timed t = render(showcase, runs);
        row("phong, showcase: SSAO (" + std::to_string(showcase.settings.ao_samples) +
                " dirs, " + (showcase.settings.ao_half_resolution ? "half res)" : "full res)"),
            t.ao, ao_error(showcase, t, showcase.settings.ao_radius, rays));
    }

    Scene ao = load_scene(configs + "ao.yaml", registry);
    ao.settings.width = width;
    ao.settings.height = height;
    ao.settings.color_format = ColorFormat::rgba32f;
    const double radius = ao.settings.ao_radius;
    override_materials(ao, registry, "ao",
                       {number("base_color", {1, 1, 1, 1}), number("ambient", {1, 1, 1}),
                        number("strength", {1})});
    ao.lights.clear();
    for (bool half : {false, true}) {
        ao.settings.ao_half_resolution = half;
        const Timed t = render(ao, runs);
        const Error e = ao_error(ao, t, radius, rays);
        const char* resolution = half ? ", half res" : "";
        row(std::string("AO depth pre-pass") + resolution, t.prepass, {});
        const std::string name = "SSAO + blur (" + std::to_string(ao.settings.ao_samples) +
                                 " dirs, r=" + std::to_string(radius).substr(0, 4) + resolution +
                                 ")";
        row(name, t.ao, e);
        row(std::string("main pass (ao scene") + resolution + ")", t.main, {});
    }
    environment_rows(configs, registry, width, height, runs, rays);
    return 0;
}
