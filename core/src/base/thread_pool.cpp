#include "base/thread_pool.hpp"

#include "base/signal_stack.hpp"

namespace facet {

ThreadPool::ThreadPool(int threads) {
    if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
    for (int w = 1; w < threads; ++w) workers_.emplace_back([this, w] { work(w); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
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
    {
        std::lock_guard lock(mutex_);
        call_ = call;
        fn_ = fn;
        count_ = n;
        next_.store(0, std::memory_order_relaxed);
        busy_ = int(workers_.size());
        ++generation_;
    }
    wake_.notify_all();
    drain(0);
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return busy_ == 0; });
}

void ThreadPool::work(int worker) {
    const SignalStack signal_stack;  // plugin code runs here: a fault can still be named
    unsigned seen = 0;
    std::unique_lock lock(mutex_);
    while (true) {
        wake_.wait(lock, [&] { return stopping_ || generation_ != seen; });
        if (stopping_) return;
        seen = generation_;
        lock.unlock();
        drain(worker);
        lock.lock();
        if (--busy_ == 0) done_.notify_one();
    }
}

}  // namespace facet
