#include "pareto.hpp"
#include "progress.hpp"

#include "reference/environment.hpp"
#include "reference/metrics.hpp"
#include "reference/render.hpp"

#include <facet/environment_map.hpp>
#include <facet/error.hpp>
#include <facet/material.hpp>
#include <facet/paths.hpp>
#include <facet/pipeline.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>

namespace facet::bench {

namespace {

namespace fs = std::filesystem;

// One point of a sweep: the knobs as set (-1: as the scene has it).
struct Setting {
    int msaa = -1;
    int filter = -1;  // Filter, as int
    int anisotropy = -1;  // Filter::anisotropic's most samples
    int subpixel_bits = -1;
    int shadow_map_size = -1;
    int pcf_kernel = -1;
    int ao_samples = -1;
    double ao_radius = -1.0;
    int ao_half = -1;    // render: ao_resolution half (1) or full (0)
    int per_pixel = -1;  // lit's per_pixel: 1, or 0 (lit per vertex)
    int environment_size = -1;     // the environment's level 0, texels a side
    int environment_samples = -1;  // its prefilter's GGX samples a texel
};

struct Point {
    std::string scene;
    Setting setting;
    double median_ms = 0.0;
    double pass_ms = 0.0;  // of it, the shadow maps' or the AO pre-pass and pass's; or
                           // (environment) the prefilter's, once at load
    reference::ImageError error;
    bool front = false;
};

std::string filter_name(const Setting& s) {
    switch (Filter(s.filter)) {
        case Filter::nearest: return "nearest";
        case Filter::bilinear: return "bilinear";
        case Filter::trilinear: return "trilinear";
        case Filter::anisotropic: return "anisotropic" + std::to_string(s.anisotropy) + "x";
    }
    return "?";
}

// Every material of `scene` replaced by a private copy changed by `edit`.
void edit_materials(Scene& scene, const std::function<void(Material&)>& edit) {
    const auto copy = [&](std::shared_ptr<Material>& slot) {
        if (!slot) return;
        slot = std::make_shared<Material>(*slot);
        edit(*slot);
    };
    for (Object& o : scene.objects) {
        copy(o.material);
        for (PartMaterial& p : o.part_materials) copy(p.material);
    }
}

// Sets parameter `name` where a material's shader declares it (INT, BOOL:
// value != 0, or FLOAT).
void set_param(Material& m, const char* name, double value) {
    const facet_param_desc* p = m.plugin ? m.plugin->find_param(name) : nullptr;
    if (!p || !m.block) return;
    auto block = std::make_shared<ParamBlock>(*m.block);
    if (p->type == FACET_PARAM_INT || p->type == FACET_PARAM_BOOL) {
        const int32_t v = p->type == FACET_PARAM_BOOL ? int32_t(value != 0.0) : int32_t(value);
        std::memcpy(block->bytes + p->offset, &v, sizeof v);
    } else if (p->type == FACET_PARAM_FLOAT) {
        const float v = float(value);
        std::memcpy(block->bytes + p->offset, &v, sizeof v);
    }
    m.block = block;
}

Scene with(const Scene& base, const Setting& s) {
    Scene scene = base;
    if (s.msaa > 0) scene.settings.msaa = s.msaa;
    if (s.subpixel_bits > 0) scene.settings.subpixel_bits = s.subpixel_bits;
    if (s.shadow_map_size > 0) scene.settings.shadow_map_size = s.shadow_map_size;
    if (s.ao_half >= 0) scene.settings.ao_half_resolution = s.ao_half == 1;
    if (s.ao_samples > 0) scene.settings.ao_samples = s.ao_samples;
    if (s.ao_radius > 0) scene.settings.ao_radius = float(s.ao_radius);
    if (s.environment_size > 0) {
        scene.environment.settings.size = s.environment_size;
        scene.environment.settings.samples = s.environment_samples;
        scene.environment.maps = load_environment(scene.environment.settings);
    }
    edit_materials(scene, [&](Material& m) {
        if (s.filter >= 0)
            for (TextureBinding& t : m.textures) {
                t.filter = Filter(s.filter);
                if (s.anisotropy > 0) t.anisotropy = s.anisotropy;
            }
        if (s.pcf_kernel > 0) set_param(m, "pcf_kernel", s.pcf_kernel);
        if (s.per_pixel >= 0) set_param(m, "per_pixel", s.per_pixel);
    });
    return scene;
}

// Median frame time and pass time over `runs` frames, each drawing its
// shadow maps: a map's size and filter cost what they cost while anything
// moves (a still frame keeps its maps).
void time_frames(const Scene& scene, Renderer& renderer, int runs, Framebuffer& fb, Point& p) {
    renderer.render(scene, fb);  // warm-up: passes allocate their buffers
    std::vector<double> ms, pass;
    for (int i = 0; i < runs; ++i) {
        renderer.forget_shadow_maps();
        const FrameStats s = renderer.render(scene, fb);
        ms.push_back(s.milliseconds);
        pass.push_back(s.ms_shadow + (s.ao_passes ? s.ms_prepass + s.ms_ao : 0.0));
    }
    std::sort(ms.begin(), ms.end());
    std::sort(pass.begin(), pass.end());
    p.median_ms = ms[ms.size() / 2];
    p.pass_ms = pass[pass.size() / 2];
}

// Marks the points of each scene that no other point of that scene beats on
// both time and RMSE.
void mark_fronts(std::vector<Point>& points) {
    for (Point& p : points) {
        p.front = true;
        for (const Point& q : points)
            if (&q != &p && q.scene == p.scene && q.median_ms <= p.median_ms &&
                q.error.rmse <= p.error.rmse &&
                (q.median_ms < p.median_ms || q.error.rmse < p.error.rmse))
                p.front = false;
    }
}

// The shadow and AO sweeps run at 4x MSAA, so that edge aliasing, which
// those knobs do not touch, does not drown what they change.
constexpr int kPassMsaa = 4;

std::vector<Setting> sweep(const std::string& scene, const Scene& base) {
    std::vector<Setting> out;
    if (scene == "default" || scene == "lit" || scene == "gallery") {  // textured
        // filters: nearest, bilinear, trilinear, anisotropic 4x and 16x
        const std::pair<Filter, int> filters[] = {{Filter::nearest, -1},
                                                  {Filter::bilinear, -1},
                                                  {Filter::trilinear, -1},
                                                  {Filter::anisotropic, 4},
                                                  {Filter::anisotropic, 16}};
        for (int bits : {4, 8})
            for (const auto& [filter, most] : filters)
                for (int msaa : {1, 2, 4, 8})
                    for (int per_pixel : scene == "lit" ? std::vector<int>{1, 0}
                                                        : std::vector<int>{-1}) {
                        Setting s;
                        s.msaa = msaa;
                        s.filter = int(filter);
                        s.anisotropy = most;
                        s.subpixel_bits = bits;
                        s.per_pixel = per_pixel;
                        out.push_back(s);
                    }
    } else if (scene == "phong" || scene == "toon") {  // no texture; edges only
        for (int bits : {2, 4, 6, 8})
            for (int msaa : {1, 2, 4, 8}) {
                Setting s;
                s.msaa = msaa;
                s.subpixel_bits = bits;
                out.push_back(s);
            }
    } else if (scene == "shadow") {
        for (int size : {512, 1024, 2048, 4096})
            for (int pcf : {1, 3, 5, 7}) {
                Setting s;
                s.msaa = kPassMsaa;
                s.shadow_map_size = size;
                s.pcf_kernel = pcf;
                out.push_back(s);
            }
    } else if (scene == "environment") {
        for (int size : {32, 64, 128, 256})
            for (int samples : {16, 64, 256}) {
                Setting s;
                s.environment_size = size;
                s.environment_samples = samples;
                out.push_back(s);
            }
    } else if (scene == "ao") {
        const double radius = base.settings.ao_radius;
        for (double scale : {0.5, 1.0, 2.0})
            for (int samples : {4, 8, 16, 32})
                for (int half : {0, 1}) {
                    Setting s;
                    s.msaa = kPassMsaa;
                    s.ao_samples = samples;
                    s.ao_radius = radius * scale;
                    s.ao_half = half;
                    out.push_back(s);
                }
    }
    return out;
}

// The CSV's header, and a point's row: `pareto` is 1 or 0 once the fronts
// are known, empty before (a run stopped part way).
void csv_header(std::ostream& out) {
    out << "scene,msaa,filter,subpixel_bits,shadow_map_size,pcf_kernel,ao_samples,ao_radius,"
           "ao_resolution,per_pixel,environment_size,environment_samples,threads,median_ms,pass_ms,"
           "rmse,max_error,dssim,pareto\n";
}

void csv_row(std::ostream& out, const Point& p, int threads, bool fronts_known) {
    const Setting& s = p.setting;
    out << p.scene << ',' << s.msaa << ',' << (s.filter >= 0 ? filter_name(s) : "") << ','
        << s.subpixel_bits << ',' << s.shadow_map_size << ',' << s.pcf_kernel << ','
        << s.ao_samples << ',' << s.ao_radius << ','
        << (s.ao_half < 0 ? "" : s.ao_half ? "half" : "full") << ',' << s.per_pixel << ','
        << s.environment_size << ',' << s.environment_samples << ',' << threads << ',' << p.median_ms << ',' << p.pass_ms << ',' << p.error.rmse << ','
        << p.error.max << ',' << p.error.dssim << ','
        << (fronts_known ? (p.front ? "1" : "0") : "") << '\n';
}

void write_csv(const std::string& path, const std::vector<Point>& points, int threads) {
    std::ofstream out(path);
    csv_header(out);
    for (const Point& p : points) csv_row(out, p, threads, true);
    if (!out) throw std::runtime_error("cannot write " + path);
}

std::string label(const Setting& s) {
    std::string l;
    auto add = [&](const std::string& part) { l += (l.empty() ? "" : " ") + part; };
    if (s.msaa > 0) add("msaa=" + std::to_string(s.msaa));
    if (s.filter >= 0) add(filter_name(s));
    if (s.subpixel_bits > 0) add("bits=" + std::to_string(s.subpixel_bits));
    if (s.shadow_map_size > 0) add("map=" + std::to_string(s.shadow_map_size));
    if (s.pcf_kernel > 0) add("pcf=" + std::to_string(s.pcf_kernel));
    if (s.ao_samples > 0) add("samples=" + std::to_string(s.ao_samples));
    if (s.ao_radius > 0) {
        char r[32];
        std::snprintf(r, sizeof r, "radius=%.3g", s.ao_radius);
        add(r);
    }
    if (s.ao_half >= 0) add(s.ao_half ? "half" : "full");
    if (s.per_pixel >= 0) add(s.per_pixel ? "per-pixel" : "per-vertex");
    if (s.environment_size > 0) add("size=" + std::to_string(s.environment_size));
    if (s.environment_samples > 0) add("ggx=" + std::to_string(s.environment_samples));
    return l;
}

// The environment scene as its Monte Carlo reference sees it: no post
// chain, its tonemap's exposure moved into the environment's intensity (so
// that the comparison's sRGB values are the picture's, before the curve).
void lit_by_environment_alone(Scene& scene) {
    for (const PostPass& p : scene.post)
        if (p.name == "tonemap")
            for (const MaterialParam& m : p.params)
                if (m.name == "exposure" && !m.numbers.empty())
                    scene.environment.settings.intensity *= float(std::exp2(m.numbers[0]));
    scene.settings.post = false;
}

// The environment scene's truth, as an image: the Monte Carlo reference of
// reference/environment.hpp (its pixels see pbr surfaces or the sky).
std::vector<glm::dvec4> environment_truth(const Scene& scene, int rays, int threads) {
    const reference::EnvironmentImage image(scene.environment.settings.files.at(0));
    const reference::EnvironmentTruth t = reference::environment_truth(scene, image, rays, threads);
    std::vector<glm::dvec4> out(t.color.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = glm::dvec4(t.color[i], 1.0);
    return out;
}

// One scene of the sweep: its reference settings and the quality
// settings to measure against it.
struct Study {
    std::string name;
    fs::path file;
    Scene base;
    std::vector<Setting> settings;
    reference::RenderOptions ro;
    double samples;  // the reference's rays: its cost
};

// Every scene and its settings, first, to count the work (`total` steps:
// each scene's reference and its settings).
std::vector<Study> load_studies(const ParetoOptions& o, PluginRegistry& registry, int threads,
                                int& total) {
    const std::vector<std::string> all = {"default", "lit",     "phong",      "toon",
                                          "shadow",  "ao",      "gallery",    "environment"};
    for (const std::string& name : o.scenes)
        if (std::find(all.begin(), all.end(), name) == all.end())
            throw std::runtime_error("--pareto has no study '" + name + "' (it has default, lit, "
                                     "phong, toon, shadow, ao, gallery and environment)");
    std::vector<Study> studies;
    for (const std::string& name : o.scenes.empty() ? all : o.scenes) {
        Study st{name, data_dir() / "configs" / (name == "default" ? "default.yaml" : "scenes/" + name + ".yaml"),
                 {}, {}, {}, 0.0};
        st.base = load_scene(st.file, registry);
        // The reference draws no cutouts: the gallery's leaves are opaque on
        // both sides of the comparison.
        edit_materials(st.base, [](Material& m) {
            if (!m.discards) return;
            set_param(m, "alpha_cutoff", 0.0);
            m.discards = false;
        });
        st.base.settings.width = o.width;
        st.base.settings.height = o.height;
        // The knobs' own error, not the 8-bit output's rounding: the metrics
        // compare sRGB values without it (metrics.hpp).
        st.base.settings.color_format = ColorFormat::rgba32f;
        st.ro.grid = name == "ao" ? o.ao_grid : o.grid;
        st.ro.ao_rays = o.ao_rays;
        st.ro.threads = threads;
        st.samples = double(o.width) * o.height * st.ro.grid * st.ro.grid * (name == "ao" ? o.ao_rays : 1);
        if (name == "environment") {
            lit_by_environment_alone(st.base);
            st.samples = double(o.width) * o.height * o.environment_rays;
        }
        st.settings = sweep(name, st.base);
        total += 1 + int(st.settings.size());
        studies.push_back(std::move(st));
    }
    return studies;
}

// The plot of the sweep (o.plot) from its CSV, through matplotlib.
int plot(const ParetoOptions& o) {
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::string command = python + " \"" FACET_SOURCE_DIR "/bench/plot_pareto.py\" \"" +
                                o.csv + "\" \"" + o.plot + "\"";
    if (std::system(command.c_str()) != 0) {
        spdlog::error("plotting failed ({}); python3-matplotlib comes with scripts/install-deps",
                      command);
        return 1;
    }
    std::printf("wrote %s\n", o.plot.c_str());
    return 0;
}

}  // namespace

int run_pareto(const ParetoOptions& o) {
    // The environment study times its prefilters: none read from disk.
    setenv("FACET_CACHE_DIR", "off", 1);
    const int threads = o.threads > 0 ? o.threads : default_threads();
    std::printf("facet-bench --pareto: %dx%d, %d thread(s), median of %d frames; reference "
                "%dx%d samples per pixel (ao scene: %dx%d, %d AO rays each), %d thread(s)\n",
                o.width, o.height, threads, o.runs, o.grid, o.grid, o.ao_grid, o.ao_grid,
                o.ao_rays, threads);
    PluginRegistry registry;
    Renderer renderer(threads);
    renderer.pipeline().stop_when(o.stop);
    Framebuffer fb;

    int total = 0;
    std::vector<Study> studies = load_studies(o, registry, threads, total);
    Progress progress("steps", total);
    // Time left: the references still to render at the seconds per sample
    // of those done, and the settings left at the mean time of those done.
    double reference_seconds = 0.0, reference_samples = 0.0, setting_seconds = 0.0;
    int settings_done = 0;
    const auto seconds_left = [&](size_t study, bool reference_next) -> std::optional<double> {
        if (reference_samples == 0.0 || settings_done == 0) return std::nullopt;
        double left = 0.0;
        for (size_t k = study; k < studies.size(); ++k) {
            if (k > study || reference_next) left += studies[k].samples * reference_seconds / reference_samples;
            left += double(studies[k].settings.size()) * setting_seconds / settings_done;
        }
        return left;
    };
    std::ofstream csv(o.csv);  // a row at a time; rewritten with the fronts at the end
    csv_header(csv);
    csv.flush();
    std::vector<Point> points;
    for (size_t k = 0; k < studies.size(); ++k) {
        Study& st = studies[k];
        progress.begin(st.name + ": reference image", seconds_left(k, true));
        const auto start = std::chrono::steady_clock::now();
        const std::vector<glm::dvec4> truth =
            st.name == "environment" ? environment_truth(st.base, o.environment_rays, threads)
                                     : reference::render(st.base, st.ro);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        reference_seconds += seconds;
        reference_samples += st.samples;
        progress.end();
        progress.clear();
        std::printf("\n%s (%s): reference in %.1f s\n", st.name.c_str(), st.file.string().c_str(),
                    seconds);
        std::printf("  %-44s %9s %9s %9s %9s %9s\n", "setting", "ms", "pass ms", "rmse", "max",
                    "dssim");
        for (size_t i = 0; i < st.settings.size(); ++i) {
            const Setting& s = st.settings[i];
            std::optional<double> left = seconds_left(k, false);
            if (left && settings_done) left = *left - double(i) * setting_seconds / settings_done;
            progress.begin(st.name + ": " + label(s), left);
            const auto setting_start = std::chrono::steady_clock::now();
            const Scene scene = with(st.base, s);
            const double prefilter_ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                          setting_start).count();
            Point p{st.name, s, 0.0, 0.0, {}, false};
            try {
                time_frames(scene, renderer, o.runs, fb, p);
                if (s.environment_size > 0) p.pass_ms = prefilter_ms;
            } catch (const Error& e) {
                if (e.code() != ErrorCode::interrupted) throw;
                progress.clear();
                std::printf("stopped after %d of %d steps: %s keeps the %zu settings finished\n",
                            progress.done(), total, o.csv.c_str(), points.size());
                return 130;
            }
            p.error = reference::compare(reference::linear_image(fb), truth, o.width, o.height);
            setting_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                             setting_start).count();
            ++settings_done;
            progress.end();
            progress.clear();
            std::printf("  %-44s %9.2f %9.2f %9.5f %9.4f %9.5f\n", label(s).c_str(), p.median_ms,
                        p.pass_ms, p.error.rmse, p.error.max, p.error.dssim);
            std::fflush(stdout);
            csv_row(csv, p, threads, false);
            csv.flush();
            points.push_back(p);
        }
    }
    mark_fronts(points);
    std::printf("\nPareto front (no setting of the same scene is both faster and lower in RMSE):\n");
    for (const Point& p : points)
        if (p.front)
            std::printf("  %-7s %-40s %8.2f ms  rmse %.5f\n", p.scene.c_str(), label(p.setting).c_str(),
                        p.median_ms, p.error.rmse);
    write_csv(o.csv, points, threads);
    std::printf("wrote %s\n", o.csv.c_str());

    return o.plot.empty() ? 0 : plot(o);
}

}  // namespace facet::bench
