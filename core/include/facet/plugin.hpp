// Shader plugins: loading, ABI checks, and finding them by name.
//
// A ShaderPlugin is one loaded plugin library (or, for tests and embedders,
// a descriptor compiled into the host): a material shader, or a screen pass,
// which the scene's post chain runs. load() refuses a library built for
// another ABI major version (naming it: an ABI 1 plugin is told to be
// rebuilt), or whose descriptor is too small or inconsistent, with an Error
// that says why. The library stays loaded while any shared_ptr to its
// ShaderPlugin lives.
//
// A PluginRegistry finds a plugin by name as "<name>.so" on its search path:
// the build's plugin folder first, then the folders a scene names, then
// those in FACET_PLUGIN_PATH (colon-separated). It never dlopen()s the file
// it finds: it loads a private copy (NAME.<generation>.so in a folder of its
// own), so a compiler can overwrite the original while it is in use, and a
// reload gets a new handle rather than the one dlopen() cached.
#pragma once

#include "facet/isa.hpp"

#include <facet/shader_abi.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace facet {

class ShaderPlugin {
public:
    // Loads the shared library at `path`. If `expected_name` is given, the
    // descriptor's name must match it. If `private_copy` is given, `path` is
    // first copied there and the copy is loaded (and deleted with the plugin).
    // Throws Error(plugin_*).
    static std::shared_ptr<ShaderPlugin> load(const std::filesystem::path& path,
                                              std::string_view expected_name = {},
                                              const std::filesystem::path& private_copy = {});
    // Wraps a descriptor that lives in this process. Validated as load() does.
    static std::shared_ptr<ShaderPlugin> from_descriptor(const facet_plugin_desc* desc,
                                                         std::string origin);

    ~ShaderPlugin();
    ShaderPlugin(const ShaderPlugin&) = delete;
    ShaderPlugin& operator=(const ShaderPlugin&) = delete;

    // The host's own copies of the plugin's descriptors: fields past a
    // record's struct_size read as zero, as does the shader record of a
    // screen pass and the pass record of a shader.
    const facet_plugin_desc& desc() const { return desc_; }
    const facet_schema& schema() const { return desc_.schema; }
    const facet_shader_desc& shader_desc() const { return shader_; }
    const std::string& name() const { return name_; }
    const std::string& origin() const { return origin_; }  // file it came from
    // The fragment function to call on instruction-set path `isa`: the
    // entry of the widest instruction set the plugin has that the path allows.
    facet_fragment_fn fragment_for(Isa isa) const { return fragment_[int(isa)]; }
    bool is_post() const { return pass_ != nullptr; }
    facet_pass_fn pass() const { return pass_; }  // a screen pass's function
    uint32_t needs() const { return shader_.needs; }
    bool needs(facet_need need) const { return (shader_.needs & need) != 0; }
    uint32_t varying_floats() const { return varying_floats_; }
    // The varying floats a draw with parameter block `params` reads, a
    // prefix of them: all but the conditional varyings when their condition
    // is 0 (facet_shader_desc.conditional_varyings).
    uint32_t read_floats(const void* params) const;
    // facet_interpolation of each varying float.
    const uint8_t* float_interpolation() const { return float_interpolation_; }
    // Index of the first varying float of texture slot `slot`'s UV.
    int texture_uv_float(int slot) const { return texture_uv_float_[slot]; }
    // Index of the first varying float of the second UV set (ABI 2.1,
    // facet_shader_desc.second_uv), or -1: the shader has none.
    int second_uv_float() const { return second_uv_float_; }
    // The UV float a texture slot is sampled at for a binding of UV set
    // `set` (0 or 1; -1 where there is none).
    int texture_uv_float(int slot, int set) const {
        return set == 0 || texture_uv_float_[slot] < 0 ? texture_uv_float_[slot] : second_uv_float_;
    }

    // Schema look-ups.
    const facet_param_desc* find_param(std::string_view name) const;
    // Index (0-based, in declaration order) of each TEXTURE parameter: its slot.
    int texture_slot(const facet_param_desc& param) const;
    int texture_count() const { return texture_count_; }
    // Whether `pc` is in the plugin's own code (its executable segments);
    // false for a plugin made from a descriptor. Async-signal-safe.
    bool runs_code_at(uintptr_t pc) const { return pc >= code_begin_ && pc < code_end_; }
    // "base_color (color4), base_texture (texture)", for error messages.
    std::string describe_params() const;

private:
    ShaderPlugin() = default;
    void adopt(const facet_plugin_desc* desc);
    void adopt_fragments();

    void* handle_ = nullptr;
    uintptr_t code_begin_ = 0, code_end_ = 0;  // its executable segments, once loaded
    std::filesystem::path private_copy_;
    facet_plugin_desc desc_{};
    facet_shader_desc shader_{};
    facet_pass_fn pass_ = nullptr;
    facet_fragment_fn fragment_[3] = {};  // by Isa
    std::string name_;
    std::string origin_;
    uint32_t varying_floats_ = 0;
    uint32_t unconditional_floats_ = 0;  // the floats before the conditional varyings
    int texture_count_ = 0;
    uint8_t float_interpolation_[FACET_MAX_VARYING_FLOATS] = {};
    int texture_uv_float_[FACET_MAX_TEXTURES] = {};
    int second_uv_float_ = -1;
};

// Checks a descriptor against this host's ABI and limits.
// Throws Error(plugin_abi_mismatch | plugin_struct_size | plugin_invalid).
void validate_descriptor(const facet_plugin_desc* desc, const std::string& origin);

// Whether a plugin file is whole: an ELF-64 file whose headers and loaded
// segments fit in it. A linker still writing it may leave it otherwise for
// a while (hot reload waits; loading refuses it).
bool plugin_file_complete(const std::filesystem::path& path);

// The name of a facet_param_type ("color4").
std::string_view param_type_name(uint32_t type);
// Floats a parameter type stores; 0 for the int32 types (INT, BOOL,
// TEXTURE, CHOICE).
int param_float_count(uint32_t type);
// The names of a CHOICE parameter, from its "a|b|c" (shader_abi.h).
std::vector<std::string> choice_names(std::string_view choices);

// The needs this host can serve; a plugin asking for others is refused.
constexpr uint32_t kSupportedNeeds = FACET_NEED_NORMALS | FACET_NEED_UVS | FACET_NEED_COLORS |
                                     FACET_NEED_TANGENTS | FACET_NEED_LIGHTS | FACET_NEED_TEXTURES |
                                     FACET_NEED_SHADOW_MAP | FACET_NEED_AO |
                                     FACET_NEED_DERIVATIVES | FACET_NEED_BLENDING |
                                     FACET_NEED_DISCARD | FACET_NEED_UV1;

// A registry loads each plugin from a private copy, in a folder of its own
// in the temp folder (facet-plugins-PID-N), which its destructor removes.
// The first registry a process makes removes the folders of processes that
// no longer run (killed, or crashed). remove_private_plugin_copies()
// removes this process's folders, for a program about to exit at once
// (after a signal), whose destructors will not run.
void remove_private_plugin_copies();

// Makes a crash in plugin code say where it happened. Installs handlers for
// SIGSEGV, SIGBUS, SIGILL, SIGFPE and SIGABRT that, when the crashing
// thread is running a plugin's code, write to stderr which plugin (name and
// file) and which of its functions: loading (its static constructors), its
// entry point, vertex, fragment, or unloading. The process then ends as it
// would have: the handler that was there before (the default, or a
// sanitizer's) takes the signal. Plugin code that calls exit() on a thread
// running a plugin call (not on a thread the plugin started) is named the
// same way, and the process ends with status 70 rather than the status the
// plugin gave (an atexit handler; static destructors registered after it
// run first). For programs, once, early in main(): a library should not
// take its host's signals.
void report_plugin_faults();

// A watchdog for plugin calls. A call into a plugin (loading it, its entry
// point, its vertex, fragment or post function, unloading it) that has not
// returned within `limit` is named on stderr: which plugin, which function,
// and the limit. Then:
//   end_process    the process ends with status 70 (facet-render, and each
//                  rank of facet-render-mpi, whose job then ends);
//   abandon_frame  the stalled vertex, fragment or post call is returned
//                  from (by a signal to its thread, SIGRTMIN + 2, once the
//                  thread runs the plugin's own code), the frame's other
//                  plugin calls are skipped, and Renderer::render throws
//                  ErrorCode::plugin_stalled (the viewer keeps its last
//                  good frame). The plugin's own stack is left as it was:
//                  what it allocated there leaks. A stall while loading or
//                  unloading, and a call that cannot be returned from
//                  within 2 s more (it waits in a system call, say), end
//                  the process as above.
// For programs, once, early in main(); later calls change nothing. A limit
// of 0 starts no watchdog.
struct PluginWatchdog {
    std::chrono::milliseconds limit{10000};
    enum class OnStall { end_process, abandon_frame } on_stall = OnStall::end_process;
};
void watch_plugin_calls(const PluginWatchdog& watchdog);

class PluginRegistry {
public:
    // Starts with the built-in plugins' folders (facet/paths.hpp), then
    // FACET_PLUGIN_PATH.
    PluginRegistry();
    explicit PluginRegistry(std::vector<std::filesystem::path> search_path);
    ~PluginRegistry();
    PluginRegistry(const PluginRegistry&) = delete;
    PluginRegistry& operator=(const PluginRegistry&) = delete;

    // Adds a folder named by a scene; searched after the build's folder and
    // before FACET_PLUGIN_PATH.
    void add_scene_path(const std::filesystem::path& folder);
    std::vector<std::filesystem::path> search_path() const;

    // The plugin called `name`, loaded on first use and cached.
    // Throws Error(unknown_shader) listing the folders searched, or the
    // load error of the file found.
    std::shared_ptr<ShaderPlugin> get(const std::string& name);
    // Where `name` would be loaded from; empty if not found. get() warns,
    // naming both files, when a plugin of the same name later on the search
    // path is shadowed by the one found: shadowed() lists those.
    std::filesystem::path locate(const std::string& name) const;
    std::vector<std::filesystem::path> shadowed(const std::string& name) const;

    // Loads `name` again from disk, as a new private copy, without touching
    // the cache: the caller checks it, then commits it with add().
    std::shared_ptr<ShaderPlugin> load_fresh(const std::string& name);

    // From now on, get() first draws a probe frame with each plugin it has
    // not loaded before, in facet-sandbox (../libexec beside the program),
    // with `time_limit` for each call into the plugin (the watchdog's, in
    // the sandbox) and the memory budget: a sphere (or, for a screen
    // pass, a cleared frame) in its default parameters. A plugin that
    // crashes there, calls exit() or _exit(), loops, or allocates without
    // bound is refused (Error(plugin_load_failed) naming what happened)
    // before it runs in this process. Plugins in facet's own folders
    // (facet/paths.hpp) are not probed. 0 ms: no probe (the default).
    void probe_first_loads(std::chrono::milliseconds time_limit);

    // Registers a plugin under its name, replacing any loaded before (tests,
    // embedders, and hot reload committing a load_fresh()).
    void add(std::shared_ptr<ShaderPlugin> plugin);
    bool is_loaded(const std::string& name) const { return loaded_.count(name) != 0; }

private:
    static constexpr int kProbeWidth = 64;
    static constexpr std::chrono::seconds kProbeStart{5};  // the sandbox's start, at most
    void probe(const std::string& name) const;
    std::filesystem::path next_private_copy(const std::string& name);
    // Every <name>.so on the search path, in search order.
    std::vector<std::filesystem::path> files_named(const std::string& name) const;

    std::vector<std::filesystem::path> build_paths_;
    std::vector<std::filesystem::path> scene_paths_;
    std::vector<std::filesystem::path> env_paths_;
    std::map<std::string, std::shared_ptr<ShaderPlugin>, std::less<>> loaded_;
    std::filesystem::path private_dir_;  // created on first load
    unsigned generation_ = 0;
    std::chrono::milliseconds probe_time_{0};
};

}  // namespace facet
