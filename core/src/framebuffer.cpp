#include "facet/framebuffer.hpp"

#include "facet/error.hpp"

#include <stb/stb_image_write.h>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cstdint>
#include <cmath>

namespace facet {

namespace {

bool valid_samples(int n) { return n == 1 || n == 2 || n == 4 || n == 8; }

}  // namespace

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

void Framebuffer::resize(int width, int height, bool with_color, int samples) {
    if (width <= 0 || height <= 0 || width > kMaxSize || height > kMaxSize)
        throw Error(ErrorCode::out_of_range,
                    "framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                        " (each side must be 1.." + std::to_string(kMaxSize) + ")");
    if (!valid_samples(samples))
        throw Error(ErrorCode::out_of_range,
                    "MSAA sample count " + std::to_string(samples) + " (must be 1, 2, 4 or 8)");
    width_ = width;
    height_ = height;
    samples_ = samples;
    const size_t pixels = size_t(width) * height;
    const size_t multi = samples > 1 ? pixels * size_t(samples) : 0;
    color_.resize(with_color ? pixels : 0);
    depth_.resize(pixels);
    sample_color_.resize(with_color ? multi : 0);
    sample_depth_.resize(multi);
}

void Framebuffer::clear(const glm::vec4& color, float depth) { clear_rows(0, height_, color, depth); }

namespace {

// Fills [p, p + count) with copies of the `period` floats at `value`
// (period divides 4), streaming past the caches where the target has
// SSE: a clear's data is not read back soon, and streaming stores skip
// reading each line in before overwriting it.
void fill_streaming(float* p, size_t count, const float* value, size_t period) {
    size_t i = 0;
#if defined(__SSE2__)
    for (; i < count && reinterpret_cast<uintptr_t>(p + i) % 16 != 0; ++i) p[i] = value[i % period];
    alignas(16) float quad[4];
    for (int k = 0; k < 4; ++k) quad[k] = value[(i + size_t(k)) % period];
    const __m128 v = _mm_load_ps(quad);
    for (; i + 4 <= count; i += 4) _mm_stream_ps(p + i, v);
    _mm_sfence();
#endif
    for (; i < count; ++i) p[i] = value[i % period];
}

}  // namespace

void Framebuffer::clear_rows(int first, int count, const glm::vec4& color, float depth) {
    const size_t begin = size_t(first) * width_, pixels = size_t(count) * width_;
    const size_t n = size_t(samples_);
    if (!color_.empty()) fill_streaming(&color_[begin].x, 4 * pixels, &color.x, 4);
    fill_streaming(depth_.data() + begin, pixels, &depth, 1);
    if (!sample_color_.empty())
        fill_streaming(&sample_color_[begin * n].x, 4 * pixels * n, &color.x, 4);
    if (!sample_depth_.empty()) fill_streaming(sample_depth_.data() + begin * n, pixels * n, &depth, 1);
}

void Framebuffer::resolve() { resolve_rows(0, height_); }

void Framebuffer::resolve_rows(int first, int count) {
    if (samples_ == 1) return;
    const size_t n = size_t(samples_);
    const float weight = 1.0f / float(samples_);
    const size_t end = size_t(first + count) * width_;
    for (size_t p = size_t(first) * width_; p < end; ++p) {
        depth_[p] = sample_depth_[p * n];
        if (color_.empty()) continue;
        glm::vec4 sum(0.0f);
        for (size_t s = 0; s < n; ++s) sum += sample_color_[p * n + s];
        color_[p] = sum * weight;
    }
}

float linear_to_srgb(float linear) {
    const float c = std::clamp(linear, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

float srgb_to_linear(float encoded) {
    const float c = std::clamp(encoded, 0.0f, 1.0f);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

namespace {

// linear_to_srgb8 without a pow per value, and exact: code c starts at the
// linear value whose encoding is (c - 0.5) / 255, found in double precision
// and rounded up to the next float, so `linear >= threshold[c]` holds
// exactly when the double-precision encoding of `linear` rounds to c or
// more. A coarse table of buckets gives the starting code; at most a step
// or two remains.
struct Srgb8Table {
    static constexpr int kBuckets = 4096;
    float threshold[256];
    uint8_t start[kBuckets + 1];

    Srgb8Table() {
        threshold[0] = 0.0f;
        for (int c = 1; c < 256; ++c) {
            const double e = (c - 0.5) / 255.0;
            const double x = e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
            float t = float(x);
            if (double(t) < x) t = std::nextafter(t, 2.0f);
            threshold[c] = t;
        }
        int c = 0;
        for (int i = 0; i <= kBuckets; ++i) {
            const float v = float(i) / kBuckets;
            while (c < 255 && v >= threshold[c + 1]) ++c;
            start[i] = uint8_t(c);
        }
    }
};

const Srgb8Table kSrgb8;

}  // namespace

uint8_t linear_to_srgb8(float linear) {
    if (!(linear > 0.0f)) return 0;  // also maps NaN to 0
    if (linear >= 1.0f) return 255;
    int c = kSrgb8.start[int(linear * Srgb8Table::kBuckets)];
    while (c < 255 && linear >= kSrgb8.threshold[c + 1]) ++c;
    return uint8_t(c);
}

std::vector<uint8_t> Framebuffer::resolve_srgb8() const {
    std::vector<uint8_t> out;
    resolve_srgb8(out);
    return out;
}

void Framebuffer::resolve_srgb8(std::vector<uint8_t>& out) const {
    out.resize(color_.size() * 4);
    for (size_t i = 0; i < color_.size(); ++i) {
        const glm::vec4& c = color_[i];
        out[4 * i + 0] = linear_to_srgb8(c.r);
        out[4 * i + 1] = linear_to_srgb8(c.g);
        out[4 * i + 2] = linear_to_srgb8(c.b);
        const float a = std::clamp(std::isnan(c.a) ? 0.0f : c.a, 0.0f, 1.0f);
        out[4 * i + 3] = static_cast<uint8_t>(std::lround(a * 255.0f));
    }
}

void Framebuffer::write_png(const std::filesystem::path& path) const {
    const std::vector<uint8_t> pixels = resolve_srgb8();
    if (!stbi_write_png(path.string().c_str(), width_, height_, 4, pixels.data(), width_ * 4))
        throw Error(ErrorCode::output_failed, "cannot write PNG", path.string());
}

}  // namespace facet
