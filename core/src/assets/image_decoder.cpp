// Decoding image files (image_decoder.hpp): the one translation unit that
// holds stb_image's code.
#include "assets/image_decoder.hpp"

#include "facet/error.hpp"
#include "facet/memory.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdlib>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

namespace facet {

namespace {

const stbi_uc* data_of(std::string_view bytes) {
    return reinterpret_cast<const stbi_uc*>(bytes.data());
}

int size_of(std::string_view bytes, const std::string& source) {
    if (bytes.size() > size_t(INT_MAX))
        throw Error(ErrorCode::texture_load_failed, "an image over 2 GiB", source);
    return int(bytes.size());
}

// A binary PNM (P5 or P6) of more than 8 bits a sample: stb_image reads its
// 16-bit samples into a buffer sized for 8 bits when it converts them to
// another channel count (libstb 2022-09-08), so it is refused here; and
// one whose width or height has more digits than an int holds, which
// stb_image's parse of them overflows.
void check_pnm(std::string_view bytes, const std::string& source) {
    if (bytes.size() < 3 || bytes[0] != 'P' || (bytes[1] != '5' && bytes[1] != '6')) return;
    size_t at = 2;
    long values[3] = {};
    for (long& v : values) {
        while (at < bytes.size() && (std::isspace(static_cast<unsigned char>(bytes[at])) || bytes[at] == '#')) {
            if (bytes[at] == '#')
                while (at < bytes.size() && bytes[at] != '\n' && bytes[at] != '\r') ++at;
            else
                ++at;
        }
        for (; at < bytes.size() && std::isdigit(static_cast<unsigned char>(bytes[at])); ++at)
            v = std::min(v * 10 + (bytes[at] - '0'), 1L << 30);  // every digit, saturated
    }
    if (values[0] > (1L << 24) || values[1] > (1L << 24))  // and stb_image's int parse overflows
        throw Error(ErrorCode::texture_load_failed,
                    "a PNM image of " + std::to_string(values[0]) + "x" + std::to_string(values[1]) +
                        " pixels: more than 2^24 a side",
                    source);
    if (values[2] > 255)
        throw Error(ErrorCode::texture_load_failed,
                    "a PNM image of 16 bits a sample (maximum value " + std::to_string(values[2]) +
                        "): facet reads 8-bit PNM only; convert it to PNG",
                    source);
}

// A JPEG's Huffman tables (DHT segments, before and between scans): stb_image
// writes each table's code lengths into 257 entries without checking that
// its sixteen counts add up to at most 256 (libstb 2022-09-08), so a table
// of more codes is refused here. Entropy-coded data is skipped to the next
// marker; what does not parse is left to stb_image to refuse.
void check_jpeg(std::string_view bytes, const std::string& source) {
    const auto u = [&](size_t i) { return static_cast<unsigned char>(bytes[i]); };
    // stb_image, as JPEG allows before any marker, skips fill bytes (0xFF)
    // before the start of the image.
    size_t at = 0;
    while (at < bytes.size() && u(at) == 0xFF) ++at;
    if (at == 0 || at + 3 > bytes.size() || u(at) != 0xD8) return;
    ++at;
    while (at + 4 <= bytes.size()) {
        if (u(at) != 0xFF) {  // entropy-coded data: on to the next marker
            ++at;
            continue;
        }
        const unsigned marker = u(at + 1);
        if (marker == 0x00 || marker == 0xFF || marker == 0x01 || marker == 0xD8 ||
            (marker >= 0xD0 && marker <= 0xD7)) {  // stuffing, fill, or no length
            at += marker == 0xFF ? 1 : 2;
            continue;
        }
        if (marker == 0xD9) return;  // the end of the image
        const size_t end = at + 2 + ((size_t(u(at + 2)) << 8) | u(at + 3));
        if (marker == 0xC4)
            for (size_t p = at + 4; p < std::min(end, bytes.size());) {
                size_t codes = 0;  // stb_image reads past the end as zeros
                for (size_t i = 1; i <= 16 && p + i < bytes.size(); ++i) codes += u(p + i);
                if (codes > 256)
                    throw Error(ErrorCode::texture_load_failed,
                                "a JPEG Huffman table of " + std::to_string(codes) +
                                    " codes (at most 256)",
                                source);
                p += 17 + codes;
            }
        at = end;
    }
}

[[noreturn]] void failed(const std::string& source) {
    const std::string reason = stbi_failure_reason() ? stbi_failure_reason() : "unknown";
    if (reason == "outofmem")
        throw Error(ErrorCode::over_budget,
                    "the decoder ran out of memory" +
                        std::string(address_space_cap() ? " at the address space cap (the memory "
                                                          "budget, --max-memory, and what the "
                                                          "program maps)"
                                                        : ""),
                    source);
    throw Error(ErrorCode::texture_load_failed, reason, source);
}

}  // namespace

std::optional<ImageInfo> image_info(std::string_view bytes, const std::string& source) {
    if (bytes.size() > size_t(INT_MAX)) return std::nullopt;
    check_pnm(bytes, source);
    check_jpeg(bytes, source);
    ImageInfo info;
    if (!stbi_info_from_memory(data_of(bytes), int(bytes.size()), &info.width, &info.height,
                               &info.channels))
        return std::nullopt;
    info.hdr = stbi_is_hdr_from_memory(data_of(bytes), int(bytes.size()));
    return info;
}

std::string image_failure_reason() {
    return stbi_failure_reason() ? stbi_failure_reason() : "unknown";
}

Pixels8 decode_8bit(std::string_view bytes, int channels, const std::string& source) {
    const int size = size_of(bytes, source);
    check_pnm(bytes, source);
    check_jpeg(bytes, source);
    Pixels8 p;
    stbi_uc* data = stbi_load_from_memory(data_of(bytes), size, &p.width, &p.height,
                                          &p.file_channels, channels);
    if (!data) failed(source);
    p.data = {data, [](uint8_t* d) { stbi_image_free(d); }};
    return p;
}

std::vector<float> decode_float_rgb(std::string_view bytes, const std::string& source, int& width,
                                    int& height) {
    const int size = size_of(bytes, source);
    int channels = 0;
    float* data = stbi_loadf_from_memory(data_of(bytes), size, &width, &height, &channels, 3);
    if (!data) failed(source);
    std::vector<float> rgb(data, data + size_t(width) * size_t(height) * 3);
    stbi_image_free(data);
    return rgb;
}

}  // namespace facet
