#include "assets/glb_check.hpp"

#include "facet/error.hpp"

#include <cctype>
#include <cstdint>
#include <fstream>
#include <string>

namespace facet {

namespace {

constexpr uint32_t kMagic = 0x46546C67;      // "glTF", little-endian
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"

// A little-endian uint32 at `in`'s position; false at the end of the file.
bool read_u32(std::istream& in, uint32_t& v) {
    unsigned char b[4];
    if (!in.read(reinterpret_cast<char*>(b), 4)) return false;
    v = uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    return true;
}

[[noreturn]] void glb_fail(const std::filesystem::path& path, const std::string& why) {
    throw Error(ErrorCode::mesh_load_failed, "GLB: " + why, path.string());
}

std::string bytes(uint64_t n) { return std::to_string(n) + (n == 1 ? " byte" : " bytes"); }

}  // namespace

bool looks_like_glb(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    uint32_t magic = 0;
    return read_u32(in, magic) && magic == kMagic;
}

void check_glb(const std::filesystem::path& path) {
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    uint32_t magic = 0, version = 0, length = 0;
    if (ec || !read_u32(in, magic) || !read_u32(in, version) || !read_u32(in, length))
        glb_fail(path, "the file ends inside its 12-byte header");
    if (version != 1 && version != 2)
        glb_fail(path, "version " + std::to_string(version) + ", where 2 (or 1) was expected");
    if (length > size)
        glb_fail(path, "the header says the file has " + bytes(length) + ", but it has " +
                           bytes(size));
    // Version 1 (KHR_binary_glTF): one JSON content of contentLength bytes.
    // Version 2: chunks of 8 bytes of length and type and then their data,
    // the first of them JSON.
    uint64_t at = 12;
    for (int chunk = 0; at < length; ++chunk) {
        uint32_t chunk_length = 0, type = 0;
        if (length - at < 8 || !read_u32(in, chunk_length) || !read_u32(in, type))
            glb_fail(path, "the file ends inside the header of chunk " + std::to_string(chunk));
        if (chunk == 0 && version == 2 && type != kChunkJson)
            glb_fail(path, "the first chunk is not the JSON chunk");
        if (chunk_length > length - at - 8)
            glb_fail(path, "chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) +
                               " says it holds " + bytes(chunk_length) + ", but only " +
                               bytes(length - at - 8) + " follow");
        if (version == 1) return;  // the binary body is the rest
        at += 8 + uint64_t(chunk_length);
        in.seekg(std::streamoff(at));
    }
    if (at == 12) glb_fail(path, "no JSON chunk");
}

void check_gltf_name(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".glb" && ext != ".gltf") return;
    std::ifstream in(path, std::ios::binary);
    char head[64] = {};
    in.read(head, sizeof head);
    const size_t n = size_t(in.gcount());
    if (ext == ".glb" && !(n >= 4 && std::string(head, 4) == "glTF") &&
        !(n > 0 && head[0] == '{'))  // some write a .gltf's JSON under .glb
        throw Error(ErrorCode::mesh_load_failed,
                    "it is named .glb but is no GLB file: it does not start with 'glTF'",
                    path.string());
    size_t i = n >= 3 && std::string(head, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // a UTF-8 BOM
    while (i < n && std::isspace(static_cast<unsigned char>(head[i]))) ++i;
    if (ext == ".gltf" && !(i < n && head[i] == '{') && !(n >= 4 && std::string(head, 4) == "glTF"))
        throw Error(ErrorCode::mesh_load_failed,
                    "it is named .gltf but is no glTF file: it does not start with a JSON object",
                    path.string());
}

}  // namespace facet
