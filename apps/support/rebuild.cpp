#include "facet/rebuild.hpp"

#include "facet/paths.hpp"

#include <spdlog/spdlog.h>

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

// Runs `command` through the shell, capturing stdout and stderr.
Result run(const std::string& command) {
    Result r;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return {-1, "cannot start: " + command};
    char buffer[4096];
    for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) r.output.append(buffer, n);
    r.status = pclose(pipe);
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
