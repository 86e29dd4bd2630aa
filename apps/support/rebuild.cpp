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
#include <map>
#include <mutex>
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
    sigaddset(&defaults, SIGINT);
    sigaddset(&defaults, SIGTERM);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
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

}  // namespace

struct ShaderRebuilder::Impl {
    fs::path sources;
    Command command;
    FileWatcher watcher;
    std::mutex mutex;
    std::set<std::string> building;          // shaders with a build running
    std::set<std::string> again;             // changed again while building
    std::vector<ReloadEvent> events;
    std::map<std::string, std::thread> threads;

    Impl(fs::path s, Command c, FileWatcher::Options o)
        : sources(std::move(s)), command(std::move(c)), watcher(o) {}

    void start(const std::string& name);
    void finish(const std::string& name, const Result& r);
};

void ShaderRebuilder::Impl::start(const std::string& name) {
    events.push_back({ReloadEvent::Kind::build_started, name, "building shader '" + name + "'"});
    spdlog::info("rebuild: building shader '{}'", name);
    building.insert(name);
    if (auto old = threads.find(name); old != threads.end()) {
        old->second.join();  // finished: it cleared `building` before we got here
        threads.erase(old);
    }
    const std::string cmd = command(name);
    threads.emplace(name, std::thread([this, name, cmd] { finish(name, run(cmd)); }));
}

void ShaderRebuilder::Impl::finish(const std::string& name, const Result& r) {
    std::lock_guard lock(mutex);
    if (r.status == 0) {
        spdlog::info("rebuild: shader '{}' built", name);
        events.push_back({ReloadEvent::Kind::build_succeeded, name,
                          "built shader '" + name + "'"});
    } else {
        spdlog::error("rebuild: shader '{}' failed to build:\n{}", name, r.output);
        events.push_back({ReloadEvent::Kind::build_failed, name,
                          "shader '" + name + "' failed to build:\n" + tail(r.output, 20)});
    }
    building.erase(name);
}

ShaderRebuilder::ShaderRebuilder(const fs::path& sources, Command command,
                                 FileWatcher::Options options)
    : impl_(std::make_unique<Impl>(sources, std::move(command), options)) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(sources, ec))
        if (entry.is_directory()) impl_->watcher.watch(entry.path());
}

ShaderRebuilder::~ShaderRebuilder() {
    for (auto& [name, thread] : impl_->threads) thread.join();
}

ShaderRebuilder::Command ShaderRebuilder::cmake_target(const fs::path& build_dir) {
    return [build_dir](const std::string& name) {
        return "cmake --build '" + build_dir.string() + "' --target facet_shader_" + name;
    };
}

std::vector<ReloadEvent> ShaderRebuilder::update() {
    std::set<std::string> changed;
    for (const fs::path& path : impl_->watcher.take_changes())
        changed.insert(path.parent_path().filename().string());
    std::lock_guard lock(impl_->mutex);
    for (const std::string& name : impl_->again)
        if (!impl_->building.count(name)) changed.insert(name);
    for (const std::string& name : changed) {
        if (impl_->building.count(name)) {
            impl_->again.insert(name);  // build once more when this one ends
            continue;
        }
        impl_->again.erase(name);
        impl_->start(name);
    }
    std::vector<ReloadEvent> out;
    out.swap(impl_->events);
    return out;
}

fs::path built_in_shader_sources() { return data_dir() / "shaders"; }
fs::path build_folder() { return (executable_dir() / "..").lexically_normal(); }

}  // namespace facet
