#include "assets/import_files.hpp"

#include "base/files.hpp"

#include <cstring>
#include <filesystem>

namespace facet {

bool RegularFilesOnly::allowed(const char* file) const {
    try {
        require_regular_file(file);
        return true;
    } catch (const Error& e) {
        // Nothing there is assimp's to report (a missing .mtl is a warning
        // of its own); something there that is no file is refused.
        if (e.code() == ErrorCode::file_not_found) return false;
        if (!refused_) refused_ = e;
        return false;
    }
}

bool RegularFilesOnly::Exists(const char* file) const {
    return allowed(file) && Assimp::DefaultIOSystem::Exists(file);
}

Assimp::IOStream* RegularFilesOnly::Open(const char* file, const char* mode) {
    // Writing is not an importer's business; only reads are checked.
    if (std::strchr(mode, 'w') == nullptr && !allowed(file)) return nullptr;
    return Assimp::DefaultIOSystem::Open(file, mode);
}

}  // namespace facet
