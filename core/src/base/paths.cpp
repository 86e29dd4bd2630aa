// Executable-relative locations (facet/paths.hpp).
#include "facet/paths.hpp"

#include <system_error>

namespace facet {

namespace fs = std::filesystem;

fs::path executable_dir() {
    std::error_code error;
    const fs::path exe = fs::read_symlink("/proc/self/exe", error);
    if (error || exe.empty()) return fs::current_path(error);
    return exe.parent_path();
}

namespace {
fs::path g_install_root;  // set_install_root(); empty: beside the executable
}  // namespace

fs::path install_root() {
    return g_install_root.empty() ? (executable_dir() / "..").lexically_normal() : g_install_root;
}

void set_install_root(const fs::path& prefix) { g_install_root = fs::absolute(prefix).lexically_normal(); }

fs::path data_dir() { return install_root() / "share" / "facet"; }

std::vector<fs::path> built_in_plugin_dirs() {
    const fs::path up = install_root();
    return {up / "plugins", up / "lib" / "facet" / "plugins"};
}

}  // namespace facet
