// What stb_image holds at its peak while it decodes an image, from the
// file's header, for the memory budget (texture.cpp's require_decodable).
//
// Takes: the file's bytes, and the size stbi_info found in them.
// Gives: the bytes the decoder holds at once besides the file, as far as
// the format tells before decoding:
//   PNG: the inflated rows (channels and bit depth from IHDR), and the
//        image in the file's bit depth, twice while it is converted to
//        RGBA, three times for an interlaced (Adam7) file; a 16-bit file
//        then costs its 8-bit copy as well;
//   JPEG: for a progressive file, the coefficients of every component (2
//        bytes a sample), its planes and the RGBA output; for a baseline
//        file, the planes and the output;
//   any other format: the image in 16-bit RGBA, decoded and converted.
//
// Why: a 777 KB 16-bit PNG that decodes to 0.87 GiB held 1.5 GiB on the
// way; a progressive 10000x10000 JPEG, more than its RGBA.
#pragma once

#include <cstdint>
#include <string_view>

namespace facet {

uint64_t decoder_peak_bytes(std::string_view bytes, uint64_t width, uint64_t height);

}  // namespace facet
