#include "facet/file_watcher.hpp"

#include <spdlog/spdlog.h>

#include <sys/inotify.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>

namespace facet {

namespace fs = std::filesystem;

// What polling remembers of a file. (Not in the anonymous namespace:
// FileWatcher::Impl holds them, which in a unity build GCC warns of,
// -Wsubobject-linkage.)
struct PolledFile {
    uintmax_t size = 0;
    fs::file_time_type time;
    bool operator!=(const PolledFile& o) const { return size != o.size || time != o.time; }
};

namespace {

std::map<fs::path, PolledFile> listing(const fs::path& folder) {
    std::map<fs::path, PolledFile> out;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
        PolledFile s;
        s.size = entry.file_size(ec);
        s.time = entry.last_write_time(ec);
        if (!ec) out[entry.path()] = s;
    }
    return out;
}

}  // namespace

struct FileWatcher::Impl {
    Options options;
    Backend backend = Backend::polling;
    int inotify_fd = -1;
    int wake[2] = {-1, -1};  // pipe that interrupts the inotify thread

    std::mutex mutex;
    std::condition_variable stop_cv;
    bool stopping = false;
    std::map<int, fs::path> watches;                   // inotify descriptor -> folder
    std::map<fs::path, std::map<fs::path, PolledFile>> polled;  // folder -> listing
    std::set<fs::path> changes;
    std::thread thread;

    void run_inotify();
    void run_polling();
    void drain_inotify();
    void poll_once();
};

void FileWatcher::Impl::drain_inotify() {
    alignas(inotify_event) char buffer[16384];
    const ssize_t n = read(inotify_fd, buffer, sizeof buffer);
    bool changed = false;
    {
        std::lock_guard lock(mutex);
        for (ssize_t at = 0; at < n;) {
            const auto* e = reinterpret_cast<const inotify_event*>(buffer + at);
            auto folder = watches.find(e->wd);
            if (folder != watches.end() && e->len > 0) {
                changes.insert(folder->second / e->name);
                changed = true;
            }
            at += ssize_t(sizeof(inotify_event) + e->len);
        }
    }
    if (changed && options.on_change) options.on_change();
}

void FileWatcher::Impl::run_inotify() {
    pollfd fds[2] = {{inotify_fd, POLLIN, 0}, {wake[0], POLLIN, 0}};
    while (true) {
        if (::poll(fds, 2, -1) < 0) continue;
        if (fds[1].revents) return;
        if (fds[0].revents & POLLIN) drain_inotify();
    }
}

void FileWatcher::Impl::poll_once() {
    std::vector<fs::path> folders;
    {
        std::lock_guard lock(mutex);
        for (const auto& [folder, _] : polled) folders.push_back(folder);
    }
    bool changed = false;
    for (const fs::path& folder : folders) {
        std::map<fs::path, PolledFile> now = listing(folder);
        std::lock_guard lock(mutex);
        const size_t queued = changes.size();
        std::map<fs::path, PolledFile>& before = polled[folder];
        for (const auto& [path, stamp] : now) {
            auto it = before.find(path);
            if (it == before.end() || it->second != stamp) changes.insert(path);
        }
        for (const auto& [path, _] : before)
            if (!now.count(path)) changes.insert(path);
        before = std::move(now);
        changed |= changes.size() != queued;
    }
    if (changed && options.on_change) options.on_change();
}

void FileWatcher::Impl::run_polling() {
    std::unique_lock lock(mutex);
    while (!stop_cv.wait_for(lock, options.poll_interval, [&] { return stopping; })) {
        lock.unlock();
        poll_once();
        lock.lock();
    }
}

FileWatcher::FileWatcher() : FileWatcher(Options{}) {}

FileWatcher::FileWatcher(Options options) : impl_(std::make_unique<Impl>()) {
    impl_->options = options;
    if (!options.force_polling) {
        impl_->inotify_fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
        if (impl_->inotify_fd >= 0 && pipe(impl_->wake) == 0) {
            impl_->backend = Backend::inotify;
        } else {
            spdlog::warn("inotify unavailable; watching files by polling");
            if (impl_->inotify_fd >= 0) close(impl_->inotify_fd);
            impl_->inotify_fd = -1;
        }
    }
    Impl* impl = impl_.get();
    impl_->thread = std::thread([impl] {
        if (impl->backend == Backend::inotify) impl->run_inotify();
        else impl->run_polling();
    });
}

FileWatcher::~FileWatcher() {
    {
        std::lock_guard lock(impl_->mutex);
        impl_->stopping = true;
    }
    impl_->stop_cv.notify_all();
    if (impl_->backend == Backend::inotify) {
        const char byte = 0;
        [[maybe_unused]] ssize_t n = write(impl_->wake[1], &byte, 1);
    }
    impl_->thread.join();
    if (impl_->inotify_fd >= 0) close(impl_->inotify_fd);
    for (int fd : impl_->wake)
        if (fd >= 0) close(fd);
}

void FileWatcher::watch(const fs::path& folder) {
    std::error_code ec;
    const fs::path dir = fs::weakly_canonical(folder, ec);
    if (ec || !fs::is_directory(dir)) return;
    std::lock_guard lock(impl_->mutex);
    if (impl_->backend == Backend::polling) {
        if (!impl_->polled.count(dir)) impl_->polled[dir] = listing(dir);
        return;
    }
    const uint32_t mask = IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_DELETE | IN_MOVED_FROM;
    const int wd = inotify_add_watch(impl_->inotify_fd, dir.c_str(), mask);
    if (wd >= 0) impl_->watches[wd] = dir;
}

std::set<fs::path> FileWatcher::take_changes() {
    std::lock_guard lock(impl_->mutex);
    std::set<fs::path> out;
    out.swap(impl_->changes);
    return out;
}

FileWatcher::Backend FileWatcher::backend() const { return impl_->backend; }

}  // namespace facet
