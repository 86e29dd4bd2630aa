// The plugin watchdog (watch_plugin_calls, facet/plugin.hpp): a thread that
// reads every thread's CallSlot (plugin_calls.hpp) a few times a second. A
// slot whose call has not changed within the limit is a stalled call: it is
// named, and the process ends, or (when calls are abandonable) the stalled
// thread is sent abandon_signal(), whose handler returns that call (and no
// later one) to the landing call_abandonable() made for it, provided the
// thread is running the plugin's own code. Core or C library code the
// thread runs for the plugin is never skipped (it may hold a lock): the
// signal is sent again until the thread is back in the plugin's code, or,
// after a grace period, the process ends. Only a call that did land marks
// the frame abandoned (take_abandoned_call).
#include "facet/plugin.hpp"

#include "plugin/plugin_calls.hpp"

#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cfenv>
#include <csetjmp>
#include <csignal>
#include <cstdio>
#include <mutex>
#include <thread>
#include <ucontext.h>
#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#endif

namespace facet {

thread_local CallSlot* t_call_slot = nullptr;
std::atomic<bool> g_calls_abandonable{false};

namespace {

struct Slot {
    CallSlot call;
    std::atomic<bool> used{false};
    pthread_t thread{};      // under g_slots_mutex
    std::string given_up;    // why the watchdog gave its call up; under g_slots_mutex
};

constexpr size_t kSlots = 1024;
std::array<Slot, kSlots> g_slots;
// Held while a slot is taken or freed, and while the watchdog signals a
// thread, so that the thread it signals has not gone.
std::mutex g_slots_mutex;

thread_local CallSlot t_unwatched;  // past kSlots threads at once, and at thread exit

// A thread's slot, freed when the thread ends.
struct SlotOwner {
    Slot* slot = nullptr;
    ~SlotOwner() {
        if (!slot) return;
        // exit() runs this before its atexit handlers, one of which reads
        // the call exit() was made in (faults.cpp): it stays readable.
        t_unwatched.write(slot->call.read());
        t_call_slot = &t_unwatched;
        const std::lock_guard lock(g_slots_mutex);
        slot->used.store(false, std::memory_order_release);
    }
};
thread_local SlotOwner t_owner;

// Abandoning: set by a call that landed, cleared by take_abandoned_call().
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
    if (!landing || !call.plugin ||
        slot->changes.load(std::memory_order_relaxed) !=
            slot->given_up.load(std::memory_order_acquire) ||
        !call.plugin->runs_code_at(interrupted_pc(context)))
        return;
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
    end_process_for(call, "stalled", detail.c_str());
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
        auto last = std::chrono::steady_clock::now();
        for (;;) {
            std::this_thread::sleep_for(tick);
            const auto now = std::chrono::steady_clock::now();
            // Woken late: the process was stopped (Ctrl-Z, a debugger), and
            // its calls with it; their clocks start again.
            if (now - last > 4 * tick)
                for (Seen& seen : seen_) seen.since = now;
            last = now;
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
        const std::lock_guard lock(g_slots_mutex);
        if (!s.used.load(std::memory_order_acquire)) return;
        if (!seen.signalled) {
            s.given_up = given_up_text(call);
            s.call.given_up.store(changes, std::memory_order_release);
            seen.signalled = true;
        }
        pthread_kill(s.thread, abandon_signal());
    }

    std::string given_up_text(const PluginCall& call) const {
        char seconds[32];
        return (call.plugin->is_post() ? "screen pass '" : "shader '") + call.plugin->name() +
               "' (" + call.plugin->origin() + ") did not return from its " +
               (call.entry == PluginEntry::vertex     ? "vertex"
                : call.entry == PluginEntry::fragment ? "fragment"
                                                      : "post") +
               " function within " + seconds_text(options_.limit, seconds) +
               "; the frame was abandoned";
    }

    static constexpr std::chrono::seconds kGrace{2};
    const PluginWatchdog options_;
    std::array<Seen, kSlots> seen_{};
};

}  // namespace

CallSlot& register_call_slot() {
    const std::lock_guard lock(g_slots_mutex);
    for (Slot& s : g_slots) {
        if (s.used.load(std::memory_order_relaxed)) continue;
        s.thread = pthread_self();
        s.given_up.clear();
        s.call.write({});
        s.used.store(true, std::memory_order_release);
        t_owner.slot = &s;
        t_call_slot = &s.call;
        return s.call;
    }
    t_call_slot = &t_unwatched;
    return t_unwatched;
}

namespace {

// The floating-point control a call may leave changed when it is given up
// (rounding, flush to zero), restored after the jump.
struct FloatControl {
#if defined(__x86_64__) || defined(__i386__)
    unsigned mxcsr = _mm_getcsr();
    void restore() const { _mm_setcsr(mxcsr); }
#else
    fenv_t env;
    FloatControl() { fegetenv(&env); }
    void restore() const { fesetenv(&env); }
#endif
};

// On the thread whose call the watchdog gave up, back from the jump: the
// frame is abandoned, for the reason the watchdog gave.
void record_abandoned() {
    std::string why;
    {
        const std::lock_guard lock(g_slots_mutex);
        if (t_owner.slot) why = t_owner.slot->given_up;
    }
    const std::lock_guard lock(g_abandon_mutex);
    if (g_abandoned.empty()) g_abandoned = std::move(why);
    g_abandoning.store(true, std::memory_order_relaxed);
}

}  // namespace

void call_abandonable(CallSlot& slot, void (*call)(void*), void* context) {
    if (g_abandoning.load(std::memory_order_relaxed)) return;  // the frame is given up
    sigjmp_buf landing;
    const FloatControl control;
    void* const outer = slot.landing.load(std::memory_order_relaxed);
    if (sigsetjmp(landing, 0) != 0) {  // from on_abandon: the call was given up
        slot.landing.store(outer, std::memory_order_relaxed);
        control.restore();
        record_abandoned();
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
            action.sa_flags = SA_SIGINFO | SA_NODEFER | SA_RESTART;  // not blocked after the jump
            sigemptyset(&action.sa_mask);
            sigaction(abandon_signal(), &action, nullptr);
            g_calls_abandonable.store(true, std::memory_order_relaxed);
        }
        std::thread([watchdog = Watchdog(options)]() mutable { watchdog.run(); }).detach();
    });
}

}  // namespace facet
