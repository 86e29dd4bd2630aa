// A persistent pool of worker threads for data-parallel loops.
//
// parallel_for(n, fn) calls fn(i, worker) for every i in [0, n), spread over
// the pool's workers and the calling thread, and returns when all calls are
// done. `worker` (0 .. size() - 1) identifies the thread, for per-thread
// scratch and statistics. Items are handed out one at a time from an atomic
// counter, so uneven items balance themselves. It allocates nothing per
// call. A pool of size 1 runs everything on the caller.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace facet {

class ThreadPool {
public:
    // `threads` counts the caller; 0 means every hardware thread.
    explicit ThreadPool(int threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int size() const { return int(workers_.size()) + 1; }

    template <class Fn>
    void parallel_for(int n, Fn&& fn) {
        run(n, [](void* f, int i, int worker) { (*static_cast<Fn*>(f))(i, worker); }, &fn);
    }

private:
    using Trampoline = void (*)(void*, int, int);
    void run(int n, Trampoline call, void* fn);
    void work(int worker);
    void drain(int worker);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    unsigned generation_ = 0;  // bumped per job
    int busy_ = 0;             // workers still in the current job
    bool stopping_ = false;
    // The current job.
    Trampoline call_ = nullptr;
    void* fn_ = nullptr;
    int count_ = 0;
    std::atomic<int> next_{0};
};

}  // namespace facet
