// Rebuilding shader plugins when their sources change (the --rebuild mode).
//
// A ShaderRebuilder watches one folder per shader (SOURCES/NAME/) and, when
// a file in it changes, runs that shader's build command on a background
// thread: by default `cmake --build BUILD --target facet_shader_NAME`. The
// build writes NAME.so into a plugin folder, where HotReload picks it up like
// any other new version. update() reports builds started and finished; a
// failed build's event carries the compiler's output, and the plugin that
// was loaded keeps rendering.
#pragma once

#include "facet/file_watcher.hpp"
#include "facet/hot_reload.hpp"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace facet {

class ShaderRebuilder {
public:
    // The shell command that builds shader `name`; its output is captured.
    using Command = std::function<std::string(const std::string& name)>;

    // Watches every folder in `sources` (one per shader, named after it).
    ShaderRebuilder(const std::filesystem::path& sources, Command command,
                    FileWatcher::Options options = {});
    ~ShaderRebuilder();  // waits for a running build

    // `cmake --build build_dir --target facet_shader_NAME`.
    static Command cmake_target(const std::filesystem::path& build_dir);

    // Starts builds for shaders whose sources changed (one at a time per
    // shader) and returns the events since the last call.
    std::vector<ReloadEvent> update();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The built-in shaders' sources (shaders/ in data_dir(), facet/paths.hpp)
// and the build folder that builds them: the one the running program was
// built in (its folder's parent).
std::filesystem::path built_in_shader_sources();
std::filesystem::path build_folder();

}  // namespace facet
