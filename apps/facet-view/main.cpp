// facet-view: the SDL2 viewer.
//
//     facet-view [SCENE.yaml] [--size WxH] [--camera X,Y,Z,TX,TY,TZ[,FOV]] [--msaa N]
//                [--max-memory SIZE] [--threads N] [--plugin-path DIR]... [--rebuild]
//                [--plugin-timeout SECONDS] [--no-probe]
//                [--frames N [--screenshot out.png] [--window-screenshot win.png]]
//                [--screenshot-dir DIR] [--no-editor] [--select NAME] [-v|-q] [--version]
//
// With no scene it opens the default scene. --frames renders N frames and
// exits (with --screenshot, saving the last one first): scripted runs and
// tests. Keys and mouse: press H in the window, or see docs/viewer.md.
#include "viewer.hpp"

#include <facet/command_line.hpp>
#include <facet/error.hpp>
#include <facet/interrupts.hpp>
#include <facet/plugin.hpp>
#include <facet/tool.hpp>

#include <spdlog/spdlog.h>

#include <atomic>

namespace {

struct Script {
    int frames = 0;
    std::string screenshot;
    std::string window_screenshot;
};

int run(facet::view::Options options, const Script& script) {
    const std::atomic<bool>* stop = options.stop;
    facet::view::Viewer viewer(std::move(options));
    viewer.keep_window(!script.window_screenshot.empty());
    if (script.frames <= 0) {
        viewer.run();
        return 0;
    }
    for (int i = 0; i < script.frames; ++i) {
        viewer.invalidate();
        if (!viewer.pump()) break;
    }
    if (!script.screenshot.empty() && !(stop && stop->load())) {  // not a frame cut short
        viewer.save_screenshot(script.screenshot);
        spdlog::info("wrote {}", script.screenshot);
    }
    if (!script.window_screenshot.empty() && !(stop && stop->load())) {
        viewer.save_window(script.window_screenshot);
        spdlog::info("wrote {}", script.window_screenshot);
    }
    if (viewer.frame_error()) throw *viewer.frame_error();  // a scripted run that did not render
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    // Before any thread starts; a signal wakes the event loop, which then
    // sees options.stop.
    const facet::Interrupts interrupts("facet-view", [] {
        SDL_Event quit{};
        quit.type = SDL_QUIT;
        SDL_PushEvent(&quit);
    });
    facet::report_plugin_faults();
    facet::view::Options options;
    options.stop = &interrupts.stop();
    Script script;
    std::string size;
    CLI::App app{"An interactive viewer and editor for facet scenes.", "facet-view"};
    app.add_option("scene", options.scene, "scene file (YAML), or a model file to render framed and lit; default: the default scene");
    app.add_option("--size", size, "window size WxH in points; default: the scene's size");
    app.add_option("--camera", options.camera,
                   "camera X,Y,Z,TX,TY,TZ[,FOV]: position, target, vertical fov in degrees");
    app.add_option("--msaa", options.msaa, "samples per pixel, overriding the scene's")
        ->check(CLI::IsMember({1, 2, 4, 8}));
    facet::PluginGuards plugin_guards;
    facet::add_plugin_guard_options(app, plugin_guards);
    std::string max_memory;
    app.add_option("--max-memory", max_memory,
                   "memory budget for a target, texture or mesh, e.g. 8G (default: half of RAM, "
                   "or FACET_MAX_MEMORY)");
    app.add_option("--threads", options.threads,
                   "render threads, counting the main one; 0: FACET_NUM_THREADS, else one per "
                   "hardware thread")
        ->check(CLI::Range(0, 256));
    app.add_option("--plugin-path", options.plugin_paths, "extra folder to search for shaders");
    app.add_flag("--rebuild", options.rebuild,
                 "rebuild a shader when its sources change (the built-in ones, and projects "
                 "whose build folder is a plugin folder)");
    app.add_option("--frames", script.frames, "render N frames, then exit")
        ->check(CLI::PositiveNumber);
    app.add_option("--screenshot", script.screenshot, "with --frames: save the last frame as PNG")
        ->needs("--frames");
    app.add_option("--window-screenshot", script.window_screenshot,
                   "with --frames: save the last window as shown (overlay, editor) as PNG")
        ->needs("--frames");
    app.add_flag("!--no-editor", options.editor, "start with the editor panel hidden (E shows it)");
    app.add_option("--select", options.select, "select the object of this name at start");
    app.add_option("--screenshot-dir", options.screenshots, "where P saves screenshots")
        ->capture_default_str();
    facet::Verbosity verbosity;
    facet::add_common_options(app, verbosity);
    if (const std::optional<int> status = facet::parse_command_line(app, argc, argv)) return *status;
    facet::start_logging(verbosity);
    // A stalled call gives up its frame: the viewer keeps its last good one.
    options.probe_time =
        facet::start_plugin_guards(plugin_guards, facet::PluginWatchdog::OnStall::abandon_frame);
    if (!facet::apply_max_memory(max_memory, options.threads)) return 2;
    if (!size.empty() && !(options.size = facet::parse_size(size))) {
        spdlog::error("--size: expected WxH with each side 1..{}, got '{}'",
                      facet::Framebuffer::kMaxSize, size);
        return 2;
    }
    try {
        const int status = run(std::move(options), script);
        return interrupts.stopped() ? interrupts.exit_code() : status;
    } catch (const facet::Error& e) {
        if (e.code() == facet::ErrorCode::interrupted || interrupts.stopped())
            return interrupts.exit_code();
        spdlog::error("{}", e.what());
    } catch (const std::bad_alloc&) {
        spdlog::error("{}", facet::out_of_memory_text());
    } catch (const std::exception& e) {
        spdlog::error("unexpected error: {}", e.what());
    }
    return 1;
}
