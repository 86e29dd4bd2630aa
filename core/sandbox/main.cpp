// facet-sandbox: the process in which facet runs work it does not trust to
// end well, started by run_sandboxed() (core/src/base/isolated.hpp), which
// reads its account from stdout and what it said last from stderr. Not a
// program for people.
//
//   facet-sandbox import MEMORY FILE
//       imports a mesh file (load_mesh's isolated import)
//   facet-sandbox probe MEMORY PLUGIN WIDTH MILLISECONDS
//       loads the plugin file PLUGIN and draws a frame WIDTH pixels wide
//       with it alone (probe_frame.hpp: the trial of a plugin's first load);
//       a call into it that takes MILLISECONDS is named (the caller waits
//       that and the sandbox's start)
//   facet-sandbox trial MEMORY SCENE SHADER WIDTH [PLUGIN_FOLDER]...
//       loads shader SHADER, then the scene file with those plugin folders,
//       and renders it WIDTH pixels wide on one thread (hot reload's trial
//       frame of a new plugin version)
//
// MEMORY is the most, in bytes, the job may map beyond what the program
// maps when it starts (0: no limit).
#include "assets/mesh_import.hpp"
#include "base/isolated.hpp"
#include "probe_frame.hpp"

#include <facet/framebuffer.hpp>
#include <facet/plugin.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string trial(const fs::path& scene_file, const std::string& shader, int width,
                  const std::vector<fs::path>& folders) {
    facet::PluginRegistry registry(folders);
    registry.get(shader);  // its constructors and entry point, even if the scene left it
    facet::Scene scene = facet::load_scene(scene_file, registry);
    facet::RenderSettings& s = scene.settings;
    s.height = std::max(1, int(std::lround(double(width) * s.height / std::max(1, s.width))));
    s.width = width;
    s.msaa = 1;
    s.shadow_map_size = std::min(s.shadow_map_size, 512);
    facet::Renderer renderer(1);
    facet::Framebuffer target;
    renderer.render(scene, target);
    return {};
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() == 1 && args[0] == "--version") {
        std::printf("facet-sandbox %s (shader ABI %d.%d)\n", FACET_VERSION, FACET_ABI_MAJOR,
                    FACET_ABI_MINOR);
        return 0;
    }
    const bool import = args.size() == 3 && args[0] == "import";
    const bool probe = args.size() == 5 && args[0] == "probe";
    const bool trial_job = args.size() >= 5 && args[0] == "trial";
    if (!import && !probe && !trial_job) {
        std::fprintf(stderr, "facet-sandbox: run by facet (core/src/base/isolated.hpp), not by hand\n");
        return 2;
    }
    spdlog::set_default_logger(spdlog::stderr_color_mt("facet-sandbox"));
    facet::report_plugin_faults();
    const uint64_t memory = std::stoull(args[1]);
    int status = 0;
    if (import) {
        status = facet::serve_sandboxed([&] { return facet::import_mesh_bytes(args[2]); }, memory);
    } else if (probe) {
        facet::watch_plugin_calls({std::chrono::milliseconds(std::stoll(args[4])),
                                   facet::PluginWatchdog::OnStall::end_process});
        status = facet::serve_sandboxed(
            [&] {
                facet::probe_frame(args[2], std::stoi(args[3]));
                return std::string();
            },
            memory);
    } else {
        const std::vector<fs::path> folders(args.begin() + 5, args.end());
        status = facet::serve_sandboxed(
            [&] { return trial(args[2], args[3], std::stoi(args[4]), folders); }, memory);
    }
    facet::remove_private_plugin_copies();
    return status;
}
