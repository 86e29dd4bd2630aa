// Where facet finds its own files: relative to the running program, never
// through paths baked in at build time, so that a build tree and an
// installed prefix work alike and either may move.
//
// Both are laid out the same way around the program's folder (bin/ when
// installed, apps/, tests/ or bench/ in a build tree):
//   ../share/facet/   data: configs/ (the default scene and its
//                     materials), assets/, shaders/ (the built-in shaders'
//                     sources, for --rebuild); the build tree links these
//                     to the source tree at configure time
//   ../plugins/       the built-in shader plugins in a build tree, or
//   ../lib/facet/plugins/ once installed
#pragma once

#include <filesystem>
#include <vector>

namespace facet {

// The folder of the running executable (/proc/self/exe), or the current
// folder if that cannot be read.
std::filesystem::path executable_dir();

// The folder the layout above hangs from: the executable's folder's parent,
// unless set_install_root() gave another.
std::filesystem::path install_root();

// For a program that embeds facet (links facet::core) and is not installed
// beside it: the prefix facet is installed in (FACET_PREFIX_DIR, from
// find_package(facet)). Its data, built-in plugins and facet-sandbox are
// then found there. Call it first, before other threads start.
void set_install_root(const std::filesystem::path& prefix);

// share/facet in install_root().
std::filesystem::path data_dir();

// The folders the built-in shader plugins may be in, nearest first.
std::vector<std::filesystem::path> built_in_plugin_dirs();

}  // namespace facet
