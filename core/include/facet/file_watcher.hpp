// Watching files for changes, for hot reload.
//
// A FileWatcher watches folders from a background thread and queues the
// paths that changed in them: created, written and closed, moved in, or
// removed. On Linux it uses inotify; where inotify is unavailable (or when
// asked), it polls the folders' listings for changed sizes and times.
// Watching folders rather than files also catches editors and compilers
// that replace a file by renaming a new one over it.
//
// take_changes() may be called from any thread; it never blocks on the
// file system.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <set>
#include <vector>

namespace facet {

class FileWatcher {
public:
    enum class Backend { inotify, polling };

    struct Options {
        bool force_polling = false;
        std::chrono::milliseconds poll_interval{100};
        // Called on the watcher's thread whenever a change is queued, so a
        // host can sleep until then (a viewer wakes its event loop).
        std::function<void()> on_change;
    };

    FileWatcher();
    explicit FileWatcher(Options options);
    ~FileWatcher();
    FileWatcher(const FileWatcher&) = delete;
    FileWatcher& operator=(const FileWatcher&) = delete;

    // Starts watching `folder` (not recursively). Missing folders are ignored.
    void watch(const std::filesystem::path& folder);
    // Paths that changed since the last call, each once.
    std::set<std::filesystem::path> take_changes();
    Backend backend() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace facet
