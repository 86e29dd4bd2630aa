// What every facet program's command line shares.
//
//   --version        prints "PROGRAM VERSION (shader ABI MAJOR.MINOR)" and exits 0
//   -v, --verbose    logs debug messages too (-vv: trace)
//   -q, --quiet      logs warnings and errors only
//   --help           prints the usage and exits 0
//
// Without -v or -q the level comes from FACET_LOG_LEVEL (trace, debug, info,
// warn, error or off), else the program's default. A usage error (an
// unknown option, a missing or malformed value) prints the reason and a hint
// to stderr and exits with status 2, as POSIX tools do.
#pragma once

#include "facet/plugin.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/common.h>

#include <optional>
#include <string>

namespace facet {

struct Verbosity {
    int verbose = 0;  // -v given this many times
    bool quiet = false;
};

// "0.1.0": the project's version.
const char* version();

// Adds --version, -v and -q to `app`, whose name is the program's.
void add_common_options(CLI::App& app, Verbosity& verbosity);

// How a program guards itself against its plugins (facet/plugin.hpp).
struct PluginGuards {
    double timeout = 10.0;  // seconds a plugin call may take; 0: no limit
    bool probe = true;      // a probe frame of each new plugin, in facet-sandbox
};

// Adds --plugin-timeout SECONDS and --no-probe to `app`.
void add_plugin_guard_options(CLI::App& app, PluginGuards& guards);

// Starts the plugin watchdog with the timeout, and returns how long a new
// plugin's probe frame may take (PluginRegistry::probe_first_loads): the
// timeout, or 0 with --no-probe or no timeout.
std::chrono::milliseconds start_plugin_guards(const PluginGuards& guards,
                                              PluginWatchdog::OnStall on_stall);

// Parses the command line: nothing when the program should go on, else the
// status to exit with (0 after --help or --version, 2 for a usage error).
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv);

// Sends the log to stderr, named "facet", at the level -v, -q or
// FACET_LOG_LEVEL asks for, else at `fallback`. An unknown FACET_LOG_LEVEL
// is said in the log, at the fallback level.
void start_logging(const Verbosity& verbosity,
                   spdlog::level::level_enum fallback = spdlog::level::info);

}  // namespace facet
