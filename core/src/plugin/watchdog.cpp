// The plugin watchdog (watch_plugin_calls, facet/plugin.hpp): a thread that
// reads every thread's CallSlot (plugin_calls.hpp) a few times a second. A
// slot whose call has not changed within the limit is a stalled call: it is
// named, and the process ends, or (when calls are abandonable) the stalled
// thread is sent kAbandonSignal, whose handler returns the call to the
// landing call_abandonable() made for it, provided the thread is running the
// plugin's own code. Core or C library code the thread runs for the plugin
// is never skipped (it may hold a lock): the signal is sent again until the
// thread is back in the plugin's code, or, after a grace period, the
// process ends.
#include "facet/plugin.hpp"

#include "facet/output.hpp"
#include "plugin/plugin_calls.hpp"

#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <csetjmp>
#include <csignal>
#include <cstdio>
#include <mutex>
#include <thread>
#include <ucontext.h>

namespace facet {

thread_local CallSlot* t_call_slot = nullptr;
std::atomic<bool> g_calls_abandonable{false};

namespace {

struct Slot {
    CallSlot call;
    std::atomic<bool> used{false};
    pthread_t thread{};
};

constexpr size_t kSlots = 1024;
std::array<Slot, kSlots> g_slots;
// Held while a slot is freed and while the watchdog signals a thread, so
// that the thread it signals has not gone.
std::mutex g_slots_mutex;

// A thread's slot, freed when the thread ends.
struct SlotOwner {
    Slot* slot = nullptr;
    ~SlotOwner() {
        if (!slot) return;
        const std::lock_guard lock(g_slots_mutex);
        slot->used.store(false, std::memory_order_release);
    }
};
thread_local SlotOwner t_owner;
thread_local CallSlot t_unwatched;  // past kSlots threads at once

// Abandoning: set by the watchdog, cleared by take_abandoned_call().
std::atomic<bool> g_abandoning{false};
std::mutex g_abandon_mutex;
std::string g_abandoned;

int abandon_signal() { return SIGRTMIN + 2; }

uintptr_t interrupted_pc(void* context) {
    const auto* uc = static_cast<const ucontext_t*>(context);
#if defined(__x86_64__)
    return uintptr_t(uc->uc_mcontext.gregs[REG_RIP]);
#elif defined(__aarch64__)
    return uintptr_t(uc->uc_mcontext.pc);
#else
    (void)uc;
    return 0;  // not known: a stalled call is never returned, and the process ends
#endif
}

// On the stalled thread. Returns the call to its landing when the thread
// runs the plugin's own code; else does nothing, and the watchdog tries
// again.
void on_abandon(int, siginfo_t*, void* context) {
    CallSlot* slot = t_call_slot;
    if (!slot) return;
    void* landing = slot->landing.load(std::memory_order_relaxed);
    const PluginCall call = slot->read();
    if (!landing || !call.plugin || !call.plugin->runs_code_at(interrupted_pc(context))) return;
    siglongjmp(*static_cast<sigjmp_buf*>(landing), 1);
}

const char* seconds_text(std::chrono::milliseconds limit, char (&text)[32]) {
    std::snprintf(text, sizeof text, "%g s", double(limit.count()) / 1000.0);
    return text;
}

[[noreturn]] void end_process(const PluginCall& call, std::chrono::milliseconds limit) {
    char seconds[32];
    std::string detail = std::string("no return within ") + seconds_text(limit, seconds) +
                         "; the process ends with status 70";
    report_plugin_call(call, "stalled", detail.c_str());
    remove_partial_outputs();
    remove_private_plugin_copies();
    _exit(70);
}

bool abandonable(PluginEntry e) {
    return e == PluginEntry::vertex || e == PluginEntry::fragment || e == PluginEntry::post;
}

// What the watchdog knows of one slot.
struct Seen {
    uint32_t changes = 0;
    std::chrono::steady_clock::time_point since;
    bool signalled = false;
};

class Watchdog {
public:
    explicit Watchdog(const PluginWatchdog& options) : options_(options) {}

    [[noreturn]] void run() {
        const auto tick = std::clamp(options_.limit / 20, std::chrono::milliseconds(10),
                                     std::chrono::milliseconds(250));
        for (;;) {
            std::this_thread::sleep_for(tick);
            const auto now = std::chrono::steady_clock::now();
            for (size_t i = 0; i < kSlots; ++i) check(i, now);
        }
    }

private:
    void check(size_t i, std::chrono::steady_clock::time_point now) {
        Slot& s = g_slots[i];
        Seen& seen = seen_[i];
        const uint32_t changes = s.call.changes.load(std::memory_order_relaxed);
        const PluginCall call = s.call.read();
        if (!s.used.load(std::memory_order_acquire) || !call.plugin || changes != seen.changes) {
            seen = {changes, now, false};
            return;
        }
        const auto stalled = now - seen.since;
        if (stalled < options_.limit) return;
        const bool abandon = options_.on_stall == PluginWatchdog::OnStall::abandon_frame &&
                             abandonable(call.entry);
        if (!abandon || stalled >= options_.limit + kGrace) end_process(call, options_.limit);
        if (!seen.signalled) record_abandoned(call);
        seen.signalled = true;
        const std::lock_guard lock(g_slots_mutex);
        if (s.used.load(std::memory_order_acquire)) pthread_kill(s.thread, abandon_signal());
    }

    void record_abandoned(const PluginCall& call) {
        char seconds[32];
        const std::string text =
            (call.plugin->is_post() ? "screen pass '" : "shader '") + call.plugin->name() +
            "' (" + call.plugin->origin() + ") did not return from its " +
            (call.entry == PluginEntry::vertex     ? "vertex"
             : call.entry == PluginEntry::fragment ? "fragment"
                                                   : "post") +
            " function within " + seconds_text(options_.limit, seconds) +
            "; the frame was abandoned";
        const std::lock_guard lock(g_abandon_mutex);
        if (g_abandoned.empty()) g_abandoned = text;
        g_abandoning.store(true, std::memory_order_relaxed);
    }

    static constexpr std::chrono::seconds kGrace{2};
    const PluginWatchdog options_;
    std::array<Seen, kSlots> seen_{};
};

}  // namespace

CallSlot& register_call_slot() {
    for (Slot& s : g_slots) {
        bool expected = false;
        if (s.used.load(std::memory_order_relaxed) ||
            !s.used.compare_exchange_strong(expected, true, std::memory_order_acq_rel))
            continue;
        s.thread = pthread_self();
        s.call.write({});
        t_owner.slot = &s;
        t_call_slot = &s.call;
        return s.call;
    }
    t_call_slot = &t_unwatched;
    return t_unwatched;
}

void call_abandonable(CallSlot& slot, void (*call)(void*), void* context) {
    if (g_abandoning.load(std::memory_order_relaxed)) return;  // the frame is given up
    sigjmp_buf landing;
    void* const outer = slot.landing.load(std::memory_order_relaxed);
    if (sigsetjmp(landing, 0) != 0) {  // from on_abandon: the call was given up
        slot.landing.store(outer, std::memory_order_relaxed);
        return;
    }
    slot.landing.store(&landing, std::memory_order_relaxed);
    std::atomic_signal_fence(std::memory_order_seq_cst);
    call(context);
    std::atomic_signal_fence(std::memory_order_seq_cst);
    slot.landing.store(outer, std::memory_order_relaxed);
}

std::string take_abandoned_call() {
    if (!g_abandoning.load(std::memory_order_relaxed)) return {};
    const std::lock_guard lock(g_abandon_mutex);
    std::string why = std::move(g_abandoned);
    g_abandoned.clear();
    g_abandoning.store(false, std::memory_order_relaxed);
    return why;
}

void watch_plugin_calls(const PluginWatchdog& options) {
    static std::once_flag started;
    if (options.limit.count() <= 0) return;
    std::call_once(started, [&] {
        if (options.on_stall == PluginWatchdog::OnStall::abandon_frame) {
            struct sigaction action {};
            action.sa_sigaction = on_abandon;
            action.sa_flags = SA_SIGINFO | SA_NODEFER;  // not blocked after the jump out
            sigemptyset(&action.sa_mask);
            sigaction(abandon_signal(), &action, nullptr);
            g_calls_abandonable.store(true, std::memory_order_relaxed);
        }
        std::thread([watchdog = Watchdog(options)]() mutable { watchdog.run(); }).detach();
    });
}

}  // namespace facet
