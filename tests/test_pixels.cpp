// Colour formats: the scalar codecs of framebuffer.hpp against their
// definitions in double precision, and every instruction-set path's vector
// codecs and row kernels (kernels.hpp) against the scalar codecs, bit for
// bit, over the values where rounding decides: each sRGB code's threshold,
// each table bucket's edges, each half float's midpoints, and the special
// values. And the sRGB PNG a framebuffer writes.
#include "base/srgb8_tables.hpp"
#include "pipeline/kernels.hpp"
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/framebuffer.hpp>
#include <facet/isa.hpp>

#include <catch2/catch.hpp>

#include <stb/stb_image.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace facet;
using facet::test::TempDir;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

double srgb_decode(double e) { return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4); }

// The floats on both sides of `x`, and x.
void around(std::vector<float>& out, float x, int ulps = 2) {
    float v = x;
    for (int i = 0; i < ulps; ++i) v = std::nextafter(v, -kInf);
    for (int i = 0; i <= 2 * ulps; ++i, v = std::nextafter(v, kInf)) out.push_back(v);
}

// Floats where some codec's result changes, and others anywhere.
std::vector<float> hard_values() {
    std::vector<float> v = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f, 1e-45f, -1e-45f, 1e-38f,
                            65504.0f, 65519.99f, 65520.0f, 1e30f, -1e30f, kInf, -kInf,
                            std::numeric_limits<float>::quiet_NaN(),
                            -std::numeric_limits<float>::quiet_NaN()};
    for (int c = 1; c < 256; ++c) {
        around(v, kSrgb8.threshold[c]);
        around(v, (float(c) - 0.5f) / 255.0f);  // alpha's rounding edges
    }
    for (int b = 0; b <= Srgb8Tables::kBuckets; ++b)
        around(v, std::bit_cast<float>(uint32_t(b + Srgb8Tables::kFirstBucket) << 16), 1);
    for (uint32_t h = 0; h < 0x7C00u; ++h) {  // each positive finite half and the midpoint above
        const float a = half_to_float(uint16_t(h)), b = half_to_float(uint16_t(h + 1));
        v.push_back(a);
        around(v, a + (b - a) / 2, 1);
    }
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<uint32_t> bits;
    for (int i = 0; i < 200000; ++i) v.push_back(unit(rng));
    for (int i = 0; i < 50000; ++i) v.push_back(std::bit_cast<float>(bits(rng)));
    return v;
}

// The values as pixels: each in every channel.
std::vector<glm::vec4> pixels(const std::vector<float>& values) {
    std::vector<glm::vec4> out;
    for (float x : values) out.emplace_back(x);
    return out;
}

bool same_float(float a, float b) {
    return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b) || (a != a && b != b);
}

}  // namespace

TEST_CASE("half floats: the scalar codec is exact, rounds to nearest even", "[pixels]") {
    for (uint32_t h = 0; h < 0x10000u; ++h) {
        const uint32_t e = h >> 10 & 0x1Fu, m = h & 0x3FFu;
        const double magnitude = e == 0    ? std::ldexp(double(m), -24)
                                 : e == 31 ? (m ? std::nan("") : double(kInf))
                                           : std::ldexp(double(m | 0x400u), int(e) - 25);
        const double want = h & 0x8000u ? -magnitude : magnitude;
        const float got = half_to_float(uint16_t(h));
        REQUIRE((std::isnan(want) ? std::isnan(got) : double(got) == want));
        if (!std::isnan(want)) REQUIRE(float_to_half(got) == h);
    }
    // Ties go to the even neighbour; above the largest half, infinity.
    CHECK(float_to_half(1.0f + 0x1p-11f) == float_to_half(1.0f));
    CHECK(float_to_half(1.0f + 3 * 0x1p-11f) == float_to_half(1.0f + 0x1p-9f));
    CHECK(float_to_half(0x1p-25f) == 0);  // half the least subnormal: to even, 0
    CHECK(float_to_half(std::nextafter(0x1p-25f, 1.0f)) == 1);
    CHECK(float_to_half(65519.99f) == 0x7BFF);
    CHECK(float_to_half(65520.0f) == 0x7C00);
    CHECK(std::isnan(half_to_float(float_to_half(std::nanf("")))));
}

TEST_CASE("sRGB codes decode correctly rounded; alpha rounds halves away from zero",
          "[pixels]") {
    for (int c = 0; c < 256; ++c) {
        REQUIRE(srgb8_to_linear(uint8_t(c)) == float(srgb_decode(c / 255.0)));
        REQUIRE(linear_to_srgb8(srgb8_to_linear(uint8_t(c))) == c);
    }
    for (int c = 0; c < 255; ++c) {
        const float half = (float(c) + 0.5f) / 255.0f;  // 255 * half rounds to c + 0.5 or near
        const float product = half * 255.0f;
        CHECK(unorm8(half) == int(std::floor(double(product) + 0.5)));
    }
    CHECK(unorm8(-0.2f) == 0);
    CHECK(unorm8(1.5f) == 255);
    CHECK(unorm8(std::nanf("")) == 0);
}

TEST_CASE("every path's vector codecs give the scalar codecs' bits", "[pixels]") {
    const std::vector<float> values = hard_values();
    const std::vector<glm::vec4> linear = pixels(values);
    for (Isa isa : supported_isas())
        for (ColorFormat format : {ColorFormat::srgb8, ColorFormat::rgba16f, ColorFormat::rgba32f}) {
            INFO("path " << isa_name(isa) << ", " << color_format_name(format));
            const size_t bytes = size_t(bytes_per_pixel(format));
            std::vector<uint8_t> encoded(linear.size() * bytes);
            kernels(isa).encode_pixels(format, linear.data(), linear.size(), encoded.data());
            uint8_t want[16];
            for (size_t i = 0; i < linear.size(); ++i) {
                encode_pixel(format, linear[i], want);
                INFO("value " << values[i] << " (bits " << std::bit_cast<uint32_t>(values[i]) << ")");
                REQUIRE(std::memcmp(&encoded[i * bytes], want, bytes) == 0);
            }
            std::vector<glm::vec4> decoded(linear.size());
            kernels(isa).decode_pixels(format, encoded.data(), linear.size(), decoded.data());
            for (size_t i = 0; i < linear.size(); ++i) {
                const glm::vec4 w = decode_pixel(format, &encoded[i * bytes]);
                for (int c = 0; c < 4; ++c) REQUIRE(same_float(decoded[i][c], w[c]));
            }
        }
}

TEST_CASE("every path clears, resolves and converts to 8 bits as the scalar codecs do",
          "[pixels][msaa]") {
    const glm::vec4 clear(0.2f, 0.73f, 1.7f, 0.5f);
    for (Isa isa : supported_isas())
        for (ColorFormat format : {ColorFormat::srgb8, ColorFormat::rgba16f, ColorFormat::rgba32f}) {
            INFO("path " << isa_name(isa) << ", " << color_format_name(format));
            const Kernels& k = kernels(isa);
            // A width that is no multiple of anything, with a stencil buffer.
            Framebuffer fb(37, 11, format, 4, true);
            // In pieces, as a pipeline clears tiles: whole rows streamed, then
            // the rest in two rectangles, one through the cache.
            k.clear_rect(fb, 0, 0, fb.stride(), 5, clear, 0.25f, 0x5A, true);
            k.clear_rect(fb, 0, 5, 16, fb.rows(), clear, 0.25f, 0x5A, false);
            k.clear_rect(fb, 16, 5, fb.stride(), fb.rows(), clear, 0.25f, 0x5A, true);
            uint8_t px[16];
            encode_pixel(format, clear, px);
            const glm::vec4 stored = decode_pixel(format, px);
            // Sample s of each pixel gets a colour of its own; the resolve is
            // their mean in linear light, encoded.
            std::mt19937 rng(5);
            std::uniform_real_distribution<float> unit(0.0f, 1.0f);
            const size_t bytes = size_t(bytes_per_pixel(format));
            std::vector<glm::vec4> means;
            for (int y = 0; y < fb.height(); ++y)
                for (int x = 0; x < fb.width(); ++x) {
                    glm::vec4 sum(0.0f);
                    for (int s = 0; s < 4; ++s) {
                        REQUIRE(fb.sample(x, y, s) == stored);
                        REQUIRE(fb.sample_depth_at(x, y, s) == 0.25f);
                        REQUIRE(fb.sample_stencil_at(x, y, s) == 0x5A);
                        if (x % 3 == 0) {
                            sum += stored;
                            continue;  // some pixels keep the clear colour
                        }
                        const glm::vec4 c(unit(rng), unit(rng), 4.0f * unit(rng), unit(rng));
                        uint8_t* at = fb.sample_color_data() +
                                      ((size_t(y) * fb.stride() + x) * 4 + s) * bytes;
                        encode_pixel(format, c, at);
                        sum += decode_pixel(format, at);
                    }
                    means.push_back(sum * 0.25f);
                }
            k.resolve_rows(fb, 0, fb.height());
            std::vector<uint8_t> srgb(size_t(fb.width()) * fb.height() * 4);
            k.srgb8_rows(fb, 0, fb.height(), srgb.data());
            for (int y = 0, i = 0; y < fb.height(); ++y)
                for (int x = 0; x < fb.width(); ++x, ++i) {
                    encode_pixel(format, means[size_t(i)], px);
                    REQUIRE(fb.pixel(x, y) == decode_pixel(format, px));
                    REQUIRE(fb.depth_at(x, y) == 0.25f);
                    uint8_t want[4];
                    encode_pixel(ColorFormat::srgb8, fb.pixel(x, y), want);
                    REQUIRE(std::memcmp(&srgb[size_t(i) * 4], want, 4) == 0);
                }
        }
}

// The bucket scheme of srgb8_tables.hpp against its definition, for every
// float where the code can change: the code of x is the number of
// thresholds at or below it, minus one. Below 2^-14 every float is code 0
// (threshold[1] is 1.5e-4). Sanitizer builds, many times slower, take every
// 13th float.
TEST_CASE("every float from 2^-14 to 1 encodes to its sRGB code, on every path", "[pixels]") {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    constexpr uint32_t step = 13;
#else
    constexpr uint32_t step = 1;
#endif
    const uint32_t first = std::bit_cast<uint32_t>(0x1p-14f), last = std::bit_cast<uint32_t>(1.0f);
    REQUIRE(0x1p-14f < kSrgb8.threshold[1]);
    constexpr size_t kChunk = 1 << 18;  // pixels at a time, three floats each
    std::vector<glm::vec4> linear(kChunk);
    std::vector<uint8_t> want(kChunk * 3), encoded(kChunk * 4);
    for (Isa isa : supported_isas()) {
        INFO("path " << isa_name(isa));
        int code = 0;
        for (uint32_t bits = first; bits <= last;) {
            size_t n = 0;
            for (; n < kChunk && bits <= last; ++n) {
                for (int c = 0; c < 3; ++c, bits += step) {
                    const float x = std::bit_cast<float>(std::min(bits, last));
                    while (x >= kSrgb8.threshold[code + 1]) ++code;
                    linear[n][c] = x;
                    want[n * 3 + size_t(c)] = uint8_t(code);
                }
                linear[n][3] = 1.0f;
            }
            kernels(isa).encode_pixels(ColorFormat::srgb8, linear.data(), n, encoded.data());
            for (size_t i = 0; i < n; ++i)
                for (int c = 0; c < 3; ++c) {
                    const int expected = want[i * 3 + size_t(c)];
                    if (encoded[i * 4 + size_t(c)] == expected &&
                        linear_to_srgb8(linear[i][c]) == expected)
                        continue;
                    INFO("value " << linear[i][c] << " (bits "
                                  << std::bit_cast<uint32_t>(linear[i][c]) << ")");
                    REQUIRE(int(linear_to_srgb8(linear[i][c])) == expected);
                    REQUIRE(int(encoded[i * 4 + size_t(c)]) == expected);
                }
        }
        CHECK(code == 255);
    }
}

TEST_CASE("sRGB resolve matches the transfer function, and PNGs round-trip", "[framebuffer]") {
    for (int code = 0; code < 256; ++code) {
        const double encoded = code / 255.0;
        const double linear = encoded <= 0.04045 ? encoded / 12.92
                                                 : std::pow((encoded + 0.055) / 1.055, 2.4);
        REQUIRE(linear_to_srgb8(float(linear)) == code);
    }
    CHECK(linear_to_srgb8(-1.0f) == 0);
    CHECK(linear_to_srgb8(7.0f) == 255);
    // Against the transfer function in double precision, rounded: every
    // float in a dense sweep of 0..1 and on both sides of each code's edge.
    auto reference = [](float v) {
        const double l = v, e = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
        return int(std::floor(e * 255.0 + 0.5));
    };
    for (int i = 0; i <= 1 << 20; ++i) {
        const float v = float(i) / float(1 << 20);
        REQUIRE(int(linear_to_srgb8(v)) == reference(v));
    }
    for (int code = 1; code < 256; ++code) {
        const double e = (code - 0.5) / 255.0;
        const float edge = float(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
        for (float v = std::nextafter(edge, 0.0f), k = 0; k < 3; ++k, v = std::nextafter(v, 2.0f))
            REQUIRE(int(linear_to_srgb8(v)) == reference(v));
    }
    CHECK(linear_to_srgb8(std::nanf("")) == 0);

    Framebuffer fb(5, 3);
    fb.clear({0.2f, 0.5f, 1.0f, 0.5f}, 0.0f);
    fb.set_pixel(4, 2, {1.0f, 0.0f, 0.0f, 1.0f});
    const TempDir folder("png");
    const std::filesystem::path& dir = folder.path;
    fb.write_png(dir / "out.png");
    int w = 0, h = 0, n = 0;
    unsigned char* px = stbi_load((dir / "out.png").c_str(), &w, &h, &n, 4);
    REQUIRE(px);
    CHECK((w == 5 && h == 3));
    CHECK(int(px[0]) == linear_to_srgb8(0.2f));
    CHECK(int(px[3]) == 128);
    CHECK(int(px[(2 * 5 + 4) * 4]) == 255);
    stbi_image_free(px);
    CHECK_THROWS_AS(fb.write_png(dir / "no-such-dir" / "x.png"), Error);
    CHECK_THROWS_AS(fb.resize(0, 10), Error);
}
