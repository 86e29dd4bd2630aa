// Colour formats and exact codecs: what a framebuffer stores (framebuffer.hpp),
// and the conversions between linear light and the stored codes that
// textures, the post chain and PNG output share.
//
//   srgb8    8-bit sRGB-encoded RGB and linear 8-bit alpha, 4 bytes a pixel
//   rgba16f  IEEE half floats, 8 bytes a pixel
//   rgba32f  floats, 16 bytes a pixel
//   none     no colour (depth only)
//
// Every conversion is exact or correctly rounded: linear_to_srgb8() gives
// the code nearest the exact sRGB curve, and srgb8_to_linear() the float
// nearest that code's value.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <string_view>

namespace facet {

enum class ColorFormat { none, srgb8, rgba16f, rgba32f };

// "none", "srgb8", "rgba16f", "rgba32f"; and back.
std::string_view color_format_name(ColorFormat format);
std::optional<ColorFormat> parse_color_format(std::string_view name);
// Bytes a pixel (or sample) takes: 0, 4, 8 or 16.
constexpr int bytes_per_pixel(ColorFormat format) {
    switch (format) {
        case ColorFormat::none: return 0;
        case ColorFormat::srgb8: return 4;
        case ColorFormat::rgba16f: return 8;
        case ColorFormat::rgba32f: return 16;
    }
    return 0;
}

// Linear light -> sRGB-encoded value, both in 0..1 (input clamped).
float linear_to_srgb(float linear);
// sRGB-encoded value -> linear light.
float srgb_to_linear(float encoded);
// Linear light -> 8-bit sRGB code: the code whose value on the exact sRGB
// curve is nearest (NaN and below 0 give 0, 1 and above 255).
uint8_t linear_to_srgb8(float linear);
// 8-bit sRGB code -> linear light, correctly rounded.
float srgb8_to_linear(uint8_t code);
// A linear value in 0..1 -> 8 bits: round(255 v), halves away from zero
// (NaN gives 0). Alpha in srgb8 targets.
uint8_t unorm8(float value);
// IEEE half precision, rounded to nearest even (overflow to infinity, NaN
// kept); and back, exactly.
uint16_t float_to_half(float value);
float half_to_float(uint16_t half);

// Encodes and decodes one pixel in `format` (not none).
void encode_pixel(ColorFormat format, const glm::vec4& linear, uint8_t* out);
glm::vec4 decode_pixel(ColorFormat format, const uint8_t* in);

}  // namespace facet
