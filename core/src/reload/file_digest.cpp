#include "reload/file_digest.hpp"

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

std::optional<uint64_t> file_digest(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::vector<char> chunk(size_t(1) << 20);
    uint64_t state = 0x243F6A8885A308D3u, length = 0;
    while (in) {
        in.read(chunk.data(), std::streamsize(chunk.size()));
        const size_t n = size_t(in.gcount());
        length += n;
        size_t i = 0;
        for (; i + 8 <= n; i += 8) {
            uint64_t word;
            std::memcpy(&word, chunk.data() + i, 8);
            state = mix(state, word);
        }
        if (i < n) {  // the tail (only the last chunk has one: chunks are whole words)
            uint64_t word = 0;
            std::memcpy(&word, chunk.data() + i, n - i);
            state = mix(state, word ^ (uint64_t(n - i) << 56));
        }
    }
    if (in.bad()) return std::nullopt;
    return mix(state, length);
}

}  // namespace facet
