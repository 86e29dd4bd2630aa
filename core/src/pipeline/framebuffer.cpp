#include "facet/framebuffer.hpp"

#include "pipeline/framebuffer_access.hpp"
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

uint64_t Framebuffer::storage_bytes(int width, int height, ColorFormat format, int samples,
                                    bool stencil) {
    // As resize() lays it out: rows of a multiple of 16 pixels, a multiple of 4 rows.
    const uint64_t pixels = uint64_t((width + 15) & ~15) * uint64_t((height + 3) & ~3);
    const uint64_t per_pixel =  // colour, depth, stencil
        uint64_t(bytes_per_pixel(format)) + sizeof(float) + (stencil ? 1 : 0);
    return pixels * per_pixel * uint64_t(samples > 1 ? 1 + samples : 1);
}

void Framebuffer::resize(int width, int height, ColorFormat format, int samples, bool stencil) {
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
    require_within_budget(storage_bytes(width, height, format, samples, stencil),
                          "a " + std::to_string(width) + "x" + std::to_string(height) + " target" +
                              (samples > 1 ? " with " + std::to_string(samples) + " samples" : ""));
    FramebufferAccess::forget_cleared(*this);
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
    stencil_on_ = stencil;
    stencil_.resize(stencil ? pixels : 0);
    sample_stencil_.resize(stencil ? multi : 0);
}

void Framebuffer::clear(const glm::vec4& color, float depth, uint8_t stencil) {
    FramebufferAccess::forget_cleared(*this);
    kernels(default_isa()).clear_rect(*this, 0, 0, stride_, rows_, color, depth, stencil, true);
}

void Framebuffer::resolve() {
    if (samples_ == 1) return;
    FramebufferAccess::forget_cleared(*this);
    kernels(default_isa()).resolve_rows(*this, 0, height_);
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
    FramebufferAccess::forget_cleared(*this);
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
