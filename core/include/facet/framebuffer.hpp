// The framebuffer: linear-light float RGBA colour plus float32 depth.
//
// Colour is stored in linear light and resolved to 8-bit sRGB only for
// output (PNG, or a viewer's texture). Storage is row-major, top row first.
//
// Multisampling: a framebuffer made with samples > 1 (2, 4 or 8) also holds
// a colour and a depth per sample, at the D3D standard sample positions
// (sample_offset()). The rasterizer tests coverage and depth per sample and
// the shader runs once per pixel; resolve() then averages each pixel's
// samples into the per-pixel colour that pixel(), color() and PNG output
// read, and copies sample 0's depth into depth(). With one sample the
// rasterizer writes the per-pixel buffers directly and resolve() does
// nothing.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace facet {

class Framebuffer {
public:
    static constexpr int kMaxSize = 16384;  // per side; keeps the guard band exact
    static constexpr int kMaxSamples = 8;

    Framebuffer() = default;
    Framebuffer(int width, int height, bool with_color = true, int samples = 1) {
        resize(width, height, with_color, samples);
    }

    // Reallocates; contents are undefined until the next clear(). A
    // framebuffer without colour (shadow maps, pre-passes) holds depth only.
    // `samples` is 1, 2, 4 or 8; anything else throws Error(out_of_range).
    void resize(int width, int height, bool with_color = true, int samples = 1);
    bool has_color() const { return !color_.empty(); }
    void clear(const glm::vec4& color, float depth);
    // Averages each pixel's samples into color(), sample 0's depth into
    // depth(). Call after drawing; a no-op with one sample.
    void resolve();
    // The same for `count` rows from row `first` only: bands of rows are
    // independent, so threads can share the work.
    void clear_rows(int first, int count, const glm::vec4& color, float depth);
    void resolve_rows(int first, int count);

    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; }
    // Per-sample storage (samples() > 1): sample s of pixel (x, y) is at
    // (y * width + x) * samples + s.
    glm::vec4* sample_color() { return sample_color_.data(); }
    float* sample_depth() { return sample_depth_.data(); }
    const float* sample_depth() const { return sample_depth_.data(); }

    glm::vec4* color() { return color_.data(); }
    const glm::vec4* color() const { return color_.data(); }
    float* depth() { return depth_.data(); }
    const float* depth() const { return depth_.data(); }
    glm::vec4& pixel(int x, int y) { return color_[size_t(y) * width_ + x]; }
    const glm::vec4& pixel(int x, int y) const { return color_[size_t(y) * width_ + x]; }
    float depth_at(int x, int y) const { return depth_[size_t(y) * width_ + x]; }

    // 8-bit sRGB RGBA, row-major. Alpha is stored linearly.
    std::vector<uint8_t> resolve_srgb8() const;
    // The same into `out`, reusing its memory (a viewer's steady frames).
    void resolve_srgb8(std::vector<uint8_t>& out) const;
    // Writes resolve_srgb8() as PNG; throws Error(output_failed).
    void write_png(const std::filesystem::path& path) const;

private:
    int width_ = 0;
    int height_ = 0;
    int samples_ = 1;
    std::vector<glm::vec4> color_;
    std::vector<float> depth_;
    std::vector<glm::vec4> sample_color_;  // empty with one sample
    std::vector<float> sample_depth_;
};

// Position of sample s of an n-sample pattern, in 1/16 pixel from the pixel
// centre (x right, y down): the Direct3D 10.1+ standard patterns, which
// Vulkan's standard sample locations share. n = 1 gives the centre.
glm::ivec2 sample_offset(int n, int s);

// Linear light -> sRGB-encoded value, both in 0..1 (input clamped).
float linear_to_srgb(float linear);
// sRGB-encoded value -> linear light.
float srgb_to_linear(float encoded);
// Linear light -> 8-bit sRGB code, rounded to nearest.
uint8_t linear_to_srgb8(float linear);

}  // namespace facet
