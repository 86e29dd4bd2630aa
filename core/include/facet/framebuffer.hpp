// The framebuffer: linear-light float RGBA colour plus float32 depth.
//
// Colour is stored in linear light and resolved to 8-bit sRGB only for
// output (PNG, or a viewer's texture). Storage is row-major, top row first.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace facet {

class Framebuffer {
public:
    static constexpr int kMaxSize = 16384;  // per side; keeps the guard band exact

    Framebuffer() = default;
    Framebuffer(int width, int height, bool with_color = true) {
        resize(width, height, with_color);
    }

    // Reallocates; contents are undefined until the next clear(). A
    // framebuffer without colour (shadow maps, pre-passes) holds depth only.
    void resize(int width, int height, bool with_color = true);
    bool has_color() const { return !color_.empty(); }
    void clear(const glm::vec4& color, float depth);

    int width() const { return width_; }
    int height() const { return height_; }

    glm::vec4* color() { return color_.data(); }
    const glm::vec4* color() const { return color_.data(); }
    float* depth() { return depth_.data(); }
    const float* depth() const { return depth_.data(); }
    glm::vec4& pixel(int x, int y) { return color_[size_t(y) * width_ + x]; }
    const glm::vec4& pixel(int x, int y) const { return color_[size_t(y) * width_ + x]; }
    float depth_at(int x, int y) const { return depth_[size_t(y) * width_ + x]; }

    // 8-bit sRGB RGBA, row-major. Alpha is stored linearly.
    std::vector<uint8_t> resolve_srgb8() const;
    // Writes resolve_srgb8() as PNG; throws Error(output_failed).
    void write_png(const std::filesystem::path& path) const;

private:
    int width_ = 0;
    int height_ = 0;
    std::vector<glm::vec4> color_;
    std::vector<float> depth_;
};

// Linear light -> sRGB-encoded value, both in 0..1 (input clamped).
float linear_to_srgb(float linear);
// sRGB-encoded value -> linear light.
float srgb_to_linear(float encoded);
// Linear light -> 8-bit sRGB code, rounded to nearest.
uint8_t linear_to_srgb8(float linear);

}  // namespace facet
