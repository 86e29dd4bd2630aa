// A stack for the calling thread's signal handlers, so that a fault handler
// (report_plugin_faults, facet/plugin.hpp) still runs when code has
// overflowed the thread's own stack.
//
// Takes: the calling thread.
// Gives: an alternate signal stack for it while the SignalStack lives,
// unless the thread has one already (a sanitizer's), which is left alone.
#pragma once

#include <signal.h>

#include <memory>

namespace facet {

class SignalStack {
public:
    SignalStack() {
        stack_t current{};
        if (sigaltstack(nullptr, &current) != 0 || !(current.ss_flags & SS_DISABLE)) return;
        memory_ = std::make_unique<char[]>(kSize);
        stack_t alternate{};
        alternate.ss_sp = memory_.get();
        alternate.ss_size = kSize;
        if (sigaltstack(&alternate, nullptr) != 0) memory_.reset();
    }
    ~SignalStack() {
        if (!memory_) return;
        stack_t off{};
        off.ss_flags = SS_DISABLE;
        sigaltstack(&off, nullptr);
    }
    SignalStack(const SignalStack&) = delete;
    SignalStack& operator=(const SignalStack&) = delete;

private:
    static constexpr size_t kSize = size_t(64) << 10;
    std::unique_ptr<char[]> memory_;
};

}  // namespace facet
