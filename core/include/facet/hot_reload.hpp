// Hot reload of shader plugins and config files.
//
// A HotReload watches a scene's files (the scene, its material files) and
// the plugin folders, and applies what changed when update() is called:
// call it between frames, on the thread that renders. For a changed plugin
// it
//   1. waits until the file has stopped changing (`settle`),
//   2. renders a small trial frame of the scene file with the new version,
//      in facet-sandbox with a time limit (`trial_time`; core/src/base/
//      isolated.hpp), when a material of the scene uses the plugin: a version that crashes (in its
//      constructors, entry point, vertex or fragment function) or does not
//      finish is refused with the reason, and this process never loads it,
//   3. loads a private, versioned copy of it (PluginRegistry::load_fresh),
//   4. checks the ABI, and the parameter schema against every material
//      that uses the plugin,
//   5. swaps the new version in for all those materials.
// The old library is unloaded when the last reference to it goes: materials
// and frames hold shared_ptrs, so never while a frame still uses it.
// Anything that fails (a plugin that will not load, a schema that no longer
// fits a material, a YAML error) is refused with an event that says why,
// and the last good version keeps rendering.
//
// A plugin that appears in a plugin folder is available by name at once;
// if the scene had failed to load, it is tried again.
//
// The scene's meshes, textures and environment are watched too. A changed
// texture is read again and swapped into every material that uses it; a
// changed environment image is read and prefiltered again; a changed mesh
// reads the scene again, whole (its parts and its own materials may have
// changed). A file that will not load is refused, and the last good
// version stays.
//
// Changes are told by content: each file's digest as last applied is kept,
// and a file written again with the same bytes (a save with no edit, a
// link that gives the same library) is not applied again.
#pragma once

#include "facet/file_watcher.hpp"
#include "facet/plugin.hpp"
#include "facet/scene.hpp"
#include "facet/texture.hpp"

#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace facet {

struct ReloadEvent {
    enum class Kind {
        plugin_reloaded,  // a loaded plugin was replaced by its new version
        plugin_added,     // a new plugin file appeared
        plugin_refused,   // a new version was refused; the old one stays
        config_reloaded,  // a scene or material file was applied
        config_refused,   // a scene or material file was refused; the old one stays
        build_started,    // --rebuild: a shader's sources changed, its build runs
        build_succeeded,  // --rebuild: the build finished; the reload follows
        build_failed,     // --rebuild: the build failed; message has the compiler's output
    };
    Kind kind;
    std::string subject;  // plugin name or file
    std::string message;  // for people: what happened, or why not
    bool refused() const {
        return kind == Kind::plugin_refused || kind == Kind::config_refused ||
               kind == Kind::build_failed;
    }
};

class HotReload {
public:
    struct Options {
        FileWatcher::Options watcher;
        std::chrono::milliseconds settle{100};  // quiet time before a file counts as written
        // A plugin that is not yet a whole ELF file after `settle` (a linker
        // pausing) waits until it has been unchanged this long before it is
        // refused as broken.
        std::chrono::milliseconds unfinished{3000};
        // The trial frame: its width (its height follows the scene's
        // aspect), and how long it may take. 0 ms: no trial.
        int trial_width = 160;
        std::chrono::milliseconds trial_time{5000};
    };

    // Watches `scene` (loaded from scene.source with `registry`). Both must
    // outlive this object.
    HotReload(PluginRegistry& registry, Scene& scene);
    HotReload(PluginRegistry& registry, Scene& scene, Options options);

    // Applies settled changes. Returns true if the scene changed and should
    // be rendered again.
    bool update();

    // Events since the last call, oldest first. Each is also logged.
    std::vector<ReloadEvent> take_events();

    // True while a changed file waits to settle: keep calling update().
    bool pending() const { return !pending_.empty(); }

    // Watches the folders of the scene's files again; call after adding a
    // material file to scene.material_files (a viewer swapping materials).
    void rewatch() { watch_scene(false); }

    // `file` was just written by this program from the scene as it is in
    // memory (the viewer's editor saving): that change is not applied
    // again. A later change to it, by anyone, is.
    void written_by_us(const std::filesystem::path& file);

    FileWatcher::Backend backend() const { return watcher_.backend(); }

private:
    struct Pending {
        uintmax_t size = 0;
        std::filesystem::file_time_type time;
        std::chrono::steady_clock::time_point since;
    };

    // Watches the folders of the scene's files, and keeps their digests:
    // of all of them when `loaded_now` (the scene was just read from them),
    // else of those that have none yet.
    void watch_scene(bool loaded_now);
    void note(const std::filesystem::path& path);
    // Whether `path` holds what was last applied from it (`digest`).
    bool unchanged(const std::filesystem::path& path, std::optional<uint64_t> digest) const;
    void remember(const std::filesystem::path& path, bool loaded_now);
    bool apply(const std::filesystem::path& path);
    bool reload_plugin(const std::string& name);
    bool reload_material(const std::filesystem::path& file);
    bool reload_scene(const std::filesystem::path& cause = {});
    bool reload_asset(const std::filesystem::path& path);
    bool reload_texture(const std::filesystem::path& path);
    bool reload_environment(const std::filesystem::path& path);
    std::string trial_frame(const std::string& name);
    void report(ReloadEvent::Kind kind, std::string subject, std::string message);

    PluginRegistry& registry_;
    Scene& scene_;
    Options options_;
    FileWatcher watcher_;
    TextureCache textures_;
    std::map<std::filesystem::path, Pending> pending_;
    // written_by_us(): each file's size and time as this program left it.
    std::map<std::filesystem::path, std::pair<uintmax_t, std::filesystem::file_time_type>> ours_;
    std::vector<ReloadEvent> events_;
    bool scene_failed_ = false;
    // The scene's mesh and texture files, and each watched file's digest as
    // last applied (file_digest.hpp), by canonical path.
    std::set<std::filesystem::path> assets_;
    std::map<std::filesystem::path, uint64_t> content_;
};

}  // namespace facet
