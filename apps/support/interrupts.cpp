#include "facet/interrupts.hpp"

#include <facet/plugin.hpp>
#include <facet/output.hpp>

#include <spdlog/spdlog.h>

#include <pthread.h>
#include <unistd.h>

#include <csignal>

namespace facet {

namespace {

sigset_t interrupt_signals() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    return set;
}

// Straight to stderr: the thread that holds a logger's lock may be the one
// that is stuck.
void say(const std::string& text) {
    const std::string line = text + "\n";
    for (size_t done = 0; done < line.size();) {
        const ssize_t n = write(STDERR_FILENO, line.data() + done, line.size() - done);
        if (n <= 0) return;
        done += size_t(n);
    }
}

}  // namespace

Interrupts::Interrupts(std::string program, std::function<void()> on_stop,
                       std::chrono::milliseconds grace)
    : program_(std::move(program)), on_stop_(std::move(on_stop)), grace_(grace) {
    const sigset_t set = interrupt_signals();
    pthread_sigmask(SIG_BLOCK, &set, &before_);
    // A reader that goes away (facet-render -o - | head) and a file past
    // the size limit (ulimit -f) are write errors, EPIPE and EFBIG, that the
    // writer reports: not a silent end by SIGPIPE or SIGXFSZ.
    std::signal(SIGPIPE, SIG_IGN);
    std::signal(SIGXFSZ, SIG_IGN);
    thread_ = std::thread([this] { run(); });
}

Interrupts::~Interrupts() {
    {
        std::lock_guard lock(mutex_);
        done_ = true;
    }
    done_changed_.notify_all();
    // Wakes the thread if it still waits for a first signal (it sees done_).
    pthread_kill(thread_.native_handle(), SIGTERM);
    thread_.join();
    pthread_sigmask(SIG_SETMASK, &before_, nullptr);  // a signal from now on acts as it did
}

int Interrupts::exit_code() const {
    const int sig = signal_.load();
    return sig ? 128 + sig : 0;
}

void Interrupts::run() {
    const sigset_t set = interrupt_signals();
    int sig = 0;
    if (sigwait(&set, &sig) != 0) return;
    {
        std::lock_guard lock(mutex_);
        if (done_) return;
    }
    signal_ = sig;
    stop_ = true;
    spdlog::warn("{}: stopping", sig == SIGINT    ? "interrupted (SIGINT)"
                                 : sig == SIGHUP ? "hung up (SIGHUP)"
                                                 : "terminated (SIGTERM)");
    if (on_stop_) on_stop_();

    // A second signal ends the wait early; so does the program's exit.
    const auto deadline = std::chrono::steady_clock::now() + grace_;
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            if (done_changed_.wait_until(lock, std::min(deadline, std::chrono::steady_clock::now() +
                                                                      std::chrono::milliseconds(20)),
                                         [&] { return done_; }))
                return;
        }
        const timespec none{0, 0};
        const bool again = sigtimedwait(&set, nullptr, &none) > 0;
        {
            // The destructor's wake-up is no second signal.
            std::lock_guard lock(mutex_);
            if (done_) return;
        }
        if (again || std::chrono::steady_clock::now() >= deadline) break;
    }
    say(program_ + ": still busy " + std::to_string(grace_.count()) +
        " ms after the signal; exiting now");
    remove_private_plugin_copies();
    remove_partial_outputs();
    _exit(128 + sig);
}

}  // namespace facet
