#include "facet/plugin.hpp"

#include "facet/error.hpp"
#include "facet/paths.hpp"
#include "facet/output.hpp"
#include "base/files.hpp"
#include "base/signal_stack.hpp"
#include "plugin/descriptor.hpp"
#include "plugin/plugin_calls.hpp"

#include <spdlog/spdlog.h>

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>
#include <elf.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

namespace facet {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void refuse(ErrorCode code, const std::string& origin, const std::string& why) {
    throw Error(code, why, origin);
}

// Why `path` is not a whole ELF-64 file, or nothing if it is.
std::optional<std::string> elf_incomplete(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    Elf64_Ehdr eh{};
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    if (ec) return "cannot read it: " + ec.message();
    if (!in.read(reinterpret_cast<char*>(&eh), sizeof eh) ||
        std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 || eh.e_ident[EI_CLASS] != ELFCLASS64)
        return "not a 64-bit ELF shared library";
    uint64_t needed = uint64_t(eh.e_shoff) + uint64_t(eh.e_shnum) * eh.e_shentsize;
    needed = std::max<uint64_t>(needed, eh.e_phoff + uint64_t(eh.e_phnum) * eh.e_phentsize);
    for (int i = 0; i < eh.e_phnum && needed <= size; ++i) {
        Elf64_Phdr ph{};
        in.seekg(std::streamoff(eh.e_phoff + uint64_t(i) * eh.e_phentsize));
        if (!in.read(reinterpret_cast<char*>(&ph), sizeof ph)) break;
        if (ph.p_type == PT_LOAD) needed = std::max<uint64_t>(needed, ph.p_offset + ph.p_filesz);
    }
    if (needed > size)
        return "file is truncated (" + std::to_string(size) + " bytes, its headers need " +
               std::to_string(needed) + "); is it still being written?";
    return std::nullopt;
}

// dlopen() maps a library's segments straight from the file; a segment
// that runs past the end of a truncated file (a compiler still writing it)
// faults with SIGBUS on first touch. Refuse such a file before dlopen.
void check_elf_complete(const fs::path& path, const std::string& origin) {
    if (const std::optional<std::string> why = elf_incomplete(path))
        refuse(ErrorCode::plugin_load_failed, origin, *why);
}

// A library with no facet_plugin_entry: an ABI 1 plugin (which exported
// facet_shader_entry, its descriptor starting with the ABI it was built
// for), or no plugin at all.
[[noreturn]] void refuse_without_entry(const ShaderPlugin& plugin, void* handle,
                                       const std::string& origin) {
    using Abi1Entry = const uint16_t* (*)(void);  // abi_major, abi_minor first
    if (auto old = reinterpret_cast<Abi1Entry>(dlsym(handle, FACET_ABI1_ENTRY_SYMBOL))) {
        const uint16_t* version = nullptr;
        {
            const InPlugin in_entry(&plugin, PluginEntry::entry_point);
            version = old();
        }
        const std::string abi = version ? std::to_string(version[0]) + "." +
                                              std::to_string(version[1])
                                        : std::string("1");
        refuse(ErrorCode::plugin_abi_mismatch, origin,
               "built for ABI " + abi + " (it exports '" FACET_ABI1_ENTRY_SYMBOL
               "'); this host speaks ABI " + std::to_string(FACET_ABI_MAJOR) + "." +
                   std::to_string(FACET_ABI_MINOR) +
                   ": rebuild the plugin against this facet SDK (facet_add_shader() in CMake)");
    }
    refuse(ErrorCode::plugin_no_entry, origin,
           "no exported symbol '" FACET_PLUGIN_ENTRY_SYMBOL "' (use FACET_SHADER(...) or "
           "FACET_POST(...))");
}

}  // namespace

// ---- ShaderPlugin ------------------------------------------------------------

std::shared_ptr<ShaderPlugin> ShaderPlugin::load(const fs::path& path,
                                                 std::string_view expected_name,
                                                 const fs::path& private_copy) {
    const std::string origin = path.string();
    require_regular_file(path);
    std::shared_ptr<ShaderPlugin> plugin(new ShaderPlugin);
    plugin->origin_ = origin;
    fs::path file = path;
    if (!private_copy.empty()) {
        std::error_code ec;
        fs::copy_file(path, private_copy, fs::copy_options::overwrite_existing, ec);
        if (ec) refuse(ErrorCode::plugin_load_failed, origin, "cannot copy: " + ec.message());
        plugin->private_copy_ = file = private_copy;  // deleted by the destructor
    }
    check_elf_complete(file, origin);
    // RTLD_LOCAL keeps each plugin's symbols to itself; RTLD_NOW reports a
    // missing symbol here rather than at the first draw.
    {
        const InPlugin loading(plugin.get(), PluginEntry::load);  // its static constructors run
        plugin->handle_ = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    }
    if (!plugin->handle_) refuse(ErrorCode::plugin_load_failed, origin, dlerror());
    void* handle = plugin->handle_;
    auto entry =
        reinterpret_cast<facet_plugin_entry_fn>(dlsym(handle, FACET_PLUGIN_ENTRY_SYMBOL));
    if (!entry) refuse_without_entry(*plugin, handle, origin);
    const facet_plugin_desc* desc = nullptr;
    {
        const InPlugin in_entry(plugin.get(), PluginEntry::entry_point);
        desc = entry();
    }
    validate_descriptor(desc, origin);
    if (!expected_name.empty() && expected_name != desc->name)
        refuse(ErrorCode::plugin_invalid, origin,
               "file is named '" + std::string(expected_name) + "' but the plugin calls itself '" +
                   desc->name + "'");
    plugin->adopt(desc);
    spdlog::debug("loaded {} '{}' {} from {}", plugin->is_post() ? "screen pass" : "shader",
                 plugin->name_,
                 desc->version ? desc->version : "", origin);
    return plugin;
}

std::shared_ptr<ShaderPlugin> ShaderPlugin::from_descriptor(const facet_plugin_desc* desc,
                                                            std::string origin) {
    validate_descriptor(desc, origin);
    std::shared_ptr<ShaderPlugin> plugin(new ShaderPlugin);
    plugin->origin_ = std::move(origin);
    plugin->adopt(desc);
    return plugin;
}

// Keeps host-owned copies of the descriptor's records (zero past each
// one's struct_size), the fragment function each path calls, and the
// per-float tables every draw uses.
void ShaderPlugin::adopt(const facet_plugin_desc* desc) {
    const DescriptorCopy c = copy_descriptor(*desc);
    desc_ = c.plugin;
    shader_ = c.shader;
    pass_ = c.pass.run;
    name_ = desc_.name;
    adopt_fragments();
    int first_float[FACET_MAX_VARYINGS] = {};
    varying_floats_ = 0;
    for (uint32_t v = 0; v < shader_.varying_count; ++v) {
        first_float[v] = int(varying_floats_);
        if (v == shader_.varying_count - shader_.conditional_varyings)
            unconditional_floats_ = varying_floats_;
        for (uint32_t k = 0; k < shader_.varyings[v].components; ++k)
            float_interpolation_[varying_floats_++] = uint8_t(shader_.varyings[v].interpolation);
    }
    if (shader_.conditional_varyings == 0) unconditional_floats_ = varying_floats_;
    texture_count_ = 0;
    for (uint32_t i = 0; i < schema().param_count; ++i)
        if (schema().params[i].type == FACET_PARAM_TEXTURE) {
            const int32_t uv = schema().params[i].uv_varying;  // -1: only the shader samples it
            texture_uv_float_[texture_count_++] = uv >= 0 ? first_float[uv] : -1;
        }
}

// Each path's fragment function: the entry of the widest instruction set
// the path allows (validate_descriptor made sure of the baseline's).
void ShaderPlugin::adopt_fragments() {
    facet_fragment_fn by_isa[FACET_ISA_X86_64_V4 + 1] = {};
    for (uint32_t i = 0; i < shader_.fragment_count; ++i)
        if (shader_.fragments[i].isa <= FACET_ISA_X86_64_V4)
            by_isa[shader_.fragments[i].isa] = shader_.fragments[i].fragment;
    fragment_[int(Isa::portable)] = by_isa[FACET_ISA_BASELINE];
    fragment_[int(Isa::avx2)] = by_isa[FACET_ISA_X86_64_V3] ? by_isa[FACET_ISA_X86_64_V3]
                                                            : fragment_[int(Isa::portable)];
    fragment_[int(Isa::avx512)] = by_isa[FACET_ISA_X86_64_V4] ? by_isa[FACET_ISA_X86_64_V4]
                                                              : fragment_[int(Isa::avx2)];
}

ShaderPlugin::~ShaderPlugin() {
    if (handle_) {
        const InPlugin unloading(this, PluginEntry::unload);  // its static destructors run
        dlclose(handle_);
    }
    std::error_code ec;
    if (!private_copy_.empty()) fs::remove(private_copy_, ec);
}

uint32_t ShaderPlugin::read_floats(const void* params) const {
    if (shader_.conditional_varyings == 0 || !params) return varying_floats_;
    int32_t condition;  // TEXTURE and BOOL are both an int32
    std::memcpy(&condition,
                static_cast<const unsigned char*>(params) +
                    schema().params[shader_.varyings_condition].offset,
                sizeof condition);
    return condition ? varying_floats_ : unconditional_floats_;
}

const facet_param_desc* ShaderPlugin::find_param(std::string_view name) const {
    for (uint32_t i = 0; i < schema().param_count; ++i)
        if (name == schema().params[i].name) return &schema().params[i];
    return nullptr;
}

int ShaderPlugin::texture_slot(const facet_param_desc& param) const {
    int slot = 0;
    for (uint32_t i = 0; i < schema().param_count; ++i) {
        if (&schema().params[i] == &param) return param.type == FACET_PARAM_TEXTURE ? slot : -1;
        slot += schema().params[i].type == FACET_PARAM_TEXTURE;
    }
    return -1;
}

std::string ShaderPlugin::describe_params() const {
    if (schema().param_count == 0) return "(no parameters)";
    std::string out;
    for (uint32_t i = 0; i < schema().param_count; ++i) {
        if (i) out += ", ";
        out += schema().params[i].name;
        out += " (";
        out += param_type_name(schema().params[i].type);
        out += ")";
    }
    return out;
}

// ---- PluginRegistry ----------------------------------------------------------

namespace {

// FACET_PLUGIN_PATH's folders. One that is not a folder is named in a
// warning (once a process), not skipped in silence.
std::vector<fs::path> env_plugin_path() {
    std::vector<fs::path> out;
    const char* env = std::getenv("FACET_PLUGIN_PATH");
    if (!env) return out;
    static std::atomic<bool> warned{false};
    const bool warn = !warned.exchange(true);
    std::stringstream ss(env);
    for (std::string item; std::getline(ss, item, ':');) {
        if (item.empty()) continue;
        std::error_code ec;
        if (warn && !fs::is_directory(item, ec))
            spdlog::warn("FACET_PLUGIN_PATH: '{}' is not a folder; no plugins are found there",
                         item);
        out.emplace_back(item);
    }
    return out;
}

std::string join_paths(const std::vector<fs::path>& paths) {
    std::string out;
    for (const fs::path& p : paths) out += (out.empty() ? "" : ", ") + p.string();
    return out.empty() ? "(none)" : out;
}

}  // namespace

PluginRegistry::PluginRegistry()
    : build_paths_(built_in_plugin_dirs()), env_paths_(env_plugin_path()) {}

PluginRegistry::PluginRegistry(std::vector<fs::path> search_path)
    : build_paths_(std::move(search_path)) {}

void PluginRegistry::add_scene_path(const fs::path& folder) {
    for (const fs::path& p : scene_paths_)
        if (p == folder) return;
    scene_paths_.push_back(folder);
}

std::vector<fs::path> PluginRegistry::search_path() const {
    std::vector<fs::path> all = build_paths_;
    all.insert(all.end(), scene_paths_.begin(), scene_paths_.end());
    all.insert(all.end(), env_paths_.begin(), env_paths_.end());
    return all;
}

std::vector<fs::path> PluginRegistry::files_named(const std::string& name) const {
    std::vector<fs::path> found;
    for (const fs::path& dir : search_path()) {
        fs::path candidate = dir / (name + ".so");
        std::error_code ec;
        if (!fs::is_regular_file(candidate, ec)) continue;
        // A folder named twice (FACET_PLUGIN_PATH and the build's) is one file.
        const bool seen = std::any_of(found.begin(), found.end(), [&](const fs::path& f) {
            std::error_code e;
            return fs::equivalent(f, candidate, e);
        });
        if (!seen) found.push_back(std::move(candidate));
    }
    return found;
}

fs::path PluginRegistry::locate(const std::string& name) const {
    std::vector<fs::path> found = files_named(name);
    return found.empty() ? fs::path() : found.front();
}

std::vector<fs::path> PluginRegistry::shadowed(const std::string& name) const {
    std::vector<fs::path> found = files_named(name);
    if (!found.empty()) found.erase(found.begin());  // the one locate() finds
    return found;
}

PluginRegistry::~PluginRegistry() {
    // Loaded copies may outlive the registry; removing their files is safe.
    std::error_code ec;
    if (!private_dir_.empty()) fs::remove_all(private_dir_, ec);
}

namespace {

constexpr std::string_view kPrivatePrefix = "facet-plugins-";

// The process id in a private copies' folder name "facet-plugins-PID-N";
// 0 for any other name.
pid_t private_folder_owner(const std::string& name) {
    unsigned long pid = 0, n = 0;
    int end = 0;
    if (name.rfind(kPrivatePrefix, 0) != 0 ||
        std::sscanf(name.c_str() + kPrivatePrefix.size(), "%lu-%lu%n", &pid, &n, &end) != 2 ||
        size_t(end) != name.size() - kPrivatePrefix.size() || pid == 0 || pid > 0x7fffffff)
        return 0;
    return pid_t(pid);
}

// Removes this user's private copies' folders whose process `matches`;
// errors (a race with another process) leave a folder alone. (A process
// in another PID namespace that shares the temp folder, under the same
// user, would look dead from here: containers should not share /tmp.)
template <class Matches>
void remove_private_folders(Matches&& matches) {
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(fs::temp_directory_path(ec), ec)) {
        const pid_t owner = private_folder_owner(e.path().filename().string());
        struct stat info {};
        if (!owner || lstat(e.path().c_str(), &info) != 0 || info.st_uid != getuid() ||
            !S_ISDIR(info.st_mode) || !matches(owner))
            continue;
        std::error_code ignored;
        fs::remove_all(e.path(), ignored);
    }
}

bool process_runs(pid_t pid) { return kill(pid, 0) == 0 || errno == EPERM; }

}  // namespace

void remove_private_plugin_copies() {
    const pid_t self = getpid();
    remove_private_folders([&](pid_t owner) { return owner == self; });
}

fs::path PluginRegistry::next_private_copy(const std::string& name) {
    if (private_dir_.empty()) {
        static std::atomic<unsigned> registries{0};
        remove_private_folders([](pid_t owner) { return !process_runs(owner); });
        private_dir_ = fs::temp_directory_path() /
                       (std::string(kPrivatePrefix) + std::to_string(getpid()) + "-" +
                        std::to_string(registries++));
        std::error_code ec;
        fs::create_directories(private_dir_, ec);
        if (ec)
            throw Error(ErrorCode::plugin_load_failed,
                        "cannot make a folder for private copies: " + ec.message(),
                        private_dir_.string());
    }
    return private_dir_ / (name + "." + std::to_string(++generation_) + ".so");
}

std::shared_ptr<ShaderPlugin> PluginRegistry::load_fresh(const std::string& name) {
    const bool plain = !name.empty() && name.find_first_of("/\\") == std::string::npos;
    const fs::path file = plain ? locate(name) : fs::path();
    spdlog::debug("shader '{}': searched {}: {}", name, join_paths(search_path()),
                  file.empty() ? "not found" : file.string());
    if (file.empty())
        throw Error(ErrorCode::unknown_shader,
                    "'" + name + "': no " + name + ".so in " + join_paths(search_path()));
    return ShaderPlugin::load(file, name, next_private_copy(name));
}

std::shared_ptr<ShaderPlugin> PluginRegistry::get(const std::string& name) {
    if (auto it = loaded_.find(name); it != loaded_.end()) return it->second;
    std::shared_ptr<ShaderPlugin> plugin = load_fresh(name);
    for (const fs::path& hidden : shadowed(name))
        spdlog::warn("shader '{}': {} is used; {}, of the same name and later on the search "
                     "path, is not",
                     name, plugin->origin(), hidden.string());
    loaded_.emplace(name, plugin);
    return plugin;
}

void PluginRegistry::add(std::shared_ptr<ShaderPlugin> plugin) {
    loaded_[plugin->name()] = std::move(plugin);
}

// ---- fault reports -------------------------------------------------------------

thread_local PluginCall t_plugin_call;

namespace {

constexpr int kFaultSignals[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};
struct sigaction g_before[NSIG];

const char* entry_text(PluginEntry e) {
    switch (e) {
        case PluginEntry::load: return "while loading (its static constructors)";
        case PluginEntry::entry_point: return "in its entry point (" FACET_PLUGIN_ENTRY_SYMBOL ")";
        case PluginEntry::vertex: return "in its vertex function";
        case PluginEntry::fragment: return "in its fragment function";
        case PluginEntry::post: return "in its post function";
        case PluginEntry::unload: return "while unloading (its static destructors)";
        default: return "";
    }
}

const char* signal_text(int sig) {
    switch (sig) {
        case SIGSEGV: return "SIGSEGV, invalid memory access";
        case SIGBUS: return "SIGBUS, bus error";
        case SIGILL: return "SIGILL, illegal instruction";
        case SIGFPE: return "SIGFPE, arithmetic error";
        case SIGABRT: return "SIGABRT, aborted";
        default: return "a fatal signal";
    }
}

// Only async-signal-safe calls from here on: write(), unlink(), sigaction(),
// raise(), _exit().

// "facet: shader plugin 'NAME' (FILE) <event> <where>: <detail>" on stderr.
void report_call(const PluginCall& call, const char* event, const char* detail) {
    char text[1024];
    size_t used = 0;
    auto add = [&](const char* s) {
        while (*s && used + 1 < sizeof text) text[used++] = *s++;
    };
    add("facet: shader plugin ");
    if (call.plugin->name().empty()) {  // not known before its entry point returns
        add(call.plugin->origin().c_str());
    } else {
        add("'");
        add(call.plugin->name().c_str());
        add("' (");
        add(call.plugin->origin().c_str());
        add(")");
    }
    add(" ");
    add(event);
    add(" ");
    add(entry_text(call.entry));
    add(": ");
    add(detail);
    add("\n");
    for (size_t done = 0; done < used;) {
        const ssize_t n = write(STDERR_FILENO, text + done, used - done);
        if (n <= 0) break;
        done += size_t(n);
    }
}

void on_fault(int sig, siginfo_t* info, void*) {
    const PluginCall call = t_plugin_call;
    if (call.plugin) report_call(call, "crashed", signal_text(sig));
    remove_partial_outputs();  // the images this process will not finish
    // The earlier handler takes it from here: a fault repeats when its
    // instruction runs again; a signal sent by a call (abort, raise, kill)
    // is sent again, and arrives when this handler returns.
    sigaction(sig, &g_before[sig], nullptr);
    if (info->si_code <= 0) raise(sig);
}

// exit() called by plugin code (an atexit handler runs on the thread that
// called it): named, and the process ends with status 70 (EX_SOFTWARE),
// not with the plugin's status, which could claim success with no image.
// Not a signal handler: it may remove the private plugin copies too.
void on_exit_in_plugin() {
    const PluginCall call = t_plugin_call;
    if (!call.plugin) return;
    report_call(call, "called exit()", "the process ends with status 70");
    remove_partial_outputs();
    remove_private_plugin_copies();
    _exit(70);
}

}  // namespace

void report_plugin_faults() {
    // A stack of its own for this thread (the pool's workers make theirs),
    // so that a stack overflow in a plugin can still be reported.
    static const SignalStack stack;
    struct sigaction action {};
    action.sa_sigaction = on_fault;
    action.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&action.sa_mask);
    for (const int sig : kFaultSignals) sigaction(sig, &action, &g_before[sig]);
    static const bool exit_watched = std::atexit(on_exit_in_plugin) == 0;
    (void)exit_watched;
}

bool plugin_file_complete(const fs::path& path) { return !elf_incomplete(path); }

}  // namespace facet
