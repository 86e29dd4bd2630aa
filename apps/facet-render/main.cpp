// facet-render: render a scene headless to a PNG.
//
//     facet-render [SCENE.yaml] [-o out.png] [--size WxH] [--plugin-path DIR]...
//
// With no scene, renders the default scene (configs/default.yaml).
#include <facet/error.hpp>
#include <facet/framebuffer.hpp>
#include <facet/plugin.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <string>

namespace {

struct Options {
    std::string scene;
    std::string output = "facet.png";
    std::string size;
    std::vector<std::string> plugin_paths;
    bool verbose = false;
};

// "1280x720" -> width, height; false if malformed.
bool parse_size(const std::string& text, int& width, int& height) {
    char x = 0;
    char rest = 0;
    return std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) == 3 &&
           (x == 'x' || x == 'X');
}

void report(const facet::FrameStats& s, const facet::Scene& scene) {
    spdlog::info("rendered {}x{} in {:.2f} ms: {} objects ({} culled), {} triangles in, "
                 "{} rasterized, {} clipped, {} back-facing, {} outside, {} degenerate, "
                 "{} invalid; {} fragments shaded",
                 scene.settings.width, scene.settings.height, s.milliseconds, s.objects,
                 s.objects_culled, s.triangles_in, s.triangles_rasterized, s.triangles_clipped,
                 s.triangles_culled_backface, s.triangles_culled_frustum,
                 s.triangles_culled_degenerate, s.triangles_invalid, s.fragments_shaded);
}

int run(const Options& opt) {
    facet::PluginRegistry registry;
    for (const std::string& dir : opt.plugin_paths) registry.add_scene_path(dir);
    const std::string path =
        opt.scene.empty() ? facet::default_scene_path().string() : opt.scene;
    facet::Scene scene = facet::load_scene(path, registry);
    if (!opt.size.empty()) {
        int w = 0, h = 0;
        if (!parse_size(opt.size, w, h) || w < 1 || h < 1 || w > facet::Framebuffer::kMaxSize ||
            h > facet::Framebuffer::kMaxSize) {
            spdlog::error("--size: expected WxH with each side 1..{}, got '{}'",
                          facet::Framebuffer::kMaxSize, opt.size);
            return 2;
        }
        scene.settings.width = w;
        scene.settings.height = h;
    }
    facet::Framebuffer framebuffer;
    facet::Renderer renderer;
    const facet::FrameStats stats = renderer.render(scene, framebuffer);
    framebuffer.write_png(opt.output);
    report(stats, scene);
    spdlog::info("wrote {}", opt.output);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    CLI::App app{"facet-render: render a facet scene headless to a PNG"};
    app.add_option("scene", opt.scene, "scene file (YAML); default: the default scene");
    app.add_option("-o,--output", opt.output, "output PNG")->capture_default_str();
    app.add_option("--size", opt.size, "image size WxH, overriding the scene's");
    app.add_option("--plugin-path", opt.plugin_paths, "extra folder to search for shaders");
    app.add_flag("-v,--verbose", opt.verbose, "log debug messages");
    CLI11_PARSE(app, argc, argv);
    spdlog::set_default_logger(spdlog::stderr_color_mt("facet"));
    spdlog::set_level(opt.verbose ? spdlog::level::debug : spdlog::level::info);
    try {
        return run(opt);
    } catch (const facet::Error& e) {
        spdlog::error("{}", e.what());
    } catch (const std::exception& e) {
        spdlog::error("unexpected error: {}", e.what());
    }
    return 1;
}
