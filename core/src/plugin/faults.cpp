// Fault reports (report_plugin_faults, facet/plugin.hpp): a signal or an
// exit() in plugin code is named with the plugin and the function it was
// in (plugin_calls.hpp), partial outputs are removed, and the process ends
// as it would have.
#include "facet/plugin.hpp"

#include "facet/output.hpp"
#include "base/signal_stack.hpp"
#include "plugin/plugin_calls.hpp"

#include <unistd.h>

#include <csignal>
#include <cstdlib>

namespace facet {

thread_local PluginCall t_plugin_call;

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

// Only async-signal-safe calls from here on: write(), unlink(), sigaction(),
// raise(), _exit().

// "facet: shader plugin 'NAME' (FILE) <event> <where>: <detail>" on stderr.
void report_call(const PluginCall& call, const char* event, const char* detail) {
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

void on_fault(int sig, siginfo_t* info, void*) {
    const PluginCall call = t_plugin_call;
    if (call.plugin) report_call(call, "crashed", signal_text(sig));
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
    const PluginCall call = t_plugin_call;
    if (!call.plugin) return;
    report_call(call, "called exit()", "the process ends with status 70");
    remove_partial_outputs();
    remove_private_plugin_copies();
    _exit(70);
}

}  // namespace

void report_plugin_faults() {
    // A stack of its own for this thread (the pool's workers make theirs),
    // so that a stack overflow in a plugin can still be reported.
    static const SignalStack stack;
    struct sigaction action {};
    action.sa_sigaction = on_fault;
    action.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&action.sa_mask);
    for (const int sig : kFaultSignals) sigaction(sig, &action, &g_before[sig]);
    static const bool exit_watched = std::atexit(on_exit_in_plugin) == 0;
    (void)exit_watched;
}

}  // namespace facet
