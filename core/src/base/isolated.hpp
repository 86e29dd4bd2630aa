// Work done in a child process, with a memory and a time limit, for code
// that facet does not trust to end well: importing a mesh (assimp has
// readers that abort, or allocate for whatever count a file declares), and
// a hot-reloaded plugin's trial frame (which may crash or loop). Whatever
// the work does wrong ends the child, and this process gets an account of
// it instead.
//
// Takes: the work, as a function returning bytes; the limits.
// Gives: the bytes, or how the child ended: a facet::Error it threw (its id
// and message), memory past the limit, a fatal signal (with what the child
// wrote to stderr last, such as report_plugin_faults()'s line naming the
// plugin), or the time limit (the child is killed).
//
// The child is a fork(): it has a copy of this process's memory (the
// scene, the plugins loaded), and only the calling thread. The work must
// not start threads that outlive it, nor use locks another thread of this
// process may have held (glibc's allocator is safe; a logger may not be:
// the child's log lines are kept back and dropped). It dies with this
// process (PR_SET_PDEATHSIG), and signals such as Ctrl-C reach it with
// their default action. Its stdout goes to /dev/null.
#pragma once

#include "facet/error.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace facet {

struct IsolationLimits {
    uint64_t memory = 0;              // bytes the child may map beyond what it inherits; 0: no limit
    std::chrono::milliseconds time{};  // wall time; 0: no limit
};

struct IsolatedResult {
    enum class End {
        finished,       // the work returned: `output` is what it returned
        error,          // it threw facet::Error: `error` is a copy
        out_of_memory,  // an allocation failed at the memory limit
        crashed,        // a fatal signal: `output` says which, and what the child said last
        out_of_time,    // killed at the time limit
    };
    End end = End::finished;
    std::string output;          // finished: what the work returned; else what happened, for people
    std::optional<Error> error;  // End::error
};

IsolatedResult run_isolated(const std::function<std::string()>& work,
                            const IsolationLimits& limits);

}  // namespace facet
