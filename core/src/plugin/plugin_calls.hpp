// Which plugin code each thread runs, for the fault handlers (faults.cpp)
// and the watchdog (watchdog.cpp): every call into a plugin (loading it,
// its entry point, its vertex, fragment and post functions, unloading it)
// is made inside an InPlugin, which publishes it in the thread's CallSlot.
// The fault handler reads the crashing thread's slot; the watchdog reads
// every thread's, and names a call that has not returned within its limit.
//
// Vertex, fragment and post functions are called through call_plugin(),
// which, when the watchdog abandons stalled calls (the viewer), gives the
// call a landing: the watchdog's signal returns a stalled call there, and
// the frame is abandoned (take_abandoned_call()).
//
// Takes: the plugin about to run, and which of its functions.
// Gives: nothing; the thread's slot, restored when the InPlugin goes.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <tuple>

namespace facet {

class ShaderPlugin;

enum class PluginEntry : uint8_t { none, load, entry_point, vertex, fragment, post, unload };

struct PluginCall {
    const ShaderPlugin* plugin = nullptr;
    PluginEntry entry = PluginEntry::none;
};

// One thread's plugin call, as its own thread writes it and others (and its
// signal handlers) read it. Relaxed atomics: plain loads and stores on x86.
struct CallSlot {
    std::atomic<const ShaderPlugin*> plugin{nullptr};
    std::atomic<PluginEntry> entry{PluginEntry::none};
    std::atomic<uint32_t> changes{0};     // +1 whenever a call starts or ends
    std::atomic<void*> landing{nullptr};  // a sigjmp_buf: where a stalled call may return
    // `changes` as the watchdog saw it when it gave the call up: the
    // signal returns that call only, never a later one it arrives in.
    std::atomic<uint32_t> given_up{~0u};

    PluginCall read() const {
        return {plugin.load(std::memory_order_relaxed), entry.load(std::memory_order_relaxed)};
    }
    void write(const PluginCall& call) {
        entry.store(call.entry, std::memory_order_relaxed);
        plugin.store(call.plugin, std::memory_order_relaxed);
        changes.store(changes.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    }
};

// This thread's slot, or null before its first plugin call. Defined in
// watchdog.cpp, and not inline: the per-path kernels, whose other symbols
// are made local, must share this one.
extern thread_local CallSlot* t_call_slot;
// Gives this thread a slot the watchdog reads (or, past a thousand threads
// at once, one it does not), and returns it.
CallSlot& register_call_slot();

inline CallSlot& call_slot() { return t_call_slot ? *t_call_slot : register_call_slot(); }

class InPlugin {
public:
    InPlugin(const ShaderPlugin* plugin, PluginEntry entry)
        : slot_(call_slot()), saved_(slot_.read()) {
        slot_.write({plugin, entry});
    }
    ~InPlugin() { slot_.write(saved_); }
    InPlugin(const InPlugin&) = delete;
    InPlugin& operator=(const InPlugin&) = delete;

    CallSlot& slot() const { return slot_; }

private:
    CallSlot& slot_;
    PluginCall saved_;
};

// "facet: shader plugin 'NAME' (FILE) <event> <where>: <detail>" on
// stderr, where is the call's function ("in its fragment function").
// Async-signal-safe. faults.cpp.
void report_plugin_call(const PluginCall& call, const char* event, const char* detail);
// Reports the call so, removes the partial outputs and the private plugin
// copies, and ends the process with status 70 (EX_SOFTWARE): exit() in
// plugin code, or a stall. Not for signal handlers. faults.cpp.
[[noreturn]] void end_process_for(const PluginCall& call, const char* event, const char* detail);

// True when the watchdog abandons stalled calls rather than ending the
// process (watch_plugin_calls, facet/plugin.hpp).
extern std::atomic<bool> g_calls_abandonable;

// Runs call(context) with a landing in `slot` for the watchdog's signal;
// skips it once a call of this frame has been abandoned. watchdog.cpp.
void call_abandonable(CallSlot& slot, void (*call)(void*), void* context);

// Calls fn(args...), code of `plugin` serving as its `entry` function.
template <class Fn, class... Args>
inline void call_plugin(const ShaderPlugin* plugin, PluginEntry entry, Fn fn, Args... args) {
    const InPlugin in(plugin, entry);
    if (g_calls_abandonable.load(std::memory_order_relaxed)) [[unlikely]] {
        std::tuple<Fn, Args...> call{fn, args...};
        call_abandonable(
            in.slot(),
            [](void* c) {
                std::apply([](Fn f, Args... a) { f(a...); }, *static_cast<decltype(call)*>(c));
            },
            &call);
        return;
    }
    fn(args...);
}

// Why a call was abandoned since the last take ("" if none), and clears it:
// plugin calls are made again. The renderer takes it at the end of a frame,
// and throws.
std::string take_abandoned_call();

// Host code that a plugin calls and that waits on other threads (a post
// pass's parallel_for): while it lives, the thread is in no plugin call, so
// neither is it timed as one, nor is its wait ever skipped by the
// watchdog's signal.
class InHostCode {
public:
    InHostCode()
        : slot_(call_slot()), saved_(slot_.read()),
          landing_(slot_.landing.exchange(nullptr, std::memory_order_relaxed)) {
        slot_.write({});
    }
    ~InHostCode() {
        slot_.write(saved_);
        slot_.landing.store(landing_, std::memory_order_relaxed);
    }
    InHostCode(const InHostCode&) = delete;
    InHostCode& operator=(const InHostCode&) = delete;

private:
    CallSlot& slot_;
    PluginCall saved_;
    void* landing_;
};

}  // namespace facet
