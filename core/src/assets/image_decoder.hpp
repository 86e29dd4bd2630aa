// Decoding image files: stb_image, compiled into facet here and nowhere
// else, its functions private to image_decoder.cpp.
//
// Takes: an image file's bytes (PNG, JPEG, TGA, BMP, PSD, GIF, PNM, HDR).
// Gives: its size and channels from the header; its pixels, 8 bits a
// channel, or for a Radiance HDR file linear floats; an Error naming the
// source where the file cannot be decoded.
//
// Why here: libdraco, which assimp links, carries a copy of stb_image of
// its own and exports its functions under the same names, so calls by name
// went to whichever library the program found first: an older copy, in
// every program but the viewer. Compiled here from the libstb-dev header
// (STB_IMAGE_STATIC), facet decodes with the version the build saw, the
// one its preflights (png_check, hdr_check, decoder_peak, and the PNM and
// JPEG checks in image_decoder.cpp) were written against.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace facet {

struct ImageInfo {
    int width = 0, height = 0, channels = 0;
    bool hdr = false;  // a Radiance HDR file: decode_float_rgb
};

// The header's size and channels, or nothing where it is not an image
// (image_failure_reason() then says why). Throws
// Error(texture_load_failed) naming `source` for a file the preflights
// refuse before stb_image reads it.
std::optional<ImageInfo> image_info(std::string_view bytes, const std::string& source);
// Why the last call on this thread failed, in stb_image's words.
std::string image_failure_reason();

struct Pixels8 {
    std::unique_ptr<uint8_t[], void (*)(uint8_t*)> data{nullptr, nullptr};
    int width = 0, height = 0;
    int file_channels = 0;  // as the file has them; data holds the asked-for count
};

// The pixels with `channels` (1..4) channels a pixel. Throws
// Error(texture_load_failed) with the reason, Error(over_budget) when the
// decoder runs out of memory.
Pixels8 decode_8bit(std::string_view bytes, int channels, const std::string& source);

// A Radiance HDR file's linear RGB, width * height * 3 floats. Throws as
// decode_8bit.
std::vector<float> decode_float_rgb(std::string_view bytes, const std::string& source, int& width,
                                    int& height);

}  // namespace facet
