// PluginRegistry (facet/plugin.hpp): the search path, loading a shader by
// name into a private copy of its file, and the private copies' folders.
#include "facet/plugin.hpp"

#include "facet/error.hpp"
#include "facet/memory.hpp"
#include "facet/paths.hpp"
#include "base/isolated.hpp"

#include <spdlog/spdlog.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace facet {

namespace fs = std::filesystem;

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

void PluginRegistry::probe_first_loads(std::chrono::milliseconds time_limit) {
    probe_time_ = time_limit;
}

// The probe frame of `name`'s file, in facet-sandbox, before its first
// load; throws why it failed.
void PluginRegistry::probe(const std::string& name) const {
    if (probe_time_.count() <= 0 || in_sandbox()) return;
    const fs::path file = locate(name);
    if (file.empty()) return;  // get() says what was searched
    std::error_code ec;
    for (const fs::path& own : built_in_plugin_dirs())
        if (fs::equivalent(file.parent_path(), own, ec)) return;  // tested with facet
    if (!sandbox_program()) {
        spdlog::warn("shader '{}' is loaded without a probe frame: facet-sandbox is not "
                     "installed beside this program", name);
        return;
    }
    const auto start = std::chrono::steady_clock::now();
    // The sandbox names a call past the limit itself; the wait allows for
    // its start (slow under a sanitizer) as well.
    const IsolatedResult r =
        run_sandboxed("probe",
                      {file.string(), std::to_string(kProbeWidth),
                       std::to_string(probe_time_.count())},
                      {memory_budget(), probe_time_ + kProbeStart});
    if (r.end == IsolatedResult::End::finished) {
        spdlog::debug("shader '{}' drew its probe frame in {:.0f} ms", name,
                      std::chrono::duration<double, std::milli>(
                          std::chrono::steady_clock::now() - start).count());
        return;
    }
    if (r.end == IsolatedResult::End::error) throw *r.error;
    throw Error(ErrorCode::plugin_load_failed,
                "its probe frame (a sphere it draws alone, in another process) failed: " +
                    r.output,
                file.string());
}

std::shared_ptr<ShaderPlugin> PluginRegistry::get(const std::string& name) {
    if (auto it = loaded_.find(name); it != loaded_.end()) return it->second;
    probe(name);
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

}  // namespace facet
