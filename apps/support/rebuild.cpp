#include "facet/rebuild.hpp"

#include "facet/paths.hpp"

#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

namespace facet {

namespace fs = std::filesystem;

namespace {

struct Result {
    int status = -1;
    std::string output;
};

// Runs `command` through the shell, capturing stdout and stderr. The child
// starts with no signal blocked and the default actions, whatever this
// thread has (Interrupts blocks SIGINT and SIGTERM in every thread), so
// that Ctrl-C reaches the build too.
Result run(const std::string& command) {
    int out[2];
    if (pipe2(out, O_CLOEXEC) != 0) return {-1, "cannot start: " + command};
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_adddup2(&files, out[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&files, out[1], STDERR_FILENO);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    // What facet's programs block or ignore (facet/interrupts.hpp) acts
    // by default again in the build: cmake and the compilers as a shell runs them.
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXFSZ}) sigaddset(&defaults, sig);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    // Nor does the build inherit the address space cap (cap_address_space).
    const std::string uncapped = "ulimit -S -v \"$(ulimit -H -v)\" 2>/dev/null; " + command;
    const char* argv[] = {"/bin/sh", "-c", uncapped.c_str(), nullptr};
    pid_t pid = 0;
    const int failed = posix_spawn(&pid, "/bin/sh", &files, &attributes,
                                   const_cast<char* const*>(argv), environ);
    posix_spawn_file_actions_destroy(&files);
    posix_spawnattr_destroy(&attributes);
    close(out[1]);
    Result r;
    if (failed) {
        close(out[0]);
        return {-1, "cannot start: " + command};
    }
    char buffer[4096];
    for (ssize_t n; (n = read(out[0], buffer, sizeof buffer)) != 0;) {
        if (n > 0) r.output.append(buffer, size_t(n));
        else if (errno != EINTR) break;
    }
    close(out[0]);
    while (waitpid(pid, &r.status, 0) < 0 && errno == EINTR) {}
    return r;
}

// The last `lines` lines of `text`: where compilers put the error summary.
std::string tail(const std::string& text, int lines) {
    size_t at = text.size();
    for (int i = 0; i < lines && at > 0; ++i) {
        const size_t newline = text.rfind('\n', at - 1);
        if (newline == std::string::npos) return text;
        at = newline;
    }
    return text.substr(at);
}

// A file whose change means a rebuild: sources, headers and build scripts
// (not an editor's swap or backup file, nor build output).
bool is_source(const fs::path& file) {
    static const std::set<std::string> extensions = {".c",   ".cc",  ".cpp", ".cxx", ".h",
                                                      ".hh",  ".hpp", ".hxx", ".inl", ".ipp",
                                                      ".cmake"};
    return file.filename() == "CMakeLists.txt" || extensions.count(file.extension().string());
}

// "'/a/b c'", quoted for /bin/sh.
std::string quoted(const fs::path& path) {
    std::string out = "'";
    for (const char c : path.string()) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// CMakeCache.txt's value of `key` (KEY:TYPE=value), or nothing.
std::optional<std::string> cache_value(const fs::path& build_dir, const std::string& key) {
    std::ifstream in(build_dir / "CMakeCache.txt");
    for (std::string line; std::getline(in, line);)
        if (line.compare(0, key.size() + 1, key + ":") == 0) {
            const size_t eq = line.find('=');
            if (eq != std::string::npos) return line.substr(eq + 1);
        }
    return std::nullopt;
}

bool is_build_folder(const fs::path& dir) {
    std::error_code ec;
    return fs::is_regular_file(dir / "CMakeCache.txt", ec);
}

}  // namespace

std::optional<ShaderProject> ShaderProject::built_in(const fs::path& build_dir) {
    if (!is_build_folder(build_dir)) return std::nullopt;
    ShaderProject p{"built-in shaders", {}, "cmake --build " + quoted(build_dir) +
                                                " --target facet_shaders"};
    const fs::path sources = data_dir() / "shaders";
    std::error_code ec;
    p.folders.push_back(sources);
    for (const auto& entry : fs::directory_iterator(sources, ec))
        if (entry.is_directory()) p.folders.push_back(entry.path());
    return p;
}

std::optional<ShaderProject> ShaderProject::cmake_project(const fs::path& build_dir) {
    const std::optional<std::string> source = cache_value(build_dir, "CMAKE_HOME_DIRECTORY");
    if (!source || !is_build_folder(build_dir)) return std::nullopt;
    ShaderProject p{fs::path(*source).filename().string(), {fs::path(*source)},
                    "cmake --build " + quoted(build_dir)};
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(*source, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.is_directory() && !name.empty() && name[0] != '.' && !is_build_folder(entry.path()))
            p.folders.push_back(entry.path());
    }
    return p;
}

std::vector<ShaderProject> rebuild_projects(const std::vector<fs::path>& plugin_search_path) {
    std::vector<ShaderProject> out;
    std::set<fs::path> seen;
    if (auto p = ShaderProject::built_in(build_folder())) {
        out.push_back(*p);
        seen.insert(fs::weakly_canonical(build_folder()));
    }
    for (const fs::path& dir : plugin_search_path)
        if (seen.insert(fs::weakly_canonical(dir)).second)
            if (auto p = ShaderProject::cmake_project(dir)) out.push_back(*p);
    for (const ShaderProject& p : out)
        spdlog::debug("rebuild: {} from {}: {}", p.name, p.folders.front().string(), p.command);
    return out;
}

std::string nothing_to_rebuild() {
    return "--rebuild: nothing to rebuild: this program is not in a build tree (an installed "
           "facet has no build of its shaders), and no folder on the plugin search path is a "
           "CMake build folder; give your shader project's build folder with --plugin-path "
           "(or the scene's plugin_paths)";
}

struct ShaderRebuilder::Impl {
    std::vector<ShaderProject> projects;
    FileWatcher watcher;
    std::mutex mutex;
    std::set<size_t> building;          // projects with a build running
    std::set<size_t> again;             // changed again while building
    std::vector<ReloadEvent> events;
    std::map<size_t, std::thread> threads;

    Impl(std::vector<ShaderProject> p, FileWatcher::Options o)
        : projects(std::move(p)), watcher(o) {}

    void start(size_t project);
    void finish(size_t project, const Result& r);
};

void ShaderRebuilder::Impl::start(size_t project) {
    const std::string& name = projects[project].name;
    events.push_back({ReloadEvent::Kind::build_started, name, "building " + name});
    spdlog::info("rebuild: building {}", name);
    building.insert(project);
    if (auto old = threads.find(project); old != threads.end()) {
        old->second.join();  // finished: it cleared `building` before we got here
        threads.erase(old);
    }
    const std::string cmd = projects[project].command;
    threads.emplace(project, std::thread([this, project, cmd] { finish(project, run(cmd)); }));
}

void ShaderRebuilder::Impl::finish(size_t project, const Result& r) {
    std::lock_guard lock(mutex);
    const std::string& name = projects[project].name;
    if (r.status == 0) {
        spdlog::info("rebuild: {} built", name);
        events.push_back({ReloadEvent::Kind::build_succeeded, name, "built " + name});
    } else {
        spdlog::error("rebuild: {} failed to build:\n{}", name, r.output);
        events.push_back({ReloadEvent::Kind::build_failed, name,
                          name + " failed to build:\n" + tail(r.output, 20)});
    }
    building.erase(project);
}

ShaderRebuilder::ShaderRebuilder(std::vector<ShaderProject> projects, FileWatcher::Options options)
    : impl_(std::make_unique<Impl>(std::move(projects), options)) {
    for (const ShaderProject& p : impl_->projects)
        for (const fs::path& folder : p.folders) impl_->watcher.watch(folder);
}

ShaderRebuilder::~ShaderRebuilder() {
    for (auto& [project, thread] : impl_->threads) thread.join();
}

std::vector<ReloadEvent> ShaderRebuilder::update() {
    std::set<size_t> changed;
    for (const fs::path& path : impl_->watcher.take_changes()) {
        if (!is_source(path)) continue;
        const fs::path folder = fs::weakly_canonical(path.parent_path());
        for (size_t i = 0; i < impl_->projects.size(); ++i)
            for (const fs::path& watched : impl_->projects[i].folders)
                if (fs::weakly_canonical(watched) == folder) changed.insert(i);
    }
    std::lock_guard lock(impl_->mutex);
    for (const size_t project : impl_->again)
        if (!impl_->building.count(project)) changed.insert(project);
    for (const size_t project : changed) {
        if (impl_->building.count(project)) {
            impl_->again.insert(project);  // build once more when this one ends
            continue;
        }
        impl_->again.erase(project);
        impl_->start(project);
    }
    std::vector<ReloadEvent> out;
    out.swap(impl_->events);
    return out;
}

fs::path build_folder() { return (executable_dir() / "..").lexically_normal(); }

}  // namespace facet
