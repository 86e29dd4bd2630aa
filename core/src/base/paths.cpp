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

fs::path data_dir() { return (executable_dir() / ".." / "share" / "facet").lexically_normal(); }

std::vector<fs::path> built_in_plugin_dirs() {
    const fs::path up = executable_dir() / "..";
    return {(up / "plugins").lexically_normal(), (up / "lib" / "facet" / "plugins").lexically_normal()};
}

}  // namespace facet
