#include "assets/png_check.hpp"

#include "facet/error.hpp"

#include <zlib.h>

#include <cstdint>
#include <cstdio>

namespace facet {

namespace {

constexpr std::string_view kSignature("\x89PNG\r\n\x1a\n", 8);

uint32_t big_endian(std::string_view bytes, size_t at) {
    const auto b = [&](size_t i) { return uint32_t(uint8_t(bytes[at + i])); };
    return b(0) << 24 | b(1) << 16 | b(2) << 8 | b(3);
}

// A chunk type as text, its four letters (or their codes, if not letters).
std::string type_text(std::string_view type) {
    std::string out = "'";
    for (const char c : type) {
        if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')) {
            out += c;
        } else {
            char code[8];
            std::snprintf(code, sizeof code, "\\x%02x", unsigned(uint8_t(c)));
            out += code;
        }
    }
    return out + "'";
}

[[noreturn]] void png_fail(const std::string& source, const std::string& why) {
    throw Error(ErrorCode::texture_load_failed, "PNG: " + why, source);
}

}  // namespace

bool looks_like_png(std::string_view bytes) { return bytes.substr(0, 8) == kSignature; }

void check_png(std::string_view bytes, const std::string& source) {
    size_t at = kSignature.size();
    for (;;) {
        if (bytes.size() - at < 12)
            png_fail(source, "the file ends at byte " + std::to_string(bytes.size()) +
                                 " before its IEND chunk: it is cut short");
        const uint32_t length = big_endian(bytes, at);
        const std::string_view type = bytes.substr(at + 4, 4);
        const std::string where = "chunk " + type_text(type) + " at byte " + std::to_string(at);
        if (length > bytes.size() - at - 12)
            png_fail(source, where + " says it holds " + std::to_string(length) +
                                 " bytes, but the file ends " +
                                 std::to_string(bytes.size() - at - 8) +
                                 " bytes on: it is cut short");
        const std::string_view body = bytes.substr(at + 4, 4 + size_t(length));
        const uint32_t computed =
            uint32_t(crc32_z(0L, reinterpret_cast<const Bytef*>(body.data()), body.size()));
        const uint32_t stored = big_endian(bytes, at + 8 + length);
        if (computed != stored) {
            char crcs[64];
            std::snprintf(crcs, sizeof crcs, " (it carries 0x%08x, its bytes give 0x%08x)",
                          unsigned(stored), unsigned(computed));
            png_fail(source, where + " fails its CRC" + crcs + ": the file is damaged");
        }
        if (type == "IEND") return;
        at += 12 + size_t(length);
    }
}

}  // namespace facet
