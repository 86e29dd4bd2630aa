#include "base/file_digest.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <vector>

namespace facet {

namespace {

// One 64-bit word into the state: multiply, rotate and multiply (the
// constants are odd, with well-mixed bits), so that every bit of the word
// reaches every bit of the state within two words.
uint64_t mix(uint64_t state, uint64_t word) {
    constexpr uint64_t k1 = 0x9E3779B97F4A7C15u, k2 = 0xC2B2AE3D27D4EB4Fu;
    return std::rotl((state ^ word) * k1, 29) * k2;
}

}  // namespace

// Chunks of a whole number of words, then the tail.
void BytesDigest::add(const void* p, size_t n) {
    const char* data = static_cast<const char*>(p);
    length_ += n;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t word;
        std::memcpy(&word, data + i, 8);
        state_ = mix(state_, word);
    }
    if (i < n) {  // the tail (only the last chunk has one: chunks are whole words)
        uint64_t word = 0;
        std::memcpy(&word, data + i, n - i);
        state_ = mix(state_, word ^ (uint64_t(n - i) << 56));
    }
}

uint64_t BytesDigest::value() const { return mix(state_, length_); }

std::optional<uint64_t> file_digest(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::vector<char> chunk(size_t(1) << 20);
    BytesDigest digest;
    while (in) {
        in.read(chunk.data(), std::streamsize(chunk.size()));
        digest.add(chunk.data(), size_t(in.gcount()));
    }
    if (in.bad()) return std::nullopt;
    return digest.value();
}

uint64_t bytes_digest(std::string_view bytes) {
    BytesDigest digest;
    digest.add(bytes.data(), bytes.size());
    return digest.value();
}

}  // namespace facet
