// facet-bench: frame times of facet's pipeline over scenes, sizes, shaders
// and thread counts.
//
//     facet-bench [--scene NAME]... [--mesh FILE]... [--size WxH]... [--shader NAME]...
//                 [--threads N]... [--isa PATH]... [--target srgb8|rgba32f] [--runs N]
//                 [--rounds N] [--render YAML]... [--redraw-shadows] [--depth-prepass]
//                 [--csv FILE] [--json FILE]
//     facet-bench --pareto [--size WxH] [--threads N] [--runs N]
//                 [--reference-grid N] [--csv FILE] [--plot FILE]
//     facet-bench --llvmpipe [the options of the first form]
//
// Each configuration is measured on each instruction-set path of --isa
// (sse2, avx2, avx512; by default every one this CPU has), side by side in
// one run, and the output names the CPU, the path of each row and the
// thread count. --target is the colour target both renderers draw into:
// srgb8 (the default, what a display or a PNG takes) or rgba32f.
//
// --pareto measures run time against error instead (pareto.hpp).
//
// --render '{key: value, ...}' applies render settings over each scene's, as
// a scene file's render: map would ('{shadows: false}', '{msaa: 4}'); given
// several times, each is its own set of rows, side by side ('{}': none).
// --redraw-shadows draws every shadow map in every frame, as while the
// camera moves; otherwise a map is kept while nothing it depends on changes.
// Each row also gives the median time of its shadow maps and of its AO
// pre-pass and pass.
//
// --llvmpipe (when built with OSMesa) also draws each configuration through
// Mesa's llvmpipe with a GLSL version of its shader (phong and unlit only;
// other shaders' rows get no llvmpipe columns; a scene file when all its
// materials are opaque phong or unlit with no texture but a base texture;
// no row under --render),
// in a child process that
// sets llvmpipe's thread count (llvmpipe/worker.hpp, llvmpipe/llvmpipe.hpp), once per
// configuration (all paths' rows share it). It adds llvmpipe's median, the
// ratio llvmpipe ms / facet ms (above 1: facet is faster) and the pixels
// whose coverage differs (a share in the table; the CSV and JSON also give
// the count): which pixels any geometry covers, from an unlit white frame on
// black drawn by each. The GLSL computes the plugins' colours, with their
// base textures (facet's mip chain, filter and wrap: llvmpipe.hpp).
// The GLSL receives no shadows, so facet draws the rows that have llvmpipe
// columns without them (render: shadows: false, said in the row's note).
// With --target srgb8 both encode each fragment to 8-bit sRGB as they write
// it (GL_FRAMEBUFFER_SRGB; 4 bytes a pixel). When a worker fails (a crash, a
// timeout, settings llvmpipe cannot model such as MSAA or wireframe), the
// error is logged, that row's llvmpipe columns stay empty, the run goes on
// and facet-bench exits with 1 at the end.
//
// Scenes, by name (made here, except the bunny and the dragon), or a scene
// file (NAME.yaml), drawn with its own materials and settings but the size
// and target of the command line:
//   small     a sphere of ~1k triangles
//   medium    the Stanford bunny (69,451 triangles) from ../shared/assets,
//             or a ~70k-triangle sphere where that file is absent
//   dragon    the Stanford dragon (202,520 triangles) from ../shared/assets,
//             or a ~200k-triangle sphere where that file is absent
//   large     a sphere of ~1M triangles
//   fill      six screen-covering quads drawn far to near: 6x overdraw
//   subpixel  a grid of ~1M triangles of about half a pixel each
//   huge      a sphere of ~5M triangles (memory: a draw holds per-vertex
//             results and a bounded batch of triangles, never the whole mesh)
// and three textured scene files, by name:
//   town      an MTL town of ~107k triangles and 56 textures, trilinear, seen
//             down a street (written by the build: town/make_town.cpp)
//   gallery   configs/scenes/gallery.yaml, glTF materials through pbr
//   spot      bench/scenes/spot_textured.yaml: Spot with its texture, phong
// Every object gets the shader under test with its default parameters, one
// shadow-casting directional light and one point light (no shadows in rows
// against llvmpipe, above).
//
// --mesh FILE (any mesh load_mesh reads: OBJ, PLY, glTF, GLB, OFF, STL, ...)
// is a scene of its own, the user's setting: the mesh framed in view by its
// bounds, back faces culled, and one directional light that casts no
// shadow; each --shader draws it. With --mesh and no --scene, only the
// meshes are measured. Each configuration
// renders one warm-up frame, then --runs frames; the median is reported, with
// the thread count and the peak resident memory while rendering that scene
// (Linux: VmHWM, reset when the scene starts; it includes the scene itself,
// not --llvmpipe's facet coverage pass).
#include "meshes.hpp"  // tests/meshes.hpp
#include "pareto.hpp"
#include "progress.hpp"
#ifdef FACET_HAVE_OSMESA
#include "llvmpipe/worker.hpp"
#endif

#include <facet/command_line.hpp>
#include <facet/error.hpp>
#include <facet/interrupts.hpp>
#include <facet/isa.hpp>
#include <facet/material.hpp>
#include <facet/pipeline.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/tool.hpp>

#include <spdlog/spdlog.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

using namespace facet;
using bench::Progress;

namespace {

// A UV sphere of radius 1 with about `triangles` triangles.
std::shared_ptr<Mesh> sphere(int triangles) {
    return std::make_shared<Mesh>(test::uv_sphere(std::max(4, int(std::sqrt(triangles / 4.0)))));
}

// An n x n grid of quads in the z = 0 plane over [-w, w] x [-h, h], facing +Z.
std::shared_ptr<Mesh> grid(int n, float w, float h, float z = 0.0f) {
    auto m = std::make_shared<Mesh>();
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            m->positions.push_back({w * (2.0f * i / n - 1.0f), h * (2.0f * j / n - 1.0f), z});
            m->normals.push_back({0, 0, 1});
            m->uvs.push_back({float(i) / n, float(j) / n});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1),
                           d = c + 1;
            m->indices.insert(m->indices.end(), {a, b, d, a, d, c});
        }
    m->bounds = compute_bounds(m->positions);
    return m;
}

// The mesh scaled and moved to fit a unit sphere at the origin.
Transform fit(const Mesh& m) {
    Transform t;
    const glm::vec3 centre = 0.5f * (m.bounds.min + m.bounds.max);
    const float radius = 0.5f * glm::length(m.bounds.max - m.bounds.min);
    t.scale = glm::vec3(1.0f / radius);
    t.translation = -centre / radius;
    return t;
}

// A model from ../shared/assets/models, fitted to the unit sphere; a UV
// sphere of about as many triangles where the file is absent, which the
// console (once a run) and the note say.
std::vector<Object> shared_model(const std::string& file, const std::string& what,
                                 int triangles, std::string& note) {
    const std::filesystem::path path =
        std::filesystem::path(FACET_SOURCE_DIR) / "../shared/assets/models" / file;
    if (std::filesystem::exists(path)) {
        auto mesh = load_mesh(path);
        note = what;
        return {{file, mesh, fit(*mesh), nullptr, true}};
    }
    note = std::to_string(triangles / 1000) + "k-triangle sphere (" + file + " not found)";
    static std::set<std::string> said;
    if (said.insert(file).second)
        spdlog::warn("{} not found: measuring a {}k-triangle sphere in its place, which each "
                     "row's note says; these rows do not measure the {}",
                     path.lexically_normal().string(), triangles / 1000, what);
    return {{"sphere", sphere(triangles), {}, nullptr, true}};
}

// --mesh FILE's scene, by name: "mesh:" and the file's absolute path (the
// --llvmpipe worker makes the scene again from its name).
constexpr std::string_view kMeshPrefix = "mesh:";

bool is_mesh_scene(const std::string& name) { return name.starts_with(kMeshPrefix); }

std::string mesh_scene(const std::string& file) {
    return std::string(kMeshPrefix) + std::filesystem::absolute(file).lexically_normal().string();
}

std::filesystem::path mesh_file(const std::string& name) {
    return name.substr(kMeshPrefix.size());
}

// The user's mesh, fitted to the unit sphere (so the camera frames it).
std::vector<Object> mesh_objects(const std::string& name, std::string& note) {
    auto mesh = load_mesh(mesh_file(name));
    note = "framed by its bounds; one light";
    return {{mesh_file(name).filename().string(), mesh, fit(*mesh), nullptr, true}};
}

std::vector<Object> scene_objects(const std::string& name, std::string& note) {
    if (is_mesh_scene(name)) return mesh_objects(name, note);
    if (name == "small") return {{"sphere", sphere(1000), {}, nullptr, true}};
    if (name == "large") return {{"sphere", sphere(1000000), {}, nullptr, true}};
    if (name == "huge") return {{"sphere", sphere(5000000), {}, nullptr, true}};
    if (name == "medium") return shared_model("stanford-bunny.obj", "Stanford bunny", 70000, note);
    if (name == "dragon")
        return shared_model("stanford-dragon-202k.obj", "Stanford dragon", 202520, note);
    if (name == "fill") {
        std::vector<Object> quads;
        for (int k = 0; k < 6; ++k)  // far to near: every layer passes the depth test
            quads.push_back({"layer", grid(1, 4.0f, 4.0f, -1.5f + 0.5f * k), {}, nullptr, true});
        return quads;
    }
    if (name == "subpixel") return {{"grid", grid(700, 1.6f, 0.9f), {}, nullptr, true}};
    throw std::runtime_error("unknown scene '" + name + "'");
}

Scene make_scene(const std::string& name, std::string& note) {
    Scene s;
    s.objects = scene_objects(name, note);
    s.camera.position = {0.0f, 0.35f, 2.6f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.fov_y = 45.0f;
    Light sun;
    sun.direction = glm::normalize(glm::vec3(-0.5f, -1.0f, -0.4f));
    sun.casts_shadow = true;
    Light point;
    point.type = LightType::point;
    point.position = {1.5f, 1.5f, 2.0f};
    point.attenuation = {1.0f, 0.0f, 0.2f};
    s.lights = {sun, point};
    if (is_mesh_scene(name)) {  // the user's setting: one light, no shadow
        sun.casts_shadow = false;
        s.lights = {sun};
    }
    return s;
}

bool is_scene_file(const std::string& name) {
    return !is_mesh_scene(name) && name.size() > 5 &&
           name.compare(name.size() - 5, 5, ".yaml") == 0;
}

// The textured scenes by name, as the scene files they are: `town` (the
// build writes it: town/make_town.cpp), the glTF `gallery`, and `spot`.
std::string named_scene_file(const std::string& name) {
    if (name == "town") return FACET_TOWN_SCENE;
    if (name == "gallery") return FACET_SOURCE_DIR "/configs/scenes/gallery.yaml";
    if (name == "spot") return FACET_SOURCE_DIR "/bench/scenes/spot_textured.yaml";
    return name;
}

void set_shader(Scene& s, PluginRegistry& registry, const std::string& shader) {
    auto m = std::make_shared<Material>();
    m->source = "facet-bench";
    m->shader = shader;
    TextureCache cache;
    bind(*m, registry.get(shader), cache);
    for (Object& o : s.objects) o.use_material(m);
}

// Peak resident memory since the last reset_peak_rss(), in MiB (Linux's
// VmHWM; elsewhere the process's peak, from getrusage).
double peak_rss_mib() {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;
}

// Linux: writing 5 to clear_refs resets VmHWM to the current resident size.
void reset_peak_rss() { std::ofstream("/proc/self/clear_refs") << "5"; }

// The peak resident memory of one scene's rows, from the scene's start,
// leaving out facet-bench's own side work (--llvmpipe's facet coverage
// pass): the peak so far is carried over that work and the kernel's peak
// reset after it.
class PeakRss {
public:
    PeakRss() { reset_peak_rss(); }
    double read() const { return std::max(carried_, peak_rss_mib()); }

    template <class Work>
    auto excluding(Work&& work) {
        carried_ = read();
        struct Reset {
            ~Reset() { reset_peak_rss(); }
        } reset;
        return work();
    }

private:
    double carried_ = 0.0;
};

// Pixels covered by one renderer only.
struct CoverageDiff {
    double percent = 0.0;
    size_t pixels = 0;
    size_t covered = 0;  // pixels facet covers (0: nothing in view)
};

// --llvmpipe: the same configuration drawn by llvmpipe.
struct Versus {
    int threads;                   // LP_NUM_THREADS (bench::llvmpipe_threads)
    double median_ms, min_ms;
    CoverageDiff coverage;
};

struct Result {
    std::string scene, note, shader, isa;
    int width, height, threads;
    uint64_t triangles;
    double median_ms, min_ms, peak_rss_mib;
    double shadow_ms, ao_ms;  // medians of the shadow maps' and the AO pre-pass and pass's times
    double post_ms = 0.0;     // median of the post chain's passes, all together
    std::vector<std::pair<std::string, double>> post_pass_ms;  // each pass's median
    std::optional<Versus> llvmpipe;  // --llvmpipe, for shaders it has, when its worker succeeded
    std::string render;  // the --render settings it ran under ("" for the scene's own)
    bool shadows_dropped = false;  // drawn without its shadows, as llvmpipe draws it
};

// The middle value of a non-empty list (the upper of the two middle ones).
double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

Result measure(Scene& scene, const std::string& name, const std::string& note,
               const std::string& shader, int threads, Isa isa, int runs, bool redraw_shadows,
               const PeakRss& peak, const std::atomic<bool>* stop) {
    Renderer renderer(threads, isa);
    renderer.pipeline().stop_when(stop);  // Ctrl-C: Error(interrupted) within a tile
    Framebuffer fb;
    const FrameStats first = renderer.render(scene, fb);  // warm-up
    const size_t timed = std::min<size_t>(first.post_passes, FrameStats::kPostTimings);
    std::vector<double> ms, shadow_ms, ao_ms, post_ms;
    std::vector<std::vector<double>> pass_ms(timed);
    for (int i = 0; i < runs; ++i) {
        if (redraw_shadows) renderer.forget_shadow_maps();
        const FrameStats s = renderer.render(scene, fb);
        ms.push_back(s.milliseconds);
        shadow_ms.push_back(s.ms_shadow);
        ao_ms.push_back(s.ao_passes ? s.ms_prepass + s.ms_ao : 0.0);
        double post = 0.0;
        for (size_t k = 0; k < timed; ++k) {
            pass_ms[k].push_back(s.ms_post_pass[k]);
            post += s.ms_post_pass[k];
        }
        post_ms.push_back(post);
    }
    const double min_ms = *std::min_element(ms.begin(), ms.end());
    Result r{name, note, shader, std::string(isa_name(isa)), scene.settings.width,
             scene.settings.height, renderer.threads(), first.triangles_in, median(ms), min_ms,
             peak.read(), median(shadow_ms), median(ao_ms), median(post_ms), {}, {}, {}, false};
    for (size_t k = 0; k < timed; ++k)
        r.post_pass_ms.emplace_back(scene.post[k].name, median(pass_ms[k]));
    return r;
}

// Each post pass's time, "bloom=3.10;tonemap=0.52" (CSV, JSON), or with
// spaces (the table).
std::string post_passes_text(const Result& r, char separator) {
    std::string out;
    for (const auto& [name, ms] : r.post_pass_ms) {
        char text[32];
        std::snprintf(text, sizeof text, "=%.2f", ms);
        out += (out.empty() ? "" : std::string(1, separator)) + name + text;
    }
    return out;
}

// With a float target, what turning it into 8-bit sRGB for a PNG or a window
// costs against clearing it (Pipeline::resolve_srgb8, Pipeline::clear): the
// medians of `runs`, in ms, of a target of varied colours.
void print_output_cost(const std::string& target, const glm::ivec2& size, int threads, Isa isa,
                       int runs) {
    Framebuffer fb(size.x, size.y, *parse_color_format(target));
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
            fb.set_pixel(x, y, {float(x) / float(size.x), float(y) / float(size.y),
                                float((x * 7 + y * 13) % 101) / 50.0f, 1.0f});
    Pipeline pipeline(threads, isa);
    std::vector<uint8_t> rgba;
    const auto median_ms = [&](auto&& work) {
        std::vector<double> ms;
        for (int i = 0; i <= runs; ++i) {  // the first warms up
            const auto start = std::chrono::steady_clock::now();
            work();
            const std::chrono::duration<double, std::milli> d = std::chrono::steady_clock::now() - start;
            if (i) ms.push_back(d.count());
        }
        return median(ms);
    };
    const double convert = median_ms([&] { pipeline.resolve_srgb8(fb, rgba); });
    FrameStats unused;
    float shade = 0.0f;
    const double clear = median_ms([&] {
        // With no draws, flush() clears every tile that does not still hold
        // the values: a colour other than the last clear's, every time.
        shade = shade == 0.1f ? 0.2f : 0.1f;
        pipeline.clear(fb, glm::vec4(shade), 0.0f);
        pipeline.flush(unused);
    });
    std::printf("%s %dx%d to 8-bit sRGB, %d threads, %s: %.2f ms (a clear: %.2f ms)\n",
                target.c_str(), size.x, size.y, pipeline.threads(),
                std::string(isa_name(isa)).c_str(), convert, clear);
}

// The CPU's model, without the commas that would split a CSV field.
std::string cpu_for_csv() {
    std::string cpu = cpu_name();
    std::replace(cpu.begin(), cpu.end(), ',', ' ');
    return cpu;
}

// The CSV, a row at a time as each configuration is measured (and flushed),
// so that a run stopped part way keeps the rows it finished. `round` is the
// round (1..N) a row was measured in; with --rounds N > 1 each row's median
// over the rounds follows at the end, its round "median". With `llvmpipe`,
// its columns too (empty in rows llvmpipe did not draw). Every row is
// drawn into the colour target `target`, by both renderers.
class CsvRows {
public:
    CsvRows(const std::string& path, const std::string& target, bool llvmpipe)
        : path_(path), out_(path), target_(target), cpu_(cpu_for_csv()), llvmpipe_(llvmpipe) {
        if (!out_) throw std::runtime_error("cannot write " + path);
        out_ << "scene,note,shader,cpu,isa,target,width,height,threads,triangles,median_ms,min_ms,"
                "shadow_ms,ao_ms,post_ms,post_passes,peak_rss_mib";
        if (llvmpipe_)
            out_ << ",llvmpipe_threads,llvmpipe_median_ms,llvmpipe_min_ms,"
                    "ratio_llvmpipe_over_facet,coverage_diff_percent,coverage_diff_pixels,covered_pixels";
        out_ << ",round\n" << std::flush;
    }

    void add(const Result& r, const std::string& round) {
        out_ << r.scene << ",\"" << r.note << "\"," << r.shader << ',' << cpu_ << ',' << r.isa
             << ',' << target_ << ',' << r.width << ',' << r.height << ',' << r.threads << ','
             << r.triangles << ',' << r.median_ms << ',' << r.min_ms << ',' << r.shadow_ms << ','
             << r.ao_ms << ',' << r.post_ms << ',' << post_passes_text(r, ';') << ','
             << r.peak_rss_mib;
        if (llvmpipe_ && r.llvmpipe)
            out_ << ',' << r.llvmpipe->threads << ',' << r.llvmpipe->median_ms << ','
                 << r.llvmpipe->min_ms << ',' << r.llvmpipe->median_ms / r.median_ms << ','
                 << r.llvmpipe->coverage.percent << ',' << r.llvmpipe->coverage.pixels << ','
                 << r.llvmpipe->coverage.covered;
        else if (llvmpipe_)
            out_ << ",,,,,,,";
        out_ << ',' << round << '\n' << std::flush;
        ++rows_;
    }

    const std::string& path() const { return path_; }
    int rows() const { return rows_; }

private:
    std::string path_;
    std::ofstream out_;
    std::string target_, cpu_;
    bool llvmpipe_;
    int rows_ = 0;
};

// The JSON fields of --llvmpipe (null where llvmpipe did not draw the row).
std::string json_llvmpipe(const Result& r) {
    if (!r.llvmpipe)
        return ", \"llvmpipe_threads\": null, \"llvmpipe_median_ms\": null, "
               "\"llvmpipe_min_ms\": null, \"ratio_llvmpipe_over_facet\": null, "
               "\"coverage_diff_percent\": null, \"coverage_diff_pixels\": null, "
               "\"covered_pixels\": null";
    std::ostringstream out;
    out << ", \"llvmpipe_threads\": " << r.llvmpipe->threads
        << ", \"llvmpipe_median_ms\": " << r.llvmpipe->median_ms
        << ", \"llvmpipe_min_ms\": " << r.llvmpipe->min_ms
        << ", \"ratio_llvmpipe_over_facet\": " << r.llvmpipe->median_ms / r.median_ms
        << ", \"coverage_diff_percent\": " << r.llvmpipe->coverage.percent
        << ", \"coverage_diff_pixels\": " << r.llvmpipe->coverage.pixels
        << ", \"covered_pixels\": " << r.llvmpipe->coverage.covered;
    return out.str();
}

void write_json(const std::string& path, const std::vector<Result>& results,
                const std::string& target, bool llvmpipe) {
    std::ofstream out(path);
    const std::string cpu = cpu_for_csv();
    out << "[\n";
    for (size_t i = 0; i < results.size(); ++i) {
        const Result& r = results[i];
        out << "  {\"scene\": \"" << r.scene << "\", \"note\": \"" << r.note
            << "\", \"shader\": \"" << r.shader << "\", \"cpu\": \"" << cpu
            << "\", \"isa\": \"" << r.isa << "\", \"target\": \"" << target
            << "\", \"width\": " << r.width << ", \"height\": " << r.height
            << ", \"threads\": " << r.threads << ", \"triangles\": " << r.triangles
            << ", \"median_ms\": " << r.median_ms << ", \"min_ms\": " << r.min_ms
            << ", \"shadow_ms\": " << r.shadow_ms << ", \"ao_ms\": " << r.ao_ms
            << ", \"post_ms\": " << r.post_ms << ", \"post_passes\": \"" << post_passes_text(r, ';')
            << "\""
            << ", \"peak_rss_mib\": " << r.peak_rss_mib << (llvmpipe ? json_llvmpipe(r) : "")
            << "}" << (i + 1 < results.size() ? "," : "") << "\n";
    }
    out << "]\n";
}

#ifdef FACET_HAVE_OSMESA
// Which pixels facet covers: 1 where an unlit white frame of `scene` on its
// black clear is not black. The image is the same at any thread count.
std::vector<uint8_t> facet_coverage(const Scene& scene, PluginRegistry& registry) {
    Scene white = scene;
    set_shader(white, registry, "unlit");
    Renderer renderer;
    Framebuffer fb;
    renderer.render(white, fb);
    const std::vector<glm::vec4> px = fb.linear();
    std::vector<uint8_t> covered(px.size());
    for (size_t i = 0; i < covered.size(); ++i) covered[i] = glm::vec3(px[i]) != glm::vec3(0.0f);
    return covered;
}

// The pixels covered in one mask and not in the other.
CoverageDiff coverage_diff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    if (a.size() != b.size() || a.empty())
        throw std::runtime_error("coverage masks of different sizes");
    CoverageDiff d;
    for (size_t i = 0; i < a.size(); ++i) {
        d.pixels += (a[i] != 0) != (b[i] != 0);
        d.covered += a[i] != 0;
    }
    d.percent = 100.0 * double(d.pixels) / double(a.size());
    return d;
}

// What one llvmpipe worker measured, as a row's columns, and its GL renderer.
struct LlvmpipeRun {
    Versus versus;
    std::string renderer;
};

// --llvmpipe: configuration `r` (scene, size, shader, threads) drawn by
// llvmpipe in a child process. Coverage depends on neither the shader nor
// the thread count, so it is compared once per scene and size: `known` is
// that comparison when it has been made. facet's side of it stays out of
// the rows' peak memory.
LlvmpipeRun versus_llvmpipe(const Result& r, const std::string& size, int runs,
                            bench::LlvmpipeTarget target, const Scene& scene,
                            PluginRegistry& registry, std::optional<CoverageDiff> known,
                            PeakRss& peak) {
    const bench::LlvmpipeJob job{.scene = r.scene,
                                 .size = size,
                                 .shader = r.shader,
                                 .runs = runs,
                                 .threads = bench::llvmpipe_threads(r.threads),
                                 .target = target,
                                 .coverage = !known};
    const bench::LlvmpipeResult lp = bench::measure_llvmpipe(job);
    const CoverageDiff coverage = known ? *known : peak.excluding([&] {
        return coverage_diff(facet_coverage(scene, registry), lp.coverage);
    });
    return {{job.threads, lp.median_ms, lp.min_ms, coverage}, lp.renderer};
}

// facet-bench --llvmpipe-worker: the child's side of bench::measure_llvmpipe,
// for the job's one configuration. It logs an error as the bare message,
// which the parent quotes (measure_llvmpipe captures its output).
int llvmpipe_worker(const bench::LlvmpipeJob& job, const std::string& result_path,
                    const std::string& mask_path) {
    try {
        std::string note;
        PluginRegistry registry;
        const bool file = is_scene_file(job.scene);
        // A scene file is drawn with its own materials (the job's shader is
        // "(scene)"), as facet-bench drew it.
        Scene scene = file ? load_scene(job.scene, registry) : make_scene(job.scene, note);
        const auto size = parse_size(job.size);
        if (!size) throw std::runtime_error("bad size '" + job.size + "'");
        scene.settings.width = size->x;
        scene.settings.height = size->y;
        bench::LlvmpipeRenderer lp(size->x, size->y, job.target);
        std::vector<uint8_t> coverage;
        if (!mask_path.empty()) {  // first, so that the timed frames come last
            Scene white = scene;
            set_shader(white, registry, "unlit");
            lp.upload(white);
            lp.render(white);
            coverage = lp.coverage();
        }
        if (!file) set_shader(scene, registry, job.shader);
        lp.upload(scene);
        bench::LlvmpipeResult result = bench::time_frames(lp, scene, job.runs);
        result.coverage = std::move(coverage);
        bench::write_result(result, result_path, mask_path);
        return 0;
    } catch (const std::exception& e) {
        spdlog::set_pattern("%v");
        spdlog::error("{}", e.what());
        return 1;
    }
}
#endif

void print_header(bool llvmpipe, const std::string& target) {
    std::printf("%s; colour target %s\n", cpu_name().c_str(), target.c_str());
    std::printf("%-12s %-10s %-7s %-6s %7s %10s %12s %10s %10s %10s %10s", "scene", "size",
                "shader", "path", "threads", "triangles", "median ms", "shadow ms", "AO ms",
                "post ms", "peak MiB");
    if (llvmpipe)
        std::printf(" %11s %12s %9s %11s", "lp threads", "llvmpipe ms", "lp/facet", "cov diff %");
    std::printf("\n");
}

void print_row(const Result& r, const std::string& size, bool llvmpipe) {
    std::printf("%-12s %-10s %-7s %-6s %7d %10llu %12.2f %10.2f %10.2f %10.2f %10.1f",
                r.scene.c_str(), size.c_str(), r.shader.c_str(), r.isa.c_str(), r.threads,
                (unsigned long long)r.triangles, r.median_ms, r.shadow_ms, r.ao_ms, r.post_ms,
                r.peak_rss_mib);
    if (llvmpipe && r.llvmpipe)
        std::printf(" %11d %12.2f %9.2f %11.4f", r.llvmpipe->threads, r.llvmpipe->median_ms,
                    r.llvmpipe->median_ms / r.median_ms, r.llvmpipe->coverage.percent);
    else if (llvmpipe)
        std::printf(" %11s %12s %9s %11s", "-", "-", "-", "-");
    if (!r.note.empty() || !r.post_pass_ms.empty()) {  // what the row ran under, and its passes
        const std::string post = post_passes_text(r, ' ');
        std::printf("  (%s%s%s)", r.note.c_str(), r.note.empty() || post.empty() ? "" : "; ",
                    post.empty() ? "" : ("post ms: " + post).c_str());
    }
    std::printf("\n");
    std::fflush(stdout);
}

// --llvmpipe: its settings, the GL renderer once a child has reported it,
// the coverage comparison of the current scene and size, and the failures.
struct LlvmpipeSide {
    bool on = false;
    std::string target = "srgb8";  // the colour target of both renderers (--target)
    std::string renderer;
    std::optional<CoverageDiff> coverage;  // reset for each scene and size
    int failures = 0;

    // True when llvmpipe has a GLSL version of `shader`.
    bool draws(const std::string& shader) const {
#ifdef FACET_HAVE_OSMESA
        return bench::LlvmpipeRenderer::supports(shader);
#else
        (void)shader;
        return false;
#endif
    }

    // Row `r`'s llvmpipe columns (versus_llvmpipe), or none when its worker
    // fails: that is logged and counted, and the run goes on.
    std::optional<Versus> measure(const Result& r, const std::string& size, int runs,
                                  const Scene& scene, PluginRegistry& registry, PeakRss& peak) {
#ifdef FACET_HAVE_OSMESA
        try {
            const LlvmpipeRun run = versus_llvmpipe(r, size, runs, bench::parse_target(target),
                                                    scene, registry, coverage, peak);
            coverage = run.versus.coverage;
            renderer = run.renderer;
            return run.versus;
        } catch (const std::exception& e) {
            ++failures;
            spdlog::error("--llvmpipe, {} {} {} threads {}: {}", r.scene, size, r.shader,
                          r.threads, e.what());
            return std::nullopt;
        }
#else
        (void)r, (void)size, (void)runs, (void)scene, (void)registry, (void)peak;
        throw std::logic_error("built without OSMesa");
#endif
    }

    void print_skipped(const std::vector<std::string>& shaders) const {
        std::string skipped;
        for (const std::string& s : shaders)
            if (!draws(s)) skipped += (skipped.empty() ? "" : ", ") + s;
        if (!skipped.empty())
            std::printf("llvmpipe has no GLSL version of %s: facet only in their rows\n",
                        skipped.c_str());
    }

    void print_legend() const {
        std::printf(
            "llvmpipe: %s, colour buffer %s\n"
            "lp threads: LP_NUM_THREADS (0: llvmpipe draws on the calling thread)\n"
            "lp/facet: llvmpipe ms / facet ms (median; above 1, facet is faster)\n"
            "cov diff %%: pixels covered by only one of the two renderers\n"
            "work: the GLSL versions compute phong's and unlit's colours, base textures\n"
            "  included (facet's mip chain, filter and wrap)\n",
            renderer.empty() ? "(no worker reported)" : renderer.c_str(), target.c_str());
        if (target == "srgb8")
            std::printf("srgb8: both renderers encode each fragment to 8-bit sRGB as they write\n"
                        "  it (4 bytes a pixel), blending in linear light\n");
        if (failures)
            std::printf("llvmpipe: %d measurement(s) failed (logged above; their columns "
                        "are empty)\n",
                        failures);
    }
};

// Everything on facet-bench's command line.
struct Options {
    std::vector<std::string> scenes = {"small", "medium", "large", "fill",
                                       "subpixel", "huge", "town", "gallery"};
    std::vector<std::string> meshes;  // --mesh: files, each a scene (mesh_scene)
    std::vector<std::string> sizes = {"1280x720", "1920x1080"};
    std::vector<std::string> shaders = {"unlit", "lit", "phong", "toon", "shadow", "ao", "pbr"};
    std::vector<int> threads;  // default: 1 and default_threads()
    std::vector<std::string> isas;  // empty: every path this CPU has
    int runs = 5;
    int rounds = 1;
    bool depth_prepass = false;
    bool redraw_shadows = false;
    std::vector<std::string> render;  // --render: settings over each scene's, a row set each
    std::string csv = "facet-bench.csv", json = "facet-bench.json";
    bool pareto = false;
    bench::ParetoOptions po;
    LlvmpipeSide lp;
    std::string worker_result, worker_mask;  // --llvmpipe-worker, --llvmpipe-coverage
};

void add_options(CLI::App& app, Options& o) {
    CLI::Option* pareto_flag = app.add_flag(
        "--pareto", o.pareto,
        "run time against error for each quality knob, against the reference renderer "
        "(writes pareto.csv and pareto.png unless --csv / --plot say otherwise)");
    app.add_option("--reference-grid", o.po.grid, "--pareto: reference samples per pixel side")
        ->capture_default_str();
    app.add_option("--plot", o.po.plot, "--pareto: PNG plot of the sweep")->capture_default_str();
    app.add_option("--scene", o.scenes,
                   "small, medium, dragon, large, fill, subpixel, huge, the textured town, "
                   "gallery and spot, or a scene file (NAME.yaml, drawn with its own materials); "
                   "with --pareto, the studies to run (default, lit, phong, toon, shadow, ao, "
                   "gallery, environment)");
    app.add_option("--mesh", o.meshes,
                   "a mesh file of your own (OBJ, PLY, glTF, ...), framed in view by its bounds "
                   "and lit by one directional light, as a scene of its own (alone unless "
                   "--scene is given too)");
    app.add_option("--size", o.sizes, "image size WxH");
    app.add_option("--shader", o.shaders, "shader plugin name");
    app.add_option("--threads", o.threads,
                   "threads, counting the caller (default: 1 and FACET_NUM_THREADS, else every "
                   "hardware thread)")
        ->check(CLI::Range(1, 256));
    app.add_option("--isa", o.isas,
                   "instruction-set paths to measure facet on, side by side: sse2, avx2, "
                   "avx512 (default: every one this CPU has)");
    app.add_option("--target", o.lp.target,
                   "colour target of both renderers: srgb8 (8-bit sRGB, what a display or a "
                   "PNG takes) or rgba32f (linear float)")
        ->check(CLI::IsMember({"rgba32f", "srgb8"}))
        ->capture_default_str();
    app.add_option("--runs", o.runs, "frames per configuration (median)")->capture_default_str();
    app.add_option("--rounds", o.rounds,
                   "measure the whole table this many times, one round after another, and "
                   "report each row's median over the rounds")
        ->capture_default_str();
    app.add_option("--render", o.render,
                   "render settings over each scene's, as a scene file writes them, e.g. "
                   "'{shadows: false}'; each value is a set of rows ('{}': as the scene has them)");
    app.add_flag("--redraw-shadows", o.redraw_shadows,
                 "draw every shadow map in every frame, as while the camera or the casters "
                 "move (by default a map is kept while nothing it depends on changes)");
    app.add_flag("--depth-prepass", o.depth_prepass,
                 "render with the depth pre-pass (render: depth_prepass), noted in each row; "
                 "without it, a scene file's own setting holds");
    app.add_option("--csv", o.csv, "CSV output")->capture_default_str();
    app.add_option("--json", o.json, "JSON output")->capture_default_str();
    app.add_flag("--llvmpipe", o.lp.on,
                 "also draw each configuration (phong and unlit) through Mesa's llvmpipe "
                 "(OSMesa): its time, the ratio to facet's and the coverage difference")
        ->excludes(pareto_flag);
    // The child side of --llvmpipe (llvmpipe/worker.hpp); not for users.
    app.add_option("--llvmpipe-worker", o.worker_result)->group("");
    app.add_option("--llvmpipe-coverage", o.worker_mask)->group("");
}

// --llvmpipe-worker, or the error of --llvmpipe without OSMesa; nothing
// (continue) otherwise.
std::optional<int> run_llvmpipe_worker(const Options& o) {
#ifdef FACET_HAVE_OSMESA
    if (o.worker_result.empty()) return std::nullopt;
    // A child of --llvmpipe: the first of each list.
    const bench::LlvmpipeJob job{.scene = o.scenes.front(),
                                 .size = o.sizes.front(),
                                 .shader = o.shaders.front(),
                                 .runs = o.runs,
                                 .threads = 0,  // set by the parent, in the environment
                                 .target = bench::parse_target(o.lp.target),
                                 .coverage = !o.worker_mask.empty()};
    return llvmpipe_worker(job, o.worker_result, o.worker_mask);
#else
    if (!o.lp.on && o.worker_result.empty()) return std::nullopt;
    spdlog::error("--llvmpipe: this facet-bench was built without OSMesa; install "
                  "libosmesa6-dev (scripts/install-deps) and run CMake again");
    return 2;
#endif
}

int run_pareto(const CLI::App& app, Options& o, const Interrupts& interrupts) {
    if (app.count("--size")) {
        const auto size = parse_size(o.sizes.front());
        if (!size) {
            spdlog::error("--size: expected WxH with each side 1..{}, got '{}'",
                          Framebuffer::kMaxSize, o.sizes.front());
            return 2;
        }
        o.po.width = size->x;
        o.po.height = size->y;
    }
    if (app.count("--threads")) o.po.threads = o.threads.front();
    if (app.count("--runs")) o.po.runs = std::max(1, o.runs);
    if (app.count("--csv")) o.po.csv = o.csv;
    if (app.count("--scene")) o.po.scenes = o.scenes;
    o.po.stop = &interrupts.stop();
    const int status = bench::run_pareto(o.po);
    return interrupts.stopped() ? interrupts.exit_code() : status;
}

// Every row of scene `name` under `render` settings: each size, shader,
// thread count and path. With --llvmpipe, llvmpipe draws each configuration
// once, for all paths' rows, which facet draws without shadows, as
// llvmpipe does. A scene file's rows keep its own materials and settings
// (but the size, the target, --render, --depth-prepass and, against
// llvmpipe, shadows).

// True when llvmpipe can draw every visible object of a scene file as facet
// does: GLSL versions of their shaders, no texture but a base texture
// (and that one neither transformed nor on a second UV set).
bool llvmpipe_draws_scene(const Scene& scene, const LlvmpipeSide& lp) {
    for (const Object& o : scene.objects) {
        if (!o.visible || !o.mesh) continue;
        for (const Material* m : o.materials()) {
            if (!m->plugin) continue;
            if (!lp.draws(m->plugin->name())) return false;
            const facet_param_desc* base = m->plugin->find_param("base_texture");
            const int base_slot = base ? m->plugin->texture_slot(*base) : -1;
            for (size_t slot = 0; slot < m->textures.size(); ++slot) {
                const TextureBinding& t = m->textures[slot];
                if (t.texture && (int(slot) != base_slot || !t.transform.identity() || t.uv_set != 0))
                    return false;
            }
        }
    }
    return true;
}

// Where a table's rows go as they are measured: the count and time left,
// the CSV, and the round they belong to.
struct Sink {
    Progress& progress;
    CsvRows& csv;
    int round;  // 1..
    const std::atomic<bool>* stop;
};

// The configurations bench_scene() measures for one scene and render row.
int configurations(const std::string& name, const Options& o, size_t isas) {
    const size_t shaders = is_scene_file(name) ? 1 : o.shaders.size();
    return int(o.sizes.size() * shaders * o.threads.size() * isas);
}

void bench_scene(const std::string& name, const std::string& render, Options& o,
                 const std::vector<Isa>& isas, PluginRegistry& registry,
                 std::vector<Result>& results, Sink& sink) {
    PeakRss peak;  // from before the scene is made: its memory counts
    const bool file = is_scene_file(name);
    std::string note = file ? "scene file" : "";
    Scene scene = file ? load_scene(name, registry) : make_scene(name, note);
    if (o.depth_prepass) scene.settings.depth_prepass = true;  // else as the scene file says
    if (!render.empty()) {
        apply_render_settings(scene.settings, render, "--render");
        note += (note.empty() ? "render " : "; render ") + render;
    }
    scene.settings.color_format = *parse_color_format(o.lp.target);
    const std::vector<std::string> shaders = file ? std::vector<std::string>{"(scene)"} : o.shaders;
    const std::string label = file                ? std::filesystem::path(name).filename().string()
                              : is_mesh_scene(name) ? mesh_file(name).filename().string()
                                                    : name;
    // llvmpipe draws a scene as it is written (a scene file with its own
    // materials), never under --render settings, which its worker lacks.
    const bool versus = o.lp.on && render.empty() && (!file || llvmpipe_draws_scene(scene, o.lp));
    // Its GLSL shaders receive no shadows, so the rows compared with it are
    // drawn without them: both draw the same work.
    const bool shadows_on = scene.settings.shadows;
    const bool shadows = shadows_on && std::any_of(scene.lights.begin(), scene.lights.end(),
                                                   [](const Light& l) { return l.casts_shadow; });
    const auto noted = [&](const char* what) { return note + (note.empty() ? "" : "; ") + what; };
    if (scene.settings.depth_prepass) note = noted("depth pre-pass");
    for (const std::string& size : o.sizes) {
        const glm::ivec2 wh = *parse_size(size);  // run_table checked every size
        scene.settings.width = wh.x;
        scene.settings.height = wh.y;
        o.lp.coverage.reset();
        for (const std::string& shader : shaders) {
            if (!file) set_shader(scene, registry, shader);
            const bool compared = versus && (file || o.lp.draws(shader));
            scene.settings.shadows = shadows_on && !compared;
            const std::string row_note = compared && shadows ? noted("no shadows (llvmpipe draws none)")
                                         : o.redraw_shadows && shadows ? noted("shadow maps redrawn")
                                                                       : note;
            for (int t : o.threads) {
                std::optional<Versus> llvmpipe;
                for (Isa isa : isas) {
                    sink.progress.begin(label + " " + size + " " + shader + " " +
                                        std::to_string(t) + "t " + std::string(isa_name(isa)) +
                                        (render.empty() ? "" : " " + render));
                    Result r = measure(scene, label, row_note, shader, t, isa, o.runs,
                                       o.redraw_shadows, peak, sink.stop);
                    if (compared && isa == isas.front()) {
                        r.scene = name;  // the worker loads a scene file by its path
                        llvmpipe = o.lp.measure(r, size, o.runs, scene, registry, peak);
                        r.scene = label;
                    }
                    r.llvmpipe = llvmpipe;
                    r.render = render;
                    r.shadows_dropped = compared && shadows;
                    sink.progress.end();
                    sink.progress.clear();
                    print_row(r, size, o.lp.on);
                    sink.csv.add(r, std::to_string(sink.round));
                    results.push_back(r);
                }
            }
        }
    }
}

// With two or more --render settings, what each costs against the first:
// for every row of another render, the first's median over its own, taken
// in each round from the two rows that round measured, then the median
// (with two rounds, the higher) and the range of those over the rounds
// (the ratio of the rows' medians over rounds can pair a quiet round of
// one with a busy one of the other). "{} / {shadows: false}" over 1.5
// would say shadows cost more than half again the frame. Rows drawn
// without their shadows for --llvmpipe pair only with rows drawn so.
void print_render_ratios(const std::vector<std::vector<Result>>& rounds,
                         const std::vector<std::string>& renders) {  // as run_table keeps them
    if (renders.size() < 2) return;
    const auto same_row = [](const Result& a, const Result& b) {
        return a.scene == b.scene && a.width == b.width && a.height == b.height &&
               a.shader == b.shader && a.threads == b.threads && a.isa == b.isa &&
               a.shadows_dropped == b.shadows_dropped;
    };
    const std::string& base = renders.front();  // "" for the scene's own settings
    const auto shown = [](const std::string& render) { return render.empty() ? "{}" : render; };
    std::printf("the first render's median over each other's, per round: median [lowest, highest] "
                "over %zu round%s\n",
                rounds.size(), rounds.size() == 1 ? "" : "s");
    std::printf("%-12s %-10s %-7s %-6s %7s %8s %8s %8s  %s\n", "scene", "size", "shader", "path",
                "threads", "median", "lowest", "highest", "ratio");
    for (const Result& row : rounds.front()) {
        if (row.render == base) continue;
        std::vector<double> ratios;
        for (const std::vector<Result>& round : rounds) {
            const Result* first = nullptr;
            const Result* other = nullptr;
            for (const Result& r : round) {
                if (!same_row(r, row)) continue;
                if (r.render == base) first = &r;
                if (r.render == row.render) other = &r;
            }
            if (first && other) ratios.push_back(first->median_ms / other->median_ms);
        }
        if (ratios.empty()) continue;
        const auto [low, high] = std::minmax_element(ratios.begin(), ratios.end());
        std::printf("%-12s %-10s %-7s %-6s %7d %8.2f %8.2f %8.2f  %s / %s\n", row.scene.c_str(),
                    (std::to_string(row.width) + "x" + std::to_string(row.height)).c_str(),
                    row.shader.c_str(), row.isa.c_str(), row.threads, median(ratios), *low, *high,
                    shown(base).c_str(), shown(row.render).c_str());
    }
}

// Each row's median over rounds of the whole table (--rounds): a virtual
// machine's neighbours can slow a few seconds of a run, and rounds spread
// over minutes see through that. The fastest frame is the fastest of all;
// llvmpipe's columns, where every round has them, likewise.
std::vector<Result> median_of_rounds(const std::vector<std::vector<Result>>& rounds) {
    std::vector<Result> out = rounds.front();
    for (size_t i = 0; i < out.size(); ++i) {
        std::vector<double> ms, shadow_ms, ao_ms, post_ms, lp_ms;
        std::vector<std::vector<double>> pass_ms(out[i].post_pass_ms.size());
        for (const std::vector<Result>& round : rounds) {
            const Result& r = round[i];
            ms.push_back(r.median_ms);
            shadow_ms.push_back(r.shadow_ms);
            ao_ms.push_back(r.ao_ms);
            post_ms.push_back(r.post_ms);
            for (size_t k = 0; k < r.post_pass_ms.size() && k < pass_ms.size(); ++k)
                pass_ms[k].push_back(r.post_pass_ms[k].second);
            out[i].min_ms = std::min(out[i].min_ms, r.min_ms);
            out[i].peak_rss_mib = std::max(out[i].peak_rss_mib, r.peak_rss_mib);
            if (r.llvmpipe) lp_ms.push_back(r.llvmpipe->median_ms);
            if (r.llvmpipe && out[i].llvmpipe)
                out[i].llvmpipe->min_ms = std::min(out[i].llvmpipe->min_ms, r.llvmpipe->min_ms);
        }
        out[i].median_ms = median(ms);
        out[i].shadow_ms = median(shadow_ms);
        out[i].ao_ms = median(ao_ms);
        out[i].post_ms = median(post_ms);
        for (size_t k = 0; k < pass_ms.size(); ++k) out[i].post_pass_ms[k].second = median(pass_ms[k]);
        if (lp_ms.size() == rounds.size() && out[i].llvmpipe) out[i].llvmpipe->median_ms = median(lp_ms);
        else out[i].llvmpipe.reset();
    }
    return out;
}

// Whether `path` loads as a mesh with a triangle, having said why not.
bool loads_as_mesh(const std::filesystem::path& path) {
    try {
        if (load_mesh(path)->triangle_count() > 0) return true;
        spdlog::error("--mesh {}: the file holds no triangle", path.string());
    } catch (const Error& e) {
        spdlog::error("--mesh {}", e.what());
    }
    return false;
}

// Turns --scene's names into what bench_scene() takes and adds --mesh's
// files; false, having said why, when one is not a scene.
bool check_scenes(Options& o) {
    for (std::string& name : o.scenes) name = named_scene_file(name);
    for (const std::string& file : o.meshes) o.scenes.push_back(mesh_scene(file));
    for (const std::string& name : o.scenes) {
        if (is_scene_file(name) || is_mesh_scene(name)) {
            const std::filesystem::path path =
                is_mesh_scene(name) ? mesh_file(name) : std::filesystem::path(name);
            if (!std::filesystem::is_regular_file(path)) {
                spdlog::error("--{} {}: file not found", is_mesh_scene(name) ? "mesh" : "scene",
                              path.string());
                return false;
            }
            if (is_mesh_scene(name) && !loads_as_mesh(path)) return false;
        } else if (name != "small" && name != "medium" && name != "dragon" && name != "large" &&
                   name != "fill" && name != "subpixel" && name != "huge") {
            spdlog::error("--scene {}: expected small, medium, dragon, large, fill, subpixel, "
                          "huge, town, gallery, spot or a scene file (.yaml)", name);
            return false;
        }
    }
    return true;
}

// Checks every option of the table before the CSV (and a previous run's
// rows in it) is touched, saying what is wrong; gives the paths to measure
// and the --render settings ("" for the scene's own: no --render, or "{}").
bool check_options(Options& o, const PluginRegistry& registry, std::vector<Isa>& isas,
                   std::vector<std::string>& renders) {
    for (const std::string& size : o.sizes)
        if (!parse_size(size)) {
            spdlog::error("--size: expected WxH with each side 1..{}, got '{}'",
                          Framebuffer::kMaxSize, size);
            return false;
        }
    for (const std::string& name : o.isas) {
        const std::optional<Isa> isa = parse_isa(name);
        if (!isa || !isa_supported(*isa)) {
            spdlog::error("--isa {}: {}", name,
                          isa ? "this CPU does not have it" : "expected sse2, avx2 or avx512");
            return false;
        }
        isas.push_back(*isa);
    }
    if (isas.empty()) isas = supported_isas();
    o.runs = std::max(1, o.runs);
    o.rounds = std::max(1, o.rounds);
    renders = o.render.empty() ? std::vector<std::string>{""} : o.render;
    for (std::string& render : renders)
        if (render == "{}") render.clear();
    if (!check_scenes(o)) return false;
    const bool any_built_in = std::any_of(o.scenes.begin(), o.scenes.end(),
                                          [](const std::string& n) { return !is_scene_file(n); });
    for (const std::string& shader : any_built_in ? o.shaders : std::vector<std::string>{})
        if (registry.locate(shader).empty()) {
            spdlog::error("--shader {}: no {}.so in {}", shader, shader,
                          [&] {
                              std::string dirs;
                              for (const auto& d : registry.search_path())
                                  dirs += (dirs.empty() ? "" : ", ") + d.string();
                              return dirs;
                          }());
            return false;
        }
    for (const std::string& render : renders) {
        if (render.empty()) continue;
        RenderSettings check;
        try {
            apply_render_settings(check, render, "--render");
        } catch (const Error& e) {
            spdlog::error("{}", e.what());
            return false;
        }
    }
    return true;
}

// The table, CSV and JSON; non-zero when an option is wrong or an llvmpipe
// measurement failed (the rest still runs and is written); 130 or 143 when
// stopped by SIGINT or SIGTERM, after writing what was finished.
int run_table(Options& o, const Interrupts& interrupts) {
    PluginRegistry registry;
    std::vector<Isa> isas;
    std::vector<std::string> renders;
    if (!check_options(o, registry, isas, renders)) return 2;
    int total = 0;
    for (const std::string& name : o.scenes) total += configurations(name, o, isas.size());
    total *= int(renders.size()) * o.rounds;
    std::printf("facet-bench: %d configuration%s (%d frame%s each, after one to warm up), "
                "threads as each row says\n",
                total, total == 1 ? "" : "s", o.runs, o.runs == 1 ? "" : "s");
    Progress progress("configurations", total);
    CsvRows csv(o.csv, o.lp.target, o.lp.on);
    std::vector<std::vector<Result>> rounds(size_t(o.rounds));
    if (o.lp.on) o.lp.print_skipped(o.shaders);
    try {
        for (int r = 0; r < o.rounds; ++r) {
            if (o.rounds > 1) std::printf("round %d of %d\n", r + 1, o.rounds);
            print_header(o.lp.on, o.lp.target);
            Sink sink{progress, csv, r + 1, &interrupts.stop()};
            for (const std::string& name : o.scenes)
                for (const std::string& render : renders)
                    bench_scene(name, render, o, isas, registry, rounds[size_t(r)], sink);
        }
    } catch (const Error& e) {
        if (e.code() != ErrorCode::interrupted && !interrupts.stopped()) throw;
        progress.clear();
        std::vector<Result> finished;
        for (const std::vector<Result>& round : rounds)
            finished.insert(finished.end(), round.begin(), round.end());
        write_json(o.json, finished, o.lp.target, o.lp.on);
        std::printf("stopped after %d of %d configurations: %s and %s keep the %d rows finished\n",
                    progress.done(), total, o.csv.c_str(), o.json.c_str(), csv.rows());
        return interrupts.exit_code();
    }
    progress.clear();
    const std::vector<Result> results = median_of_rounds(rounds);
    if (o.rounds > 1) {
        std::printf("the median of the %d rounds\n", o.rounds);
        print_header(o.lp.on, o.lp.target);
        for (const Result& r : results) {
            print_row(r, std::to_string(r.width) + "x" + std::to_string(r.height), o.lp.on);
            csv.add(r, "median");
        }
    }
    print_render_ratios(rounds, renders);
    if (o.lp.on) o.lp.print_legend();
    if (o.lp.target != "srgb8")  // what a float target's 8-bit output costs
        for (const std::string& size : o.sizes)
            for (int t : o.threads)
                for (Isa isa : isas) print_output_cost(o.lp.target, *parse_size(size), t, isa, o.runs);
    write_json(o.json, results, o.lp.target, o.lp.on);
    std::printf("wrote %s and %s in %s\n", o.csv.c_str(), o.json.c_str(),
                Progress::duration(progress.elapsed_seconds()).c_str());
    if (interrupts.stopped()) return interrupts.exit_code();  // after the last row
    return o.lp.failures ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    const Interrupts interrupts("facet-bench");  // before any thread starts
    Options o;
    CLI::App app{"facet's frame times over scenes, sizes, shaders and threads, or (--pareto) "
                 "run time against error.",
                 "facet-bench"};
    add_options(app, o);
    Verbosity verbosity;
    add_common_options(app, verbosity);
    if (const std::optional<int> status = parse_command_line(app, argc, argv)) return *status;
    start_logging(verbosity, spdlog::level::warn);
    try {
        if (const std::optional<int> status = run_llvmpipe_worker(o)) return *status;
        // 1 and the default count (FACET_NUM_THREADS, else every hardware thread).
        if (!app.count("--threads")) o.threads = {1, default_threads()};
        if (!o.meshes.empty() && !app.count("--scene")) o.scenes.clear();  // the meshes alone
        std::vector<int> once;  // each count once, in the order given
        for (int t : o.threads)
            if (std::find(once.begin(), once.end(), t) == once.end()) once.push_back(t);
        o.threads = once;
        if (o.pareto) return run_pareto(app, o, interrupts);
        return run_table(o, interrupts);
    } catch (const std::exception& e) {
        if (interrupts.stopped()) return interrupts.exit_code();
        spdlog::error("{}", e.what());
        return 1;
    }
}
