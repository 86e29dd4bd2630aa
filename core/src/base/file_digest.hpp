// What a file holds, as a 64-bit digest: hot reload tells a change of
// content from a touch (an editor saving the same bytes, a build linking
// the same library again) and applies only the first.
//
// Takes: a path. Gives: the digest of its bytes, or nothing when it cannot
// be read. Not cryptographic: it tells edits apart, not adversaries.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>

namespace facet {

std::optional<uint64_t> file_digest(const std::filesystem::path& path);
// The same of bytes in memory: a file's digest is that of its bytes.
uint64_t bytes_digest(std::string_view bytes);

// The same of bytes that come in parts: each part but the last a whole
// number of 8-byte words. The parts' digest is that of their bytes joined.
class BytesDigest {
public:
    void add(const void* data, size_t n);
    uint64_t value() const;

private:
    uint64_t state_ = 0x243F6A8885A308D3u, length_ = 0;
};

}  // namespace facet
