#include "base/thread_pool.hpp"

#include "base/signal_stack.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace facet {

namespace {

// A hint to the core that this thread is spinning (it gives way to its
// hyper-thread sibling and saves power).
inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#elif defined(__aarch64__)
    asm volatile("yield");
#endif
}

// Spins until done() for up to ThreadPool::kSpin, if `spin`; whether it
// came.
template <class Done>
bool spin_until(bool spin, Done&& done) {
    if (!spin) return done();
    using Clock = std::chrono::steady_clock;
    const Clock::time_point until = Clock::now() + ThreadPool::kSpin;
    while (true) {
        for (int i = 0; i < 64; ++i) {  // the clock read less often than the flag
            if (done()) return true;
            pause();
        }
        if (Clock::now() >= until) return done();
    }
}

}  // namespace

ThreadPool::ThreadPool(int threads) {
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    if (threads <= 0) threads = cores;
    spin_ = threads <= cores;
    for (int w = 1; w < threads; ++w) workers_.emplace_back([this, w] { work(w); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stopping_.store(true, std::memory_order_relaxed);
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
}

// Takes items until none are left.
void ThreadPool::drain(int worker) {
    for (int i; (i = next_.fetch_add(1, std::memory_order_relaxed)) < count_;) call_(fn_, i, worker);
}

void ThreadPool::run(int n, Trampoline call, void* fn) {
    if (n <= 0) return;
    if (workers_.empty() || n == 1) {
        for (int i = 0; i < n; ++i) call(fn, i, 0);
        return;
    }
    // Every worker finished the last job (busy_ was 0), so none reads these.
    call_ = call;
    fn_ = fn;
    count_ = n;
    next_.store(0, std::memory_order_relaxed);
    busy_.store(int(workers_.size()), std::memory_order_relaxed);
    {
        std::lock_guard lock(mutex_);
        generation_.fetch_add(1, std::memory_order_release);  // publishes the job
    }
    wake_.notify_all();  // no system call unless a worker sleeps
    drain(0);
    const auto finished = [&] { return busy_.load(std::memory_order_acquire) == 0; };
    if (spin_until(spin_, finished)) return;
    std::unique_lock lock(mutex_);
    done_.wait(lock, finished);
}

void ThreadPool::work(int worker) {
    const SignalStack signal_stack;  // plugin code runs here: a fault can still be named
    unsigned seen = 0;
    while (true) {
        const auto woken = [&] {
            return stopping_.load(std::memory_order_relaxed) ||
                   generation_.load(std::memory_order_acquire) != seen;
        };
        if (!spin_until(spin_, woken)) {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, woken);
        }
        if (stopping_.load(std::memory_order_relaxed)) return;
        seen = generation_.load(std::memory_order_acquire);
        drain(worker);
        if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
            // The last: the caller may sleep on done_ (under the mutex, so
            // that it cannot check busy_ and then miss this).
            std::lock_guard lock(mutex_);
            done_.notify_one();
        }
    }
}

}  // namespace facet
