// The SDK's side of the plugin boundary: what a C++ exception that reaches
// it does.
//
// The host calls a plugin through the C ABI (shader_abi.h), which has no
// way to carry an exception, and unwinding through the host's frames would
// leave its draw half done. So every function the SDK exports catches what
// the shader's code throws, names the plugin, the function and the
// exception's message on stderr, and aborts: the host's fault report then
// names the plugin's file too (facet/plugin.hpp: report_plugin_faults), a
// hot reload's trial frame refuses such a version, and no image is written
// from a frame the shader did not finish.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <exception>

namespace facet::sdk::detail {

[[noreturn]] inline void exception_escaped(const char* plugin, const char* function,
                                           const char* what) noexcept {
    std::fprintf(stderr, "facet: shader plugin '%s' let a C++ exception out of its %s function: %s\n",
                 plugin, function, what);
    std::fflush(stderr);
    std::abort();
}

// Runs `body`, catching what it throws (with exceptions enabled).
template <class Body>
[[gnu::always_inline]] inline void guarded(const char* plugin, const char* function,
                                           Body&& body) noexcept {
#if defined(__cpp_exceptions)
    try {
        body();
    } catch (const std::exception& e) {
        exception_escaped(plugin, function, e.what());
    } catch (...) {
        exception_escaped(plugin, function, "an exception that is not a std::exception");
    }
#else
    body();
#endif
}

}  // namespace facet::sdk::detail
