// facet-render: render a scene headless to a PNG, or a sequence of frames.
//
//     facet-render [SCENE.yaml] [-o out.png] [--size WxH] [--camera X,Y,Z,TX,TY,TZ[,FOV]]
//                  [--msaa N] [--threads N] [--max-memory SIZE] [--wireframe]
//                  [--time T | --frames A..B|all [--fps N] [--resume]] [--band-rows N]
//                  [--plugin-path DIR]... [--plugin-timeout SECONDS] [--no-probe]
//                  [--watch [--rebuild]] [-v|-q] [--version]
//
// With no scene, renders the default scene (configs/default.yaml), posed at
// its animation's start (or --time T). --frames renders frames A..B of its
// animation, frame k at time k / fps, each to the output pattern with k in
// it (-o out_%04d.png), with progress and the time left; --resume skips
// frames whose files exist, and removes the partial files of a run that was
// killed. -o - writes the PNG to standard output. --band-rows N renders the image in bands of N
// rows, streamed into the PNG, so that no more than a band is in memory
// (images over 16384x16384 pixels always are). With
// --watch it keeps running and renders again whenever the scene, a material
// or a shader plugin changes (hot reload); with --rebuild it also rebuilds
// the shaders whose sources change: the built-in ones (shaders/, in a build
// tree) and any shader project whose CMake build folder is a plugin folder
// (--plugin-path, the scene's plugin_paths). Ctrl-C (SIGINT), SIGTERM or
// SIGHUP stops it within a second, writing no image and leaving no partial
// file: exit status 130, 143 or 129. An image that cannot be written (a
// full disk, a closed pipe) is an error with its cause, exit status 1, and
// a file that was there stays as it was. A shader plugin from outside
// facet's own folders first draws a probe frame in another process, and is
// refused if that fails (--no-probe skips it). A plugin that crashes, calls
// exit(), or stays in one call past --plugin-timeout (10 s) is named, and
// the program exits with status 70.
#include <facet/command_line.hpp>
#include <facet/error.hpp>
#include <facet/frame_report.hpp>
#include <facet/framebuffer.hpp>
#include <facet/hot_reload.hpp>
#include <facet/interrupts.hpp>
#include <facet/isa.hpp>
#include <facet/memory.hpp>
#include <facet/plugin.hpp>
#include <facet/output.hpp>
#include <facet/rebuild.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/sequence.hpp>
#include <facet/tool.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <thread>

namespace {

struct Options {
    std::string scene;
    std::string output = "facet.png";
    std::string size;
    std::string camera;
    int msaa = 0;     // 0: the scene's
    int threads = 0;  // 0: FACET_NUM_THREADS, else every hardware thread
    bool wireframe = false;
    std::vector<std::string> plugin_paths;
    bool watch = false;
    bool rebuild = false;
    std::string max_memory;
    std::optional<double> time;
    std::string frames;
    double fps = 0.0;  // 0: the scene's
    facet::PluginGuards plugin_guards;
    std::chrono::milliseconds probe_time{0};  // of a new plugin (PluginRegistry)
    bool resume = false;
    int band_rows = 0;
};

void report(const facet::FrameStats& s, const facet::Scene& scene) {
    spdlog::info("rendered {}x{} in {:.2f} ms: {} objects ({} culled), {} triangles in, "
                 "{} rasterized, {} clipped, {} back-facing, {} outside, {} degenerate or "
                 "between pixel centres, {} invalid; {} fragments shaded in {} shader calls",
                 scene.settings.width, scene.settings.height, s.milliseconds, s.objects,
                 s.objects_culled, s.triangles_in, s.triangles_rasterized, s.triangles_clipped,
                 s.triangles_culled_backface, s.triangles_culled_frustum,
                 s.triangles_culled_degenerate, s.triangles_invalid, s.fragments_shaded,
                 s.blocks_shaded);
    if (s.triangles_in > 0 && s.triangles_rasterized == 0)
        spdlog::warn("{}: nothing was drawn: every object is outside the camera's view, or each "
                     "of its triangles is degenerate or invalid as the camera sees it (counts "
                     "above)",
                     scene.source.string());
    std::vector<std::string> ran = facet::passes_run(s);
    ran.push_back(fmt::format("main {:.2f} ms", s.ms_main));
    if (s.post_passes)
        ran.push_back("post " + facet::join(facet::post_passes_run(s, scene.post), "") +
                      fmt::format(" (with resolve and output {:.2f} ms)", s.ms_post));
    else if (scene.settings.msaa > 1)
        ran.push_back(fmt::format("resolve {:.2f} ms", s.ms_post));
    spdlog::info("passes: {}", facet::join(ran, ""));
    spdlog::info("skipped: {}",
                 facet::join(facet::work_skipped(s, scene.settings, facet::Counts::full,
                                                 !scene.post.empty()),
                             "nothing"));
}

// Where the image went, for the log.
std::string written(const std::string& output) {
    return output == "-" ? "the image to standard output" : output;
}

// The image in bands of rows, each encoded as it is rendered and streamed
// into the PNG: the memory a band needs, whatever the image's size.
void render_bands(const Options& opt, const facet::Scene& scene, facet::Renderer& renderer) {
    const facet::RenderSettings& s = scene.settings;
    const int rows = facet::band_rows(opt.band_rows > 0 ? opt.band_rows : facet::kDefaultBandRows);
    const int bands = facet::band_count(s.height, rows);
    spdlog::info("rendering {}x{} in {} bands of {} rows", s.width, s.height, bands, rows);
    facet::PngWriter png(opt.output, s.width, s.height);
    facet::Progress progress("band", bands);
    facet::Framebuffer target;
    std::vector<uint8_t> rgba;
    for (int b = 0; b < bands; ++b) {
        const std::vector<facet::PngSegment> segments =
            facet::render_band(renderer, scene, b, rows, target, rgba);
        for (const facet::PngSegment& segment : segments) png.add(segment);
        progress.done(fmt::format("rows {}..{}", b * rows, std::min(s.height, (b + 1) * rows) - 1));
    }
    png.finish();
    spdlog::info("wrote {}", written(opt.output));
}

// Frames A..B of the scene's animation, each to its own file.
void render_sequence(const Options& opt, facet::Scene& scene, facet::Renderer& renderer,
                     const facet::Interrupts& interrupts) {
    const auto [range, fps] = facet::frames_to_render(opt.frames, opt.fps, scene.timeline);
    facet::Progress progress("frame", range.count());
    facet::Framebuffer target;
    std::vector<uint8_t> rgba;
    spdlog::info("rendering frames {}..{} at {} fps ({:.3f} s..{:.3f} s) to {}", range.first,
                 range.last, fps, double(range.first) / fps, double(range.last) / fps,
                 opt.output);
    // What a run that was killed left half-written: removed as its frame
    // comes up (and rendered again).
    std::multimap<std::string, std::filesystem::path> abandoned;
    if (opt.resume)
        for (const facet::AbandonedPartial& a :
             facet::abandoned_partials(std::filesystem::path(opt.output).parent_path()))
            abandoned.emplace(a.image.string(), a.file);
    for (long k = range.first; k <= range.last && !interrupts.stopped(); ++k) {
        const std::string path = facet::frame_path(opt.output, k);
        for (auto [at, end] = abandoned.equal_range(path); at != end; ++at) {
            std::error_code ec;
            if (std::filesystem::remove(at->second, ec))
                spdlog::info("removed {}, which a stopped run left unfinished", at->second.string());
        }
        if (opt.resume && std::filesystem::exists(path)) {
            spdlog::debug("frame {}: {} exists; skipped", k, path);
            progress.skipped();
            continue;
        }
        const facet::FrameStats stats =
            facet::render_frame_to_png(renderer, scene, k, fps, path, target, rgba);
        spdlog::debug("frame {}: {} triangles rasterized, {} fragments shaded in {:.2f} ms", k,
                      stats.triangles_rasterized, stats.fragments_shaded, stats.milliseconds);
        progress.done(path);
    }
    if (progress.finished() < range.count())
        spdlog::info("{} of {} frames rendered{}", progress.finished(), range.count(),
                     opt.resume ? "; the others existed" : "");
}

// Renders `scene` to the output PNG, with what the command line overrides.
void render(const Options& opt, facet::Scene& scene, std::optional<glm::ivec2> size,
            const facet::Interrupts& interrupts) {
    if (size) {
        scene.settings.width = size->x;
        scene.settings.height = size->y;
    }
    if (!opt.camera.empty()) scene.set_camera(*facet::parse_camera(opt.camera, scene.camera));
    if (opt.msaa) scene.settings.msaa = opt.msaa;
    if (opt.wireframe) scene.settings.wireframe = true;
    const facet::RenderSettings& s = scene.settings;
    const bool banded = opt.frames.empty() &&
                        (opt.band_rows > 0 ||
                         uint64_t(s.width) * uint64_t(s.height) > facet::Framebuffer::kMaxPixels);
    try {
        facet::RenderSettings needed = scene.settings;  // a band's, when in bands
        if (banded)
            needed.height = std::min(s.height, facet::band_rows(opt.band_rows > 0 ? opt.band_rows
                                                                                  : facet::kDefaultBandRows));
        facet::require_frame_within_budget(needed);
    } catch (const facet::Error& e) {  // named by what asked for the frame
        const std::string options = (size ? "--size " + opt.size : std::string()) +
                                    (size && opt.msaa ? " " : "") +
                                    (opt.msaa ? "--msaa " + std::to_string(opt.msaa) : "");
        throw facet::Error(e.code(), e.detail(),
                           options.empty() ? scene.source.string() + " (render: size, msaa)"
                                           : options);
    }
    if (banded)
        facet::check_band(s.width, std::min(s.height, facet::band_rows(opt.band_rows > 0
                                                                           ? opt.band_rows
                                                                           : facet::kDefaultBandRows)));
    facet::Renderer renderer(opt.threads);
    renderer.pipeline().stop_when(&interrupts.stop());
    spdlog::info("{} path on {}, {} threads", facet::isa_name(renderer.isa()), facet::cpu_name(),
                 renderer.threads());
    if (!opt.frames.empty()) return render_sequence(opt, scene, renderer, interrupts);
    if (opt.time) scene.pose(*opt.time);
    facet::remove_abandoned_partials(opt.output);  // what a killed run left of this image
    if (banded) return render_bands(opt, scene, renderer);
    facet::Framebuffer framebuffer;
    const facet::FrameStats stats = renderer.render(scene, framebuffer);
    std::vector<uint8_t> rgba;
    renderer.pipeline().resolve_srgb8(framebuffer, rgba);  // a copy of an srgb8 target
    facet::write_png(opt.output, framebuffer.width(), framebuffer.height(), rgba,
                     renderer.threads());
    report(stats, scene);
    spdlog::info("wrote {}", written(opt.output));
}

// Renders again whenever hot reload applies a change, until Ctrl-C.
void watch(const Options& opt, facet::PluginRegistry& registry, facet::Scene& scene,
           std::optional<glm::ivec2> size, std::vector<facet::ShaderProject> projects,
           const facet::Interrupts& interrupts) {
    facet::HotReload reload(registry, scene);
    std::optional<facet::ShaderRebuilder> rebuilder;
    if (opt.rebuild) rebuilder.emplace(std::move(projects));
    spdlog::info("watching for changes (Ctrl-C to stop)");
    while (!interrupts.stopped()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (rebuilder) rebuilder->update();  // events are logged as they happen
        if (!reload.update()) continue;
        try {
            render(opt, scene, size, interrupts);
        } catch (const facet::Error& e) {
            if (e.code() == facet::ErrorCode::interrupted) return;
            spdlog::error("{}", e.what());  // e.g. the PNG could not be written; keep watching
        }
    }
}

int run(const Options& opt, const facet::Interrupts& interrupts) {
    if (!facet::apply_max_memory(opt.max_memory, opt.threads)) return 2;
    std::optional<glm::ivec2> size;
    if (!opt.size.empty() && !(size = facet::parse_size(opt.size))) {
        spdlog::error("--size: expected WxH with each side 1..{}, got '{}'",
                      facet::Framebuffer::kMaxSize, opt.size);
        return 2;
    }
    if (!opt.camera.empty() && !facet::parse_camera(opt.camera, facet::Camera{})) {
        spdlog::error("--camera: expected X,Y,Z,TX,TY,TZ[,FOV] (position, target, degrees), "
                      "got '{}'", opt.camera);
        return 2;
    }
    facet::PluginRegistry registry;
    for (const std::string& dir : opt.plugin_paths) registry.add_scene_path(dir);
    registry.probe_first_loads(opt.probe_time);
    const std::string path =
        opt.scene.empty() ? facet::default_scene_path().string() : opt.scene;
    facet::Scene scene = facet::load_scene(path, registry);
    std::vector<facet::ShaderProject> projects;
    if (opt.rebuild && (projects = facet::rebuild_projects(registry.search_path())).empty()) {
        spdlog::error("{}", facet::nothing_to_rebuild());
        return 2;
    }
    render(opt, scene, size, interrupts);
    if (opt.watch) watch(opt, registry, scene, size, std::move(projects), interrupts);
    return interrupts.exit_code();
}

}  // namespace

int main(int argc, char** argv) {
    const facet::Interrupts interrupts("facet-render");  // before any thread starts
    facet::report_plugin_faults();
    Options opt;
    CLI::App app{"Renders a facet scene headless to a PNG.", "facet-render"};
    app.add_option("scene", opt.scene, "scene file (YAML), or a model file to render framed and lit; default: the default scene");
    app.add_option("-o,--output", opt.output,
                   "output PNG; - is standard output, and a device or FIFO is written in place")
        ->capture_default_str();
    app.add_option("--size", opt.size, "image size WxH, overriding the scene's");
    app.add_option("--camera", opt.camera,
                   "camera X,Y,Z,TX,TY,TZ[,FOV]: position, target, vertical fov in degrees");
    app.add_option("--msaa", opt.msaa, "samples per pixel, overriding the scene's")
        ->check(CLI::IsMember({1, 2, 4, 8}));
    app.add_option("--threads", opt.threads,
                   "render threads, counting the main one; 0: FACET_NUM_THREADS, else one per "
                   "hardware thread")
        ->check(CLI::Range(0, 256))
        ->capture_default_str();
    app.add_option("--max-memory", opt.max_memory,
                   "memory budget for a target, texture or mesh, e.g. 8G (default: half of RAM, "
                   "or FACET_MAX_MEMORY)");
    app.add_flag("--wireframe", opt.wireframe, "draw triangle edges over the shading");
    CLI::Option* time = app.add_option("--time", opt.time, "seconds: pose the scene's animation "
                                                            "at this time (default: its start)")
                            ->check(CLI::Range(0.0, 1e9));
    CLI::Option* frames =
        app.add_option("--frames", opt.frames,
                       "render frames A..B (or N, or all: the scene's animation) of a sequence, "
                       "frame k at time k / fps, each to -o's pattern (out_%04d.png)")
            ->excludes(time);
    app.add_option("--fps", opt.fps, "frames a second of a sequence (default: the scene's, or 30)")
        ->check(CLI::Range(0.001, 1000.0))
        ->needs(frames);
    app.add_flag("--resume", opt.resume, "skip the frames of a sequence whose files exist")
        ->needs(frames);
    app.add_option("--band-rows", opt.band_rows,
                   "render the image in bands of this many rows (rounded up to a multiple of "
                   "64), streamed into the PNG: bounded memory for any size")
        ->check(CLI::Range(1, facet::Framebuffer::kMaxSize))
        ->excludes(frames);
    app.add_option("--plugin-path", opt.plugin_paths, "extra folder to search for shaders");
    app.add_flag("--watch", opt.watch, "keep running; render again when files change");
    app.add_flag("--rebuild", opt.rebuild,
                 "with --watch: rebuild a shader when its sources change (the built-in ones, "
                 "and projects whose build folder is a plugin folder)")
        ->needs("--watch");
    frames->excludes("--watch");
    facet::add_plugin_guard_options(app, opt.plugin_guards);
    facet::Verbosity verbosity;
    facet::add_common_options(app, verbosity);
    if (const std::optional<int> status = facet::parse_command_line(app, argc, argv)) return *status;
    facet::start_logging(verbosity);
    opt.probe_time =
        facet::start_plugin_guards(opt.plugin_guards, facet::PluginWatchdog::OnStall::end_process);
    if (const std::string bad = facet::check_finite_times(opt.time, opt.fps); !bad.empty()) {
        spdlog::error("{}", bad);
        return 2;
    }
    if (!opt.frames.empty()) {
        if (app.count("--output") == 0) opt.output = "facet_%04d.png";
        if (const std::string error = facet::check_frame_pattern(opt.output); !error.empty()) {
            spdlog::error("-o: {}", error);
            return 2;
        }
    }
    try {
        return run(opt, interrupts);
    } catch (const facet::Error& e) {
        if (e.code() == facet::ErrorCode::interrupted || interrupts.stopped()) {
            spdlog::warn(opt.frames.empty() ? "stopped; no image written"
                                            : "stopped; the frames written are kept (--resume "
                                              "goes on from them)");
            return interrupts.exit_code();
        }
        spdlog::error("{}", e.what());
    } catch (const std::bad_alloc&) {
        spdlog::error("{}", facet::out_of_memory_text());
    } catch (const std::system_error& e) {  // a thread or a mapping refused at the cap
        if (facet::address_space_cap() && (e.code() == std::errc::resource_unavailable_try_again ||
                                           e.code() == std::errc::not_enough_memory))
            spdlog::error("{}: {}", e.what(), facet::out_of_memory_text());
        else
            spdlog::error("unexpected error: {}", e.what());
    } catch (const std::exception& e) {
        spdlog::error("unexpected error: {}", e.what());
    }
    return 1;
}
