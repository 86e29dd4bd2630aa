// Radiance HDR preflight (hdr_check.hpp). The format: text header lines
// up to an empty one, a resolution line "-Y height +X width", then height
// scanlines, each either width flat 4-byte RGBE pixels or, for widths of
// 8 to 32767, "2 2 hi lo" (the width) and the four channels one after
// another, each as runs: a count over 128 repeats the next byte count -
// 128 times, any other count is followed by that many bytes. stb_image
// takes the first scanline's form for every one.
#include "assets/hdr_check.hpp"

#include "facet/error.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace facet {

namespace {

[[noreturn]] void refuse(const std::string& what, const std::string& source) {
    throw Error(ErrorCode::texture_load_failed, "a Radiance HDR file " + what, source);
}

// The next line from `at`, without its newline; false past the end.
bool next_line(std::string_view bytes, size_t& at, std::string_view& line) {
    if (at >= bytes.size()) return false;
    const size_t end = bytes.find('\n', at);
    const size_t stop = end == std::string_view::npos ? bytes.size() : end;
    line = bytes.substr(at, stop - at);
    at = end == std::string_view::npos ? bytes.size() : end + 1;
    return true;
}

// One scanline of run-length encoded channels at `at`, or false where the
// data ends or a run passes the line's end.
bool rle_scanline(std::string_view bytes, size_t& at, long width) {
    if (at + 4 > bytes.size()) return false;
    at += 4;  // "2 2 hi lo", checked by the caller on the first
    for (int channel = 0; channel < 4; ++channel)
        for (long count = 0; count < width;) {
            if (at >= bytes.size()) return false;
            const unsigned c = static_cast<unsigned char>(bytes[at++]);
            const long n = c > 128 ? long(c - 128) : long(c);  // a 0 is a literal of none
            if (count + n > width) return false;
            const size_t take = c > 128 ? 1 : size_t(n);
            if (at + take > bytes.size()) return false;
            at += take;
            count += n;
        }
    return true;
}

}  // namespace

bool looks_like_hdr(std::string_view bytes) {
    return bytes.starts_with("#?RADIANCE\n") || bytes.starts_with("#?RGBE\n");
}

void check_hdr(std::string_view bytes, const std::string& source) {
    size_t at = 0;
    std::string_view line;
    do {
        if (!next_line(bytes, at, line)) refuse("that ends in its header", source);
    } while (!line.empty());
    if (!next_line(bytes, at, line)) refuse("with no resolution line", source);
    long height = 0, width = 0;
    const std::string resolution(line);
    if (std::sscanf(resolution.c_str(), "-Y %ld +X %ld", &height, &width) != 2 || height <= 0 ||
        width <= 0)
        refuse("whose resolution line is not \"-Y height +X width\" (\"" + resolution.substr(0, 40) +
                   "\")",
               source);
    if (height > (1L << 24) || width > (1L << 24))  // stb_image's limit a side
        refuse("of " + std::to_string(width) + "x" + std::to_string(height) +
                   " pixels: more than 2^24 a side",
               source);
    const auto u = [&](size_t i) { return static_cast<unsigned char>(bytes[i]); };
    const bool rle = width >= 8 && width < 32768 && at + 4 <= bytes.size() && u(at) == 2 &&
                     u(at + 1) == 2 && !(u(at + 2) & 0x80);
    if (!rle) {
        const unsigned long long need = 4ull * (unsigned long long)(width) * (unsigned long long)(height);
        if (bytes.size() - at < need)
            refuse("that ends in scanline " + std::to_string((bytes.size() - at) / 4 / width + 1) +
                       " of " + std::to_string(height),
                   source);
        return;
    }
    for (long y = 0; y < height; ++y) {
        if (at + 4 <= bytes.size() &&
            (u(at) != 2 || u(at + 1) != 2 || ((long(u(at + 2)) << 8) | u(at + 3)) != width))
            refuse("whose scanline " + std::to_string(y + 1) + " of " + std::to_string(height) +
                       " does not start as a run-length encoded one of its width",
                   source);
        if (!rle_scanline(bytes, at, width))
            refuse("that ends or overruns in scanline " + std::to_string(y + 1) + " of " +
                       std::to_string(height),
                   source);
    }
}

}  // namespace facet
