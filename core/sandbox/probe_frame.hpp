// facet-sandbox's probe frame of a plugin on its first load
// (probe_frame.cpp).
#pragma once

#include <filesystem>

namespace facet {

// Loads the plugin at `plugin_file` and draws a frame `width` pixels wide
// with it. Throws facet::Error as loading or rendering does.
void probe_frame(const std::filesystem::path& plugin_file, int width);

}  // namespace facet
