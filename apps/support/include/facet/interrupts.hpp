// SIGINT, SIGTERM and SIGHUP for facet's programs: stop promptly, whatever
// runs, and leave no partial output file behind.
//
// Construct one Interrupts at the top of main(), before any other thread
// starts (the thread pool, SDL): it blocks the three signals in the calling
// thread, so that every thread made later inherits the block, and takes
// them on a thread of its own. The first signal raises stop(), which the
// program polls and hands to Pipeline::stop_when(), so that a render ends
// within a tile's work; `on_stop` runs too (the viewer wakes its event
// loop). The program then leaves through its normal path and returns
// exit_code(). If the process still runs `grace` after the signal, because
// it is stuck where no flag is read (a mesh import, a plugin that loops),
// or on a second signal, it says so, removes its private plugin copies and
// its partial output files (facet/output.hpp) and exits at once with the same
// code. It also ignores SIGPIPE and SIGXFSZ, so that a reader that goes
// away, or a file past the size limit, is a write error the program
// reports.
#pragma once

#include <signal.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace facet {

class Interrupts {
public:
    explicit Interrupts(std::string program, std::function<void()> on_stop = {},
                        std::chrono::milliseconds grace = std::chrono::milliseconds(500));
    ~Interrupts();
    Interrupts(const Interrupts&) = delete;
    Interrupts& operator=(const Interrupts&) = delete;

    const std::atomic<bool>& stop() const { return stop_; }
    bool stopped() const { return stop_.load(); }
    // 128 + the signal's number (130 for SIGINT, 143 for SIGTERM, 129 for
    // SIGHUP), the shell's convention; 0 before any signal.
    int exit_code() const;

private:
    void run();

    std::string program_;
    std::function<void()> on_stop_;
    std::chrono::milliseconds grace_;
    std::atomic<bool> stop_{false};
    std::atomic<int> signal_{0};
    std::mutex mutex_;
    std::condition_variable done_changed_;
    bool done_ = false;  // the program has left main(): under mutex_
    sigset_t before_;    // the calling thread's mask, restored by the destructor
    std::thread thread_;
};

}  // namespace facet
