// Which plugin code each thread runs, for report_plugin_faults()
// (facet/plugin.hpp): every call into a plugin (loading it, its entry point,
// its vertex, fragment and post functions, unloading it) is made inside an
// InPlugin, and the fault handler reads the crashing thread's record.
//
// Takes: the plugin about to run, and which of its functions.
// Gives: nothing; a thread-local record, restored when the InPlugin goes.
#pragma once

#include <cstdint>

namespace facet {

class ShaderPlugin;

enum class PluginEntry : uint8_t { none, load, entry_point, vertex, fragment, post, unload };

struct PluginCall {
    const ShaderPlugin* plugin = nullptr;
    PluginEntry entry = PluginEntry::none;
};

// Defined in faults.cpp, and not inline: the per-path kernels, whose other
// symbols are made local, must share this one.
extern thread_local PluginCall t_plugin_call;

class InPlugin {
public:
    InPlugin(const ShaderPlugin* plugin, PluginEntry entry) : saved_(t_plugin_call) {
        t_plugin_call = {plugin, entry};
    }
    ~InPlugin() { t_plugin_call = saved_; }
    InPlugin(const InPlugin&) = delete;
    InPlugin& operator=(const InPlugin&) = delete;

private:
    PluginCall saved_;
};

}  // namespace facet
