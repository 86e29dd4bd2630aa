#include "facet/framebuffer.hpp"

#include "facet/error.hpp"

#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>

namespace facet {

void Framebuffer::resize(int width, int height, bool with_color) {
    if (width <= 0 || height <= 0 || width > kMaxSize || height > kMaxSize)
        throw Error(ErrorCode::out_of_range,
                    "framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                        " (each side must be 1.." + std::to_string(kMaxSize) + ")");
    width_ = width;
    height_ = height;
    color_.resize(with_color ? size_t(width) * height : 0);
    depth_.resize(size_t(width) * height);
}

void Framebuffer::clear(const glm::vec4& color, float depth) {
    std::fill(color_.begin(), color_.end(), color);
    std::fill(depth_.begin(), depth_.end(), depth);
}

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
    return static_cast<uint8_t>(std::lround(linear_to_srgb(linear) * 255.0f));
}

std::vector<uint8_t> Framebuffer::resolve_srgb8() const {
    std::vector<uint8_t> out(color_.size() * 4);
    for (size_t i = 0; i < color_.size(); ++i) {
        const glm::vec4& c = color_[i];
        out[4 * i + 0] = linear_to_srgb8(c.r);
        out[4 * i + 1] = linear_to_srgb8(c.g);
        out[4 * i + 2] = linear_to_srgb8(c.b);
        const float a = std::clamp(std::isnan(c.a) ? 0.0f : c.a, 0.0f, 1.0f);
        out[4 * i + 3] = static_cast<uint8_t>(std::lround(a * 255.0f));
    }
    return out;
}

void Framebuffer::write_png(const std::filesystem::path& path) const {
    const std::vector<uint8_t> pixels = resolve_srgb8();
    if (!stbi_write_png(path.string().c_str(), width_, height_, 4, pixels.data(), width_ * 4))
        throw Error(ErrorCode::output_failed, "cannot write PNG", path.string());
}

}  // namespace facet
