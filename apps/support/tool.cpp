#include "facet/tool.hpp"

#include <facet/shader_abi.h>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdlib>
#include <string_view>

namespace facet {

namespace {

std::optional<spdlog::level::level_enum> parse_level(std::string_view name) {
    using L = spdlog::level::level_enum;
    for (const auto& [text, level] :
         {std::pair{"trace", L::trace}, {"debug", L::debug}, {"info", L::info},
          {"warn", L::warn}, {"warning", L::warn}, {"error", L::err}, {"off", L::off}})
        if (name == text) return level;
    return std::nullopt;
}

}  // namespace

const char* version() { return FACET_VERSION; }

void add_common_options(CLI::App& app, Verbosity& verbosity) {
    app.set_version_flag("--version", app.get_name() + " " + FACET_VERSION + " (shader ABI " +
                                          std::to_string(FACET_ABI_MAJOR) + "." +
                                          std::to_string(FACET_ABI_MINOR) + ")");
    CLI::Option* verbose =
        app.add_flag("-v,--verbose", verbosity.verbose, "log debug messages too (-vv: trace)");
    app.add_flag("-q,--quiet", verbosity.quiet, "log warnings and errors only")->excludes(verbose);
    app.footer("Environment: FACET_LOG_LEVEL (trace, debug, info, warn, error, off) sets the "
               "log level when neither -v nor -q is given.");
}

void add_plugin_guard_options(CLI::App& app, PluginGuards& guards) {
    app.add_option("--plugin-timeout", guards.timeout,
                   "seconds a call into a shader plugin (or its probe frame) may take before it "
                   "is named as stalled; 0: no limit, and no probe frames")
        ->check(CLI::Validator(
            [](const std::string& text) -> std::string {
                double seconds = -1.0;
                try {
                    seconds = std::stod(text);
                } catch (const std::exception&) {
                }
                if (seconds == 0.0 || (seconds >= 0.01 && seconds <= 1e6)) return {};
                return "expected 0 (no limit) or seconds from 0.01 to 1000000, got '" + text +
                       "'";
            },
            "SECONDS"))
        ->capture_default_str();
    app.add_flag("!--no-probe", guards.probe,
                 "load new plugins without first drawing a probe frame with each in another "
                 "process");
}

std::chrono::milliseconds start_plugin_guards(const PluginGuards& guards,
                                              PluginWatchdog::OnStall on_stall) {
    PluginWatchdog watchdog;
    watchdog.limit = std::chrono::milliseconds(std::llround(guards.timeout * 1000.0));
    watchdog.on_stall = on_stall;
    watch_plugin_calls(watchdog);
    return guards.probe ? watchdog.limit : std::chrono::milliseconds(0);
}

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
        return std::nullopt;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);  // prints the reason and "Run with --help for more information."
        return 2;
    }
}

void start_logging(const Verbosity& verbosity, spdlog::level::level_enum fallback) {
    spdlog::set_default_logger(spdlog::stderr_color_mt("facet"));
    const char* env = std::getenv("FACET_LOG_LEVEL");
    const std::optional<spdlog::level::level_enum> from_env =
        env && *env ? parse_level(env) : std::nullopt;
    spdlog::level::level_enum level = from_env.value_or(fallback);
    if (verbosity.quiet) level = spdlog::level::warn;
    if (verbosity.verbose) level = verbosity.verbose > 1 ? spdlog::level::trace : spdlog::level::debug;
    spdlog::set_level(level);
    if (env && *env && !from_env)
        spdlog::warn("FACET_LOG_LEVEL={}: expected trace, debug, info, warn, error or off; "
                     "logging at {}", env, spdlog::level::to_string_view(level));
}

}  // namespace facet
