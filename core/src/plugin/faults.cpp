// Fault reports (report_plugin_faults, facet/plugin.hpp): a signal or an
// exit() in plugin code is named with the plugin and the function it was
// in (plugin_calls.hpp), partial outputs are removed, and the process ends
// as it would have.
#include "facet/plugin.hpp"

#include "facet/memory.hpp"
#include "facet/output.hpp"
#include "base/signal_stack.hpp"
#include "plugin/plugin_calls.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>

namespace facet {

namespace {

constexpr int kFaultSignals[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};
struct sigaction g_before[NSIG];

const char* entry_text(PluginEntry e) {
    switch (e) {
        case PluginEntry::load: return "while loading (its static constructors)";
        case PluginEntry::entry_point: return "in its entry point (" FACET_PLUGIN_ENTRY_SYMBOL ")";
        case PluginEntry::vertex: return "in its vertex function";
        case PluginEntry::fragment: return "in its fragment function";
        case PluginEntry::post: return "in its post function";
        case PluginEntry::unload: return "while unloading (its static destructors)";
        default: return "";
    }
}

const char* signal_text(int sig) {
    switch (sig) {
        case SIGSEGV: return "SIGSEGV, invalid memory access";
        case SIGBUS: return "SIGBUS, bus error";
        case SIGILL: return "SIGILL, illegal instruction";
        case SIGFPE: return "SIGFPE, arithmetic error";
        case SIGABRT: return "SIGABRT, aborted";
        default: return "a fatal signal";
    }
}

}  // namespace

// Only async-signal-safe calls from here on: write(), unlink(), sigaction(),
// raise(), _exit().

void report_plugin_call(const PluginCall& call, const char* event, const char* detail) {
    char text[1024];
    size_t used = 0;
    auto add = [&](const char* s) {
        while (*s && used + 1 < sizeof text) text[used++] = *s++;
    };
    add("facet: shader plugin ");
    if (call.plugin->name().empty()) {  // not known before its entry point returns
        add(call.plugin->origin().c_str());
    } else {
        add("'");
        add(call.plugin->name().c_str());
        add("' (");
        add(call.plugin->origin().c_str());
        add(")");
    }
    add(" ");
    add(event);
    add(" ");
    add(entry_text(call.entry));
    add(": ");
    add(detail);
    add("\n");
    for (size_t done = 0; done < used;) {
        const ssize_t n = write(STDERR_FILENO, text + done, used - done);
        if (n <= 0) break;
        done += size_t(n);
    }
}

namespace {

long g_page_size = 4096;  // sysconf() is not async-signal-safe: read at install

// Whether this process maps within 64 MiB of its address space cap
// (cap_address_space), where an allocation that failed is the likely cause
// of a crash. From /proc/self/statm, with open() and read().
bool near_address_space_cap() {
    const uint64_t cap = address_space_cap();
    if (cap == 0) return false;
    const int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    char text[64];
    const ssize_t n = read(fd, text, sizeof text - 1);
    close(fd);
    uint64_t pages = 0;
    for (ssize_t i = 0; i < n && text[i] >= '0' && text[i] <= '9'; ++i)
        pages = pages * 10 + uint64_t(text[i] - '0');
    return pages * uint64_t(g_page_size) + (uint64_t(64) << 20) >= cap;
}

void on_fault(int sig, siginfo_t* info, void*) {
    const PluginCall call = t_call_slot ? t_call_slot->read() : PluginCall{};
    if (call.plugin) {
        char detail[256] = {};
        size_t used = 0;
        for (const char* part : {signal_text(sig), near_address_space_cap()
                                                       ? "; the process was at its address "
                                                         "space cap (--max-memory), where "
                                                         "allocations fail"
                                                       : ""})
            for (; *part && used + 1 < sizeof detail; ++part) detail[used++] = *part;
        report_plugin_call(call, "crashed", detail);
    }
    remove_partial_outputs();  // the images this process will not finish
    // The earlier handler takes it from here: a fault repeats when its
    // instruction runs again; a signal sent by a call (abort, raise, kill)
    // is sent again, and arrives when this handler returns.
    sigaction(sig, &g_before[sig], nullptr);
    if (info->si_code <= 0) raise(sig);
}

// exit() called by plugin code (an atexit handler runs on the thread that
// called it): named, and the process ends with status 70 (EX_SOFTWARE),
// not with the plugin's status, which could claim success with no image.
// Not a signal handler: it may remove the private plugin copies too.
void on_exit_in_plugin() {
    const PluginCall call = t_call_slot ? t_call_slot->read() : PluginCall{};
    if (call.plugin) end_process_for(call, "called exit()", "the process ends with status 70");
}

}  // namespace

void end_process_for(const PluginCall& call, const char* event, const char* detail) {
    report_plugin_call(call, event, detail);
    remove_partial_outputs();
    remove_private_plugin_copies();
    _exit(70);
}

void report_plugin_faults() {
    // A stack of its own for this thread (the pool's workers make theirs),
    // so that a stack overflow in a plugin can still be reported.
    static const SignalStack stack;
    g_page_size = sysconf(_SC_PAGESIZE);
    struct sigaction action {};
    action.sa_sigaction = on_fault;
    action.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&action.sa_mask);
    for (const int sig : kFaultSignals) sigaction(sig, &action, &g_before[sig]);
    static const bool exit_watched = std::atexit(on_exit_in_plugin) == 0;
    (void)exit_watched;
}

}  // namespace facet
