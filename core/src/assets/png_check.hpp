// PNG integrity check, before decoding.
//
// Takes: an image file's bytes that start with the PNG signature.
// Gives: nothing if every chunk lies whole in the file with the CRC it
// carries, up to IEND; otherwise Error(texture_load_failed) naming the
// chunk, its place in the file and what is wrong with it.
//
// Why: stb_image checks no CRC, so a PNG whose bytes were damaged decodes
// to a wrong image without a word, and one cut short is reported as
// "1/2/4/8/16-bit only" or "outofdata". The CRCs say which it is.
#pragma once

#include <string>
#include <string_view>

namespace facet {

bool looks_like_png(std::string_view bytes);

void check_png(std::string_view bytes, const std::string& source);

}  // namespace facet
