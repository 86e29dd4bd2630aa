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
        refused_.push_back(e);
        return false;
    }
}

std::optional<Error> RegularFilesOnly::refused() const {
    if (refused_.empty()) return std::nullopt;
    return refused_.front();
}

bool RegularFilesOnly::Exists(const char* file) const {
    return allowed(file) && Assimp::DefaultIOSystem::Exists(file);
}

Assimp::IOStream* RegularFilesOnly::Open(const char* file, const char* mode) {
    // Writing is not an importer's business; only reads are checked.
    if (std::strchr(mode, 'w') == nullptr && !allowed(file)) return nullptr;
    Assimp::IOStream* stream = Assimp::DefaultIOSystem::Open(file, mode);
    if (stream) {
        // A file of this name found at a later place stands in for one
        // refused at an earlier place.
        const std::filesystem::path name = std::filesystem::path(file).filename();
        std::erase_if(refused_, [&](const Error& e) {
            return std::filesystem::path(e.file()).filename() == name;
        });
    }
    return stream;
}

}  // namespace facet
