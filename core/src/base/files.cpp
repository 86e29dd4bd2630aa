#include "files.hpp"

#include "facet/error.hpp"

#include <cerrno>

namespace facet {

namespace fs = std::filesystem;

namespace {

const char* kind_name(fs::file_type type) {
    switch (type) {
        case fs::file_type::directory: return "a folder";
        case fs::file_type::fifo: return "a named pipe (FIFO)";
        case fs::file_type::socket: return "a socket";
        case fs::file_type::block: return "a block device";
        case fs::file_type::character: return "a character device";
        default: return "not a file facet can read";
    }
}

}  // namespace

void require_regular_file(const fs::path& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::regular) return;
    // A link that leads back to itself, or a path the system cannot
    // follow, is named as such: "not found" would send the user looking.
    if (ec && ec.value() != ENOENT && ec.value() != ENOTDIR && ec.value() != ENAMETOOLONG)
        throw Error(ErrorCode::not_a_file, "cannot reach it: " + ec.message(), path.string());
    if (ec || !fs::exists(status)) throw Error(ErrorCode::file_not_found, "", path.string());
    throw Error(ErrorCode::not_a_file, std::string("it is ") + kind_name(status.type()),
                path.string());
}

}  // namespace facet
