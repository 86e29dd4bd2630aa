// Rebuilding shader plugins when their sources change (the --rebuild mode).
//
// A ShaderRebuilder watches the source folders of one or more shader
// projects and, when a source file in one changes (C and C++ sources and
// headers, CMakeLists.txt, *.cmake), runs that project's build command on a
// background thread. The build writes NAME.so into a plugin folder, where
// HotReload picks it up like any other new version. update() reports builds
// started and finished; a failed build's event carries the compiler's
// output, and the plugin that was loaded keeps rendering.
//
// Two kinds of project are found for a program:
//   built_in()       facet's own shaders and screen passes (shaders/ in
//                    data_dir()), when the program runs from a build tree:
//                    `cmake --build BUILD --target facet_shaders`
//   cmake_project()  a shader project of one's own (facet-new-shader makes
//                    one) whose build folder is on the plugin search path
//                    (--plugin-path, a scene's plugin_paths,
//                    FACET_PLUGIN_PATH): `cmake --build BUILD`
#pragma once

#include "facet/file_watcher.hpp"
#include "facet/hot_reload.hpp"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace facet {

// Sources to watch and the command that builds them.
struct ShaderProject {
    std::string name;                           // in messages: "built-in shaders", "bands"
    std::vector<std::filesystem::path> folders; // watched, not recursively
    std::string command;                        // run by /bin/sh; its output is captured

    // facet's own shaders: every folder under data_dir()/shaders, built in
    // `build_dir` (by default the build tree the program runs from).
    // Nothing when `build_dir` holds no CMakeCache.txt (an installed facet).
    static std::optional<ShaderProject> built_in(const std::filesystem::path& build_dir);
    // The CMake project built in `build_dir`: its source folder (from
    // CMakeCache.txt) and the folders under it but build folders. Nothing
    // when `build_dir` is not a CMake build folder.
    static std::optional<ShaderProject> cmake_project(const std::filesystem::path& build_dir);
};

// The projects --rebuild rebuilds for a program whose plugins are found on
// `plugin_search_path`: the built-in shaders when it runs from a build tree,
// and each CMake build folder on the path. Empty: nothing to rebuild.
std::vector<ShaderProject> rebuild_projects(const std::vector<std::filesystem::path>& plugin_search_path);

// What to tell a user whose --rebuild found no project.
std::string nothing_to_rebuild();

class ShaderRebuilder {
public:
    explicit ShaderRebuilder(std::vector<ShaderProject> projects, FileWatcher::Options options = {});
    ~ShaderRebuilder();  // waits for a running build

    // Starts builds for projects whose sources changed (one at a time per
    // project) and returns the events since the last call.
    std::vector<ReloadEvent> update();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The folder of the build tree the running program was built in (its
// folder's parent), whether or not it is one.
std::filesystem::path build_folder();

}  // namespace facet
