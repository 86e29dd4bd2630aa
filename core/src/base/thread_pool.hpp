// A persistent pool of worker threads for data-parallel loops.
//
// parallel_for(n, fn) calls fn(i, worker) for every i in [0, n), spread over
// the pool's workers and the calling thread, and returns when all calls are
// done. `worker` (0 .. size() - 1) identifies the thread, for per-thread
// scratch and statistics. Items are handed out one at a time from an atomic
// counter, so uneven items balance themselves. It allocates nothing per
// call. A pool of size 1 runs everything on the caller.
//
// A frame is dozens of short loops (clears, vertex batches, setup chunks,
// tiles, the AO pass's stages) with a little serial work between them. A
// worker that slept between two of them would have to be woken by the
// system, which on a virtual machine takes tens of microseconds a loop, so
// each thread waits spinning for kSpin before it sleeps: a worker for the
// next loop, the caller for the workers' last items. A pool of more threads
// than the machine has never spins: a spinning thread would hold a core
// that one with work to do is waiting for.
#pragma once

#include <atomic>
#include <chrono>
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

    // How long a thread spins for what it waits for before it sleeps.
    static constexpr std::chrono::microseconds kSpin{200};
    bool spins() const { return spin_; }

private:
    using Trampoline = void (*)(void*, int, int);
    void run(int n, Trampoline call, void* fn);
    void work(int worker);
    void drain(int worker);

    std::vector<std::thread> workers_;
    bool spin_ = false;
    // Sleepers wait on these; a waker changes what they wait for under the
    // mutex, or takes the mutex between the change and the notify, so that
    // no wake-up is lost.
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::atomic<unsigned> generation_{0};  // bumped per job, once the job is set
    std::atomic<int> busy_{0};             // workers still in the current job
    std::atomic<bool> stopping_{false};
    // The current job: set before generation_ is bumped, read after.
    Trampoline call_ = nullptr;
    void* fn_ = nullptr;
    int count_ = 0;
    std::atomic<int> next_{0};
};

}  // namespace facet
