// Work done in another process, with a memory and a time limit, for code
// that facet does not trust to end well: importing a mesh (assimp has
// readers that abort, or allocate for whatever count a file declares), and
// a hot-reloaded plugin's trial frame (which may crash or loop). Whatever
// the work does wrong ends that process, and this one gets an account of
// it instead.
//
// The other process is facet-sandbox (core/sandbox/main.cpp), started
// afresh with posix_spawn: a fork() of this process would inherit locks
// that its other threads hold (an allocator's, a logger's) and could
// deadlock on them. It lives in ../libexec/ beside the program (facet/
// paths.hpp); it gets the default action for SIGINT, SIGTERM and SIGHUP,
// and dies with this process (PR_SET_PDEATHSIG).
//
// Takes: the sandbox's job and its arguments; the limits.
// Gives: the bytes the job returned, or how it ended: a facet::Error it
// threw (its id, file, line and message), memory past the limit, a fatal
// signal or an exit without an account (with the last line the sandbox
// wrote to stderr, such as report_plugin_faults()'s naming the plugin), or
// the time limit (the sandbox is killed).
#pragma once

#include "facet/error.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace facet {

struct IsolationLimits {
    uint64_t memory = 0;               // bytes the job may map beyond the program's own; 0: no limit
    std::chrono::milliseconds time{};  // wall time; 0: no limit
};

struct IsolatedResult {
    enum class End {
        finished,       // the job returned: `output` is what it returned
        error,          // it threw facet::Error: `error` is a copy
        out_of_memory,  // an allocation failed at the memory limit
        crashed,        // a fatal signal, or an exit without an account: `output` says which
        out_of_time,    // killed at the time limit
    };
    End end = End::finished;
    std::string output;          // finished: what the job returned; else what happened, for people
    std::optional<Error> error;  // End::error
};

// facet-sandbox beside this program, or nothing if it is not there (an
// embedder that did not install it).
std::optional<std::filesystem::path> sandbox_program();

// Runs facet-sandbox's `job` with `args`. Throws std::system_error if the
// sandbox cannot be started (call sandbox_program() first).
IsolatedResult run_sandboxed(const std::string& job, const std::vector<std::string>& args,
                             const IsolationLimits& limits);

// True in facet-sandbox while it serves its job: work it would isolate
// (the trial frame's mesh imports) is isolated already.
bool in_sandbox();

// Limits this process's address space (the soft limit only: a sanitizer
// runtime starting in a process this one spawns sets limits of its own, and
// fails on a hard one) to what it maps now plus `memory` bytes. An
// allocation past it fails, as std::bad_alloc or a sanitizer's report.
// Returns the limit in bytes, or 0 if it could not be set.
uint64_t limit_address_space(uint64_t memory);

// In facet-sandbox: limits this process's address space to what it maps
// now plus `memory` (0: no limit), runs `work`, and writes the account
// run_sandboxed() reads to stdout. Returns the exit status.
int serve_sandboxed(const std::function<std::string()>& work, uint64_t memory);

}  // namespace facet
