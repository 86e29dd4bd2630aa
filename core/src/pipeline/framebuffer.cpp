#include "facet/framebuffer.hpp"

#include "pipeline/color_tables.hpp"
#include "pipeline/kernels.hpp"

#include "facet/error.hpp"
#include "facet/memory.hpp"
#include "facet/png.hpp"

#include <stb/stb_image_write.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace facet {

// ---- formats and codecs ----------------------------------------------------

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
        // The bucket must hold at most one threshold (see color_tables.hpp).
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

// ---- Framebuffer -------------------------------------------------------------

glm::ivec2 sample_offset(int n, int s) {
    static constexpr int kTwo[2][2] = {{4, 4}, {-4, -4}};
    static constexpr int kFour[4][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
    static constexpr int kEight[8][2] = {{1, -3}, {-1, 3}, {5, 1},  {-3, -5},
                                         {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
    switch (n) {
        case 2: return {kTwo[s][0], kTwo[s][1]};
        case 4: return {kFour[s][0], kFour[s][1]};
        case 8: return {kEight[s][0], kEight[s][1]};
        default: return {0, 0};
    }
}

uint64_t Framebuffer::storage_bytes(int width, int height, ColorFormat format, int samples) {
    // As resize() lays it out: rows of a multiple of 16 pixels, a multiple of 4 rows.
    const uint64_t pixels = uint64_t((width + 15) & ~15) * uint64_t((height + 3) & ~3);
    const uint64_t per_pixel = uint64_t(bytes_per_pixel(format)) + sizeof(float);  // colour, depth
    return pixels * per_pixel * uint64_t(samples > 1 ? 1 + samples : 1);
}

void Framebuffer::resize(int width, int height, ColorFormat format, int samples) {
    if (width <= 0 || height <= 0 || width > kMaxSize || height > kMaxSize)
        throw Error(ErrorCode::out_of_range,
                    "framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                        " (each side must be 1.." + std::to_string(kMaxSize) + ")");
    if (int64_t(width) * height > kMaxPixels)
        throw Error(ErrorCode::out_of_range,
                    "framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                        " (at most 16384x16384 pixels in one target; render a larger image in "
                        "bands of rows: facet-render --band-rows)");
    if (samples != 1 && samples != 2 && samples != 4 && samples != 8)
        throw Error(ErrorCode::out_of_range,
                    "MSAA sample count " + std::to_string(samples) + " (must be 1, 2, 4 or 8)");
    require_within_budget(storage_bytes(width, height, format, samples),
                          "a " + std::to_string(width) + "x" + std::to_string(height) + " target" +
                              (samples > 1 ? " with " + std::to_string(samples) + " samples" : ""));
    width_ = width;
    height_ = height;
    stride_ = (width + 15) & ~15;  // 64 bytes of depth: rows start on cache lines
    rows_ = (height + 3) & ~3;
    samples_ = samples;
    format_ = format;
    const size_t pixels = size_t(stride_) * size_t(rows_);
    const size_t bytes = size_t(bytes_per_pixel(format));
    const size_t multi = samples > 1 ? pixels * size_t(samples) : 0;
    color_.resize(pixels * bytes);
    depth_.resize(pixels);
    sample_color_.resize(multi * bytes);
    sample_depth_.resize(multi);
}

void Framebuffer::clear(const glm::vec4& color, float depth) {
    kernels(default_isa()).clear_rect(*this, 0, 0, stride_, rows_, color, depth, true);
}

void Framebuffer::resolve() {
    if (samples_ > 1) kernels(default_isa()).resolve_rows(*this, 0, height_);
}

glm::vec4 Framebuffer::pixel(int x, int y) const {
    const size_t at = size_t(y) * size_t(stride_) + size_t(x);
    return decode_pixel(format_, color_.data() + at * size_t(bytes_per_pixel(format_)));
}

glm::vec4 Framebuffer::sample(int x, int y, int s) const {
    if (samples_ == 1) return pixel(x, y);
    const size_t at = (size_t(y) * size_t(stride_) + size_t(x)) * size_t(samples_) + size_t(s);
    return decode_pixel(format_, sample_color_.data() + at * size_t(bytes_per_pixel(format_)));
}

void Framebuffer::set_pixel(int x, int y, const glm::vec4& linear) {
    const size_t at = size_t(y) * size_t(stride_) + size_t(x);
    encode_pixel(format_, linear, color_.data() + at * size_t(bytes_per_pixel(format_)));
}

std::vector<glm::vec4> Framebuffer::linear() const {
    std::vector<glm::vec4> out;
    out.reserve(size_t(width_) * size_t(height_));
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) out.push_back(pixel(x, y));
    return out;
}

std::vector<uint8_t> Framebuffer::resolve_srgb8() const {
    std::vector<uint8_t> out;
    resolve_srgb8(out);
    return out;
}

void Framebuffer::resolve_srgb8(std::vector<uint8_t>& out) const {
    out.resize(size_t(width_) * size_t(height_) * 4);
    if (format_ == ColorFormat::srgb8) {
        for (int y = 0; y < height_; ++y)
            std::memcpy(&out[size_t(y) * width_ * 4], &color_[size_t(y) * stride_ * 4],
                        size_t(width_) * 4);
        return;
    }
    if (format_ == ColorFormat::none) {
        std::fill(out.begin(), out.end(), uint8_t(0));
        return;
    }
    kernels(default_isa()).srgb8_rows(*this, 0, height_, out.data());
}

void Framebuffer::write_png(const std::filesystem::path& path) const {
    if (format_ == ColorFormat::srgb8) {  // straight from storage, padding skipped
        write_png_rows(path, color_.data(), size_t(stride_) * 4, width_, height_);
        return;
    }
    facet::write_png(path, width_, height_, resolve_srgb8());
}

void write_png(const std::filesystem::path& path, int width, int height,
               const std::vector<uint8_t>& rgba8, int threads) {
    if (rgba8.size() != size_t(width) * size_t(height) * 4)
        throw Error(ErrorCode::output_failed,
                    "cannot write PNG: " + std::to_string(rgba8.size()) + " bytes for " +
                        std::to_string(width) + "x" + std::to_string(height) + " pixels",
                    path.string());
    write_png_rows(path, rgba8.data(), size_t(width) * 4, width, height, threads);
}

}  // namespace facet
