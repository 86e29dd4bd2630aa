// Radiance HDR (RGBE) preflight.
//
// Takes: a file's bytes that start as a Radiance HDR file does
// (looks_like_hdr: "#?RADIANCE" or "#?RGBE").
// Gives: nothing if its pixel data is whole; otherwise
// Error(texture_load_failed) naming the file and the scanline where it
// ends or goes wrong.
//
// Why: stb_image reads past the end of a truncated HDR file as zeros and
// reports success, so a file cut short loads as an image whose bottom rows
// are black. The scanlines are walked here (their run lengths, not their
// values) before it decodes them.
#pragma once

#include <string>
#include <string_view>

namespace facet {

bool looks_like_hdr(std::string_view bytes);

void check_hdr(std::string_view bytes, const std::string& source);

}  // namespace facet
