// Decoding image files (image_decoder.hpp): the one translation unit that
// holds stb_image's code.
#include "assets/image_decoder.hpp"

#include "facet/error.hpp"
#include "facet/memory.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdlib>
#include <iterator>
#include <tuple>

// Every buffer stb_image allocates starts as zeros: what a corrupt file
// leaves unwritten (a scan that ends early after a missing restart marker,
// a table or component the checks below do not foresee) is then black or
// zero, never another allocation's leftovers.
#define STBI_MALLOC(size) std::calloc(1, size)
#define STBI_REALLOC(p, size) std::realloc(p, size)
#define STBI_FREE(p) std::free(p)
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

// What a JPEG's markers have defined so far, for the checks stb_image
// (libstb 2022-09-08) does not make. stb_image allocates its decoder's
// tables and a component's samples (or, progressive, its coefficients)
// without clearing them, so a scan that uses a table the file never
// defined decodes with whatever memory held (an out-of-bounds read of a
// Huffman table, or quantization by garbage), and so does a component no
// scan codes: each is refused.
struct JpegDefined {
    std::string_view bytes;
    const std::string& source;
    bool huffman[2][4] = {};  // [0 DC, 1 AC][table], from DHT segments
    bool quant[4] = {};       // from DQT segments
    int quant_of[256];        // a frame component's table, by component id; -1: none
    unsigned ids[4] = {}, id_count = 0;  // the frame's components
    bool coded[256] = {};     // a component a scan codes (progressive: a first DC scan)
    bool progressive = false;

    JpegDefined(std::string_view b, const std::string& s) : bytes(b), source(s) {
        std::fill(std::begin(quant_of), std::end(quant_of), -1);
    }
    // A byte as stb_image reads it: zero past the end.
    unsigned at(size_t i) const { return i < bytes.size() ? static_cast<unsigned char>(bytes[i]) : 0; }

    [[noreturn]] void refuse(const std::string& why) const {
        throw Error(ErrorCode::texture_load_failed, "a JPEG " + why, source);
    }

    // DHT: stb_image writes each table's code lengths into 257 entries
    // without checking that its sixteen counts add up to at most 256.
    void huffman_tables(size_t p, size_t end) {
        while (p < std::min(end, bytes.size())) {
            size_t codes = 0;
            for (size_t i = 1; i <= 16; ++i) codes += at(p + i);
            if (codes > 256) refuse("Huffman table of " + std::to_string(codes) + " codes (at most 256)");
            const unsigned kind = at(p) >> 4, table = at(p) & 15;
            if (kind <= 1 && table <= 3) huffman[kind][table] = true;  // stb_image refuses others
            p += 17 + codes;
        }
    }
    void quant_tables(size_t p, size_t end) {
        while (p < std::min(end, bytes.size())) {
            const unsigned precision = at(p) >> 4, table = at(p) & 15;
            if (precision > 1 || table > 3) return;  // stb_image refuses it
            quant[table] = true;
            p += precision ? 129 : 65;
        }
    }
    // SOF0-2: each component's id and quantization table. stb_image matches
    // a scan's components to the first of an id.
    void frame(size_t p, unsigned marker) {
        progressive = marker == 0xC2;
        std::fill(std::begin(quant_of), std::end(quant_of), -1);
        std::fill(std::begin(coded), std::end(coded), false);
        id_count = 0;
        const unsigned components = at(p + 5);
        for (unsigned c = 0; c < components && c < 4; ++c) {
            const size_t q = p + 6 + 3 * c;
            if (at(q + 2) > 3) continue;  // stb_image refuses a table past 3
            if (quant_of[at(q)] >= 0)  // stb_image codes only the first of an id
                refuse("frame with two components of id " + std::to_string(at(q)));
            quant_of[at(q)] = int(at(q + 2));
            ids[id_count++] = at(q);
        }
    }
    // SOS: the tables this scan decodes with must have been defined.
    void scan(size_t p) {
        const unsigned components = std::min(at(p), 4u);
        const unsigned start = at(p + 1 + 2 * components), refining = at(p + 3 + 2 * components) >> 4;
        for (unsigned c = 0; c < components; ++c) {
            const unsigned id = at(p + 1 + 2 * c), dc = at(p + 2 + 2 * c) >> 4, ac = at(p + 2 + 2 * c) & 15;
            if (quant_of[id] < 0 || dc > 3 || ac > 3) continue;  // stb_image refuses the scan
            if (!quant[quant_of[id]])
                refuse("scan of component " + std::to_string(id) + ", whose quantization table " +
                       std::to_string(quant_of[id]) + " is not defined before it");
            const bool uses_dc = !progressive || (start == 0 && refining == 0);
            const bool uses_ac = !progressive || start > 0;
            coded[id] = coded[id] || uses_dc;
            for (const auto& [used, kind, table] : {std::tuple{uses_dc, 0, dc}, std::tuple{uses_ac, 1, ac}})
                if (used && !huffman[kind][table])
                    refuse(std::string("scan that uses ") + (kind ? "AC" : "DC") + " Huffman table " +
                           std::to_string(table) +
                           ", which is not defined before it (Motion-JPEG's implied "
                           "standard tables are not read)");
        }
    }
    // At the end of the image: every component coded (and so its
    // quantization table defined, which scan() checks).
    void finish() const {
        for (unsigned c = 0; c < id_count; ++c)
            if (!coded[ids[c]])
                refuse("component " + std::to_string(ids[c]) + " that no scan codes" +
                       (progressive ? " from its first DC scan" : "") +
                       ": its pixels would be memory the decoder never wrote");
    }
};

// A JPEG's markers, checked for what stb_image trusts (JpegDefined).
// Entropy-coded data is skipped to the next marker; what does not parse is
// left to stb_image to refuse.
void check_jpeg(std::string_view bytes, const std::string& source) {
    const auto u = [&](size_t i) { return static_cast<unsigned char>(bytes[i]); };
    // stb_image, as JPEG allows before any marker, skips fill bytes (0xFF)
    // before the start of the image.
    size_t at = 0;
    while (at < bytes.size() && u(at) == 0xFF) ++at;
    if (at == 0 || at + 3 > bytes.size() || u(at) != 0xD8) return;
    ++at;
    JpegDefined defined(bytes, source);
    while (at + 2 <= bytes.size()) {
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
        if (marker == 0xD9) {  // the end of the image
            defined.finish();
            return;
        }
        if (at + 4 > bytes.size()) return;  // a segment cut short: stb_image refuses it
        const size_t end = at + 2 + ((size_t(u(at + 2)) << 8) | u(at + 3));
        if (marker == 0xC4) defined.huffman_tables(at + 4, end);
        if (marker == 0xDB) defined.quant_tables(at + 4, end);
        if (marker >= 0xC0 && marker <= 0xC2) defined.frame(at + 4, marker);
        if (marker == 0xDA) defined.scan(at + 4);
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
