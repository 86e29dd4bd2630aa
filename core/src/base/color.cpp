// Colour formats and their codecs (facet/color.hpp), and the exact 8-bit
// sRGB tables (srgb8_tables.hpp) the per-path kernels share.
#include "facet/color.hpp"

#include "base/srgb8_tables.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace facet {

std::string_view color_format_name(ColorFormat format) {
    switch (format) {
        case ColorFormat::none: return "none";
        case ColorFormat::srgb8: return "srgb8";
        case ColorFormat::rgba16f: return "rgba16f";
        case ColorFormat::rgba32f: return "rgba32f";
    }
    return "?";
}

std::optional<ColorFormat> parse_color_format(std::string_view name) {
    for (ColorFormat f : {ColorFormat::none, ColorFormat::srgb8, ColorFormat::rgba16f,
                          ColorFormat::rgba32f})
        if (name == color_format_name(f)) return f;
    return std::nullopt;
}

namespace {

// The exact curve, in double precision.
double srgb_decode(double e) { return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4); }

float bucket_first(int b) {
    return std::bit_cast<float>(uint32_t(b + Srgb8Tables::kFirstBucket) << 16);
}

}  // namespace

Srgb8Tables::Srgb8Tables() {
    threshold[0] = 0.0f;
    for (int c = 1; c < 256; ++c) {
        const double x = srgb_decode((c - 0.5) / 255.0);
        float t = float(x);
        if (double(t) < x) t = std::nextafter(t, 2.0f);
        threshold[c] = t;
    }
    threshold[256] = std::numeric_limits<float>::infinity();
    for (int c = 0; c < 256; ++c) decode[c] = float(srgb_decode(c / 255.0));
    int c = 0;
    for (int b = 0; b < kBuckets; ++b) {
        const float first = bucket_first(b), last = std::nextafter(bucket_first(b + 1), 0.0f);
        while (first >= threshold[c + 1]) ++c;
        // The bucket must hold at most one threshold (see srgb8_tables.hpp).
        if (last >= threshold[std::min(c + 2, 256)]) std::abort();
        const uint32_t next = std::bit_cast<uint32_t>(threshold[c + 1]);
        const bool inside = threshold[c + 1] <= last;
        bucket[b] = int32_t(c) << 17 | int32_t(inside ? next & 0xFFFFu : 0x10000u);
    }
}

const Srgb8Tables kSrgb8;

float linear_to_srgb(float linear) {
    const float c = std::clamp(linear, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

float srgb_to_linear(float encoded) {
    const float c = std::clamp(encoded, 0.0f, 1.0f);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

uint8_t linear_to_srgb8(float linear) {
    if (!(linear > 0.0f)) return 0;  // also maps NaN to 0
    if (linear >= 1.0f) return 255;
    const int32_t bits = std::bit_cast<int32_t>(linear), b = (bits >> 16) - Srgb8Tables::kFirstBucket;
    if (b < 0) return 0;
    return uint8_t(srgb8_from_bucket(kSrgb8.bucket[b], bits));
}

float srgb8_to_linear(uint8_t code) { return kSrgb8.decode[code]; }

uint8_t unorm8(float value) {
    const float v = std::clamp(std::isnan(value) ? 0.0f : value, 0.0f, 1.0f);
    return static_cast<uint8_t>(std::lround(v * 255.0f));
}

uint16_t float_to_half(float value) {
    const uint32_t u = std::bit_cast<uint32_t>(value);
    const uint16_t sign = uint16_t(u >> 16 & 0x8000u);
    const uint32_t a = u & 0x7FFFFFFFu;
    if (a > 0x7F800000u) return uint16_t(sign | 0x7E00u | (a >> 13 & 0x3FFu));  // NaN, quiet
    if (a >= 0x477FF000u) return uint16_t(sign | 0x7C00u);  // rounds to 65520 or more: infinity
    if (a >= 0x38800000u)  // normal: rebias, round to nearest even on the 13 dropped bits
        return uint16_t(sign | ((a - 0x38000000u + 0xFFFu + (a >> 13 & 1u)) >> 13));
    // Subnormal (or zero): a multiple of 2^-24, rounded to nearest even by
    // the float addition itself.
    const float scaled = std::bit_cast<float>(a) * 16777216.0f;  // 2^24, exact
    return uint16_t(sign | uint32_t((scaled + 8388608.0f) - 8388608.0f));
}

float half_to_float(uint16_t half) {
    const uint32_t sign = uint32_t(half & 0x8000u) << 16;
    const uint32_t exponent = half >> 10 & 0x1Fu, mantissa = half & 0x3FFu;
    if (exponent == 0)  // zero or subnormal: mantissa * 2^-24, exact
        return std::bit_cast<float>(sign | std::bit_cast<uint32_t>(float(mantissa) * 5.9604645e-8f));
    if (exponent == 31) return std::bit_cast<float>(sign | 0x7F800000u | mantissa << 13);
    return std::bit_cast<float>(sign | (exponent + 112) << 23 | mantissa << 13);
}

void encode_pixel(ColorFormat format, const glm::vec4& v, uint8_t* out) {
    switch (format) {
        case ColorFormat::srgb8: {
            const uint8_t c[4] = {linear_to_srgb8(v.r), linear_to_srgb8(v.g), linear_to_srgb8(v.b),
                                  unorm8(v.a)};
            std::memcpy(out, c, 4);
            return;
        }
        case ColorFormat::rgba16f: {
            const uint16_t h[4] = {float_to_half(v.r), float_to_half(v.g), float_to_half(v.b),
                                   float_to_half(v.a)};
            std::memcpy(out, h, 8);
            return;
        }
        case ColorFormat::rgba32f: std::memcpy(out, &v, 16); return;
        case ColorFormat::none: return;
    }
}

glm::vec4 decode_pixel(ColorFormat format, const uint8_t* in) {
    switch (format) {
        case ColorFormat::srgb8:
            return {srgb8_to_linear(in[0]), srgb8_to_linear(in[1]), srgb8_to_linear(in[2]),
                    float(in[3]) / 255.0f};
        case ColorFormat::rgba16f: {
            uint16_t h[4];
            std::memcpy(h, in, 8);
            return {half_to_float(h[0]), half_to_float(h[1]), half_to_float(h[2]),
                    half_to_float(h[3])};
        }
        case ColorFormat::rgba32f: {
            glm::vec4 v;
            std::memcpy(&v, in, 16);
            return v;
        }
        case ColorFormat::none: break;
    }
    return glm::vec4(0.0f);
}

}  // namespace facet
