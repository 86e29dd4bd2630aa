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
// another channel count (libstb 2022-09-08), so it is refused here.
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
    if (values[2] > 255)
        throw Error(ErrorCode::texture_load_failed,
                    "a PNM image of 16 bits a sample (maximum value " + std::to_string(values[2]) +
                        "): facet reads 8-bit PNM only; convert it to PNG",
                    source);
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

std::optional<ImageInfo> image_info(std::string_view bytes) {
    if (bytes.size() > size_t(INT_MAX)) return std::nullopt;
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
