#include "assets/decoder_peak.hpp"

#include <algorithm>

namespace facet {

namespace {

uint32_t big_endian16(std::string_view b, size_t at) {
    return uint32_t(uint8_t(b[at])) << 8 | uint8_t(b[at + 1]);
}

// PNG: IHDR is the first chunk (png_check made sure): bit depth at byte
// 24, colour type at 25, interlace at 28.
uint64_t png_peak(std::string_view b, uint64_t width, uint64_t height) {
    if (b.size() < 29) return 0;
    const uint64_t depth = uint8_t(b[24]), type = uint8_t(b[25]);
    const bool interlaced = uint8_t(b[28]) != 0;
    const uint64_t channels = type == 2 ? 3 : type == 4 ? 2 : type == 6 ? 4 : 1;
    const uint64_t bytes_per_channel = depth == 16 ? 2 : 1;
    const uint64_t raw = height * ((width * channels * depth + 7) / 8 + 1);
    const uint64_t image = width * height * 4 * bytes_per_channel;
    const uint64_t decoding = raw + image * (interlaced ? 3 : 2);
    const uint64_t to_8bit = depth == 16 ? image + width * height * 4 : 0;
    return std::max(decoding, to_8bit);
}

// JPEG: the first start-of-frame marker says progressive (SOF2, SOF6,
// SOF10, SOF14) or not, and the component count.
uint64_t jpeg_peak(std::string_view b, uint64_t width, uint64_t height) {
    const uint64_t samples = width * height, output = samples * 4;
    for (size_t at = 2; at + 9 < b.size();) {
        if (uint8_t(b[at]) != 0xFF) return output;  // not a marker: leave it to the decoder
        const uint8_t marker = uint8_t(b[at + 1]);
        if (marker == 0xFF) {  // fill byte
            ++at;
            continue;
        }
        const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 &&
                         marker != 0xCC;
        if (sof) {
            const uint64_t components = std::max<uint64_t>(1, uint8_t(b[at + 9]));
            const bool progressive = (marker & 3) == 2;
            return components * samples * (progressive ? 3 : 1) + output;
        }
        at += 2 + big_endian16(b, at + 2);
    }
    return output;
}

}  // namespace

uint64_t decoder_peak_bytes(std::string_view bytes, uint64_t width, uint64_t height) {
    constexpr char kPng[] = "\x89PNG";
    if (bytes.size() >= 4 && bytes.substr(0, 4) == std::string_view(kPng, 4))
        return png_peak(bytes, width, height);
    if (bytes.size() >= 2 && uint8_t(bytes[0]) == 0xFF && uint8_t(bytes[1]) == 0xD8)
        return jpeg_peak(bytes, width, height);
    return width * height * 8 * 2;
}

}  // namespace facet
