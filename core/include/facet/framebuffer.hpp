// The framebuffer: a colour buffer in one of several formats, plus float32
// depth and, where a frame's draws use one, an 8-bit stencil buffer.
//
// Shading and blending happen in linear light; a colour buffer stores it as
//   srgb8    8-bit sRGB-encoded RGB and linear 8-bit alpha, 4 bytes a pixel:
//            what a display and a PNG take, and what scenes render to by
//            default. Each write encodes exactly (the nearest code to the
//            exact sRGB curve, as linear_to_srgb8()); blending decodes the
//            stored value exactly, blends in linear light and encodes again.
//   rgba16f  half floats, 8 bytes a pixel: HDR at half the bandwidth.
//   rgba32f  floats, 16 bytes a pixel: HDR and accuracy work, exact.
//   none     depth only (shadow maps, pre-passes).
// Storage is row-major, top row first. Rows are stride() pixels apart, a
// multiple of 16, and the rows are padded to a multiple of 4, so that the
// rasterizer's 4x4 blocks never cross the end of the storage and every row
// starts on a cache line; the padding is never shown.
//
// Multisampling: a framebuffer made with samples > 1 (2, 4 or 8) also holds
// a colour, a depth and (with a stencil buffer) a stencil value per sample, at the D3D standard sample positions
// (sample_offset()), in the same format. The rasterizer tests coverage and
// depth per sample and the shader runs once per pixel; resolve() then
// averages each pixel's samples in linear light into the per-pixel colour
// that pixel() and PNG output read, and copies sample 0's depth into the
// pixel's. With one sample the rasterizer writes the per-pixel buffers
// directly and resolve() does nothing.
//
// clear(), resolve() and the 8-bit output run on FACET_ISA's path (isa.hpp)
// on the calling thread; Pipeline::clear() and resolve() share the rows out
// to the renderer's threads.
#pragma once

#include "facet/color.hpp"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <new>
#include <vector>

namespace facet {

// Storage that starts on a cache line. With rows a multiple of 16 pixels
// apart, a 64-pixel tile's rows are then whole lines, and threads drawing
// neighbouring tiles never write to the same line.
template <class T>
struct CacheLineAllocator {
    using value_type = T;
    CacheLineAllocator() = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U>&) {}
    T* allocate(size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64))); }
    void deallocate(T* p, size_t) { ::operator delete(p, std::align_val_t(64)); }
    friend bool operator==(const CacheLineAllocator&, const CacheLineAllocator&) { return true; }
};

class Framebuffer {
public:
    // An image's side, in pixels: the guard band (clip.hpp) stays exact, and
    // 16-bit pixel coordinates hold it. One target holds at most kMaxPixels,
    // which keeps every index into it in 32 bits; a larger image is rendered
    // in bands (Renderer::render_rows).
    static constexpr int kMaxSize = 32768;
    static constexpr int64_t kMaxPixels = int64_t(16384) * 16384;
    static constexpr int kMaxSamples = 8;

    Framebuffer() = default;
    Framebuffer(int width, int height, ColorFormat format = ColorFormat::rgba32f,
                int samples = 1, bool stencil = false) {
        resize(width, height, format, samples, stencil);
    }

    // Reallocates; contents are undefined until the next clear(). `samples`
    // is 1, 2, 4 or 8; a size or sample count outside the limits throws
    // Error(out_of_range), and a target over the memory budget
    // (facet/memory.hpp) Error(over_budget), before anything is allocated.
    // With `stencil`, an 8-bit stencil value a pixel (and a sample) too.
    void resize(int width, int height, ColorFormat format = ColorFormat::rgba32f,
                int samples = 1, bool stencil = false);
    // What resize() allocates for such a target: colour, depth and stencil,
    // with its samples.
    static uint64_t storage_bytes(int width, int height, ColorFormat format, int samples,
                                  bool stencil = false);
    // What a frame of that size costs a program that renders it and keeps
    // its 8-bit image: the target, the image, and twice the image again for
    // what takes it from there (the PNG encoder's filtered rows and its
    // compressed output; a window's texture).
    static uint64_t frame_bytes(int width, int height, ColorFormat format, int samples) {
        const uint64_t image = uint64_t(width) * uint64_t(height) * 4;
        return storage_bytes(width, height, format, samples) + 3 * image;
    }
    // clear(), resolve() and resolve_srgb8() run on the calling thread, on
    // the default instruction-set path (default_isa(), which throws for a
    // bad FACET_ISA); Renderer's versions use all its threads and its path.
    void clear(const glm::vec4& color, float depth, uint8_t stencil = 0);
    // Averages each pixel's samples into its colour (in linear light), and
    // copies sample 0's depth into its depth. Call after drawing; a no-op
    // with one sample.
    void resolve();

    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; }
    ColorFormat format() const { return format_; }
    bool has_color() const { return format_ != ColorFormat::none; }
    bool has_stencil() const { return stencil_on_; }
    // Pixels from one row to the next (width() rounded up to 4), and the
    // number of rows stored (height() rounded up to 4).
    int stride() const { return stride_; }
    int rows() const { return rows_; }

    // Linear RGBA of pixel (x, y), or of its sample s, decoded from the
    // format; and writing one (encoded). One pixel at a time: for tests and
    // tools, not for loops over the image (see linear()).
    glm::vec4 pixel(int x, int y) const;
    glm::vec4 sample(int x, int y, int s) const;
    void set_pixel(int x, int y, const glm::vec4& linear);
    float depth_at(int x, int y) const { return depth_[size_t(y) * stride_ + x]; }
    float sample_depth_at(int x, int y, int s) const {
        return sample_depth_[(size_t(y) * stride_ + x) * samples_ + s];
    }
    // The stencil value of pixel (x, y), or of its sample s (with MSAA the
    // samples hold it; a pixel's is not resolved from them).
    uint8_t stencil_at(int x, int y) const { return stencil_[size_t(y) * stride_ + x]; }
    uint8_t sample_stencil_at(int x, int y, int s) const {
        return samples_ == 1 ? stencil_at(x, y)
                             : sample_stencil_[(size_t(y) * stride_ + x) * samples_ + s];
    }
    // Every pixel's linear RGBA (width x height, no padding).
    std::vector<glm::vec4> linear() const;

    // The storage: pixel (x, y) at color_data() + (y * stride() + x) *
    // bytes_per_pixel(format()); with MSAA, its sample s at
    // sample_color_data() + ((y * stride() + x) * samples() + s) * bytes.
    // Depth likewise, in floats, and stencil in bytes (empty without one).
    //
    // The non-const accessors are for callers that write pixels themselves,
    // and may do so through the pointer at any time. A Pipeline::clear()
    // skips the tiles the pipeline knows still hold the values it is asked
    // to write (those no draw, write or resolve has touched since its last
    // clear to them); once writable storage has been asked for, nothing is
    // known of this framebuffer's contents any more, and every clear writes
    // every tile. To read, use a const Framebuffer&, which costs nothing.
    uint8_t* color_data() { caller_writes_.set = true; return color_.data(); }
    const uint8_t* color_data() const { return color_.data(); }
    uint8_t* sample_color_data() { caller_writes_.set = true; return sample_color_.data(); }
    const uint8_t* sample_color_data() const { return sample_color_.data(); }
    float* depth() { caller_writes_.set = true; return depth_.data(); }
    const float* depth() const { return depth_.data(); }
    float* sample_depth() { caller_writes_.set = true; return sample_depth_.data(); }
    const float* sample_depth() const { return sample_depth_.data(); }
    uint8_t* stencil() { caller_writes_.set = true; return stencil_.data(); }
    const uint8_t* stencil() const { return stencil_.data(); }
    uint8_t* sample_stencil() { caller_writes_.set = true; return sample_stencil_.data(); }
    const uint8_t* sample_stencil() const { return sample_stencil_.data(); }

    // 8-bit sRGB RGBA, row-major, width * 4 bytes a row. Alpha is stored
    // linearly. From an srgb8 target this is a copy.
    std::vector<uint8_t> resolve_srgb8() const;
    // The same into `out`, reusing its memory (a viewer's steady frames).
    void resolve_srgb8(std::vector<uint8_t>& out) const;
    // Writes resolve_srgb8() as PNG; throws Error(output_failed).
    void write_png(const std::filesystem::path& path) const;

private:
    int width_ = 0;
    int height_ = 0;
    int stride_ = 0;
    int rows_ = 0;
    int samples_ = 1;
    ColorFormat format_ = ColorFormat::none;
    std::vector<uint8_t, CacheLineAllocator<uint8_t>> color_;
    std::vector<float, CacheLineAllocator<float>> depth_;
    std::vector<uint8_t, CacheLineAllocator<uint8_t>> sample_color_;  // empty with one sample
    std::vector<float, CacheLineAllocator<float>> sample_depth_;
    bool stencil_on_ = false;
    std::vector<uint8_t, CacheLineAllocator<uint8_t>> stencil_;         // empty without stencil
    std::vector<uint8_t, CacheLineAllocator<uint8_t>> sample_stencil_;  // ... or one sample

    // What the pipeline knows of the contents: the tiles that still hold
    // every value of its last clear (colour, depth and stencil, every
    // sample, the padding too), which a clear to the same values need not
    // write again (Pipeline::clear). The pipeline's draws mark the tiles
    // they touch; clear(), set_pixel(), resize() and an MSAA resolve()
    // forget it all, as do the pipeline's sky, resolve and post chain.
    struct ClearedTiles {
        std::vector<uint8_t> held;  // per tile, row-major; empty: none known
        int tile_size = 0, columns = 0, rows = 0;
        glm::vec4 color{0.0f};
        float depth = 0.0f;
        uint8_t stencil = 0;
    };
    ClearedTiles cleared_;
    // Writable storage was asked for: nothing is known. An assignment keeps
    // it set, since it may reuse the storage a caller's pointer points into.
    struct Sticky {
        bool set = false;
        Sticky() = default;
        Sticky(const Sticky&) = default;
        Sticky& operator=(const Sticky& o) {
            set = set || o.set;
            return *this;
        }
    };
    Sticky caller_writes_;
    friend struct FramebufferAccess;  // the core's own (core/src/pipeline/framebuffer_access.hpp)
};

// Position of sample s of an n-sample pattern, in 1/16 pixel from the pixel
// centre (x right, y down): the Direct3D 10.1+ standard patterns, which
// Vulkan's standard sample locations share. n = 1 gives the centre.
glm::ivec2 sample_offset(int n, int s);

// Writes width x height 8-bit RGBA pixels (rows width * 4 bytes apart) as
// a PNG, compressed on `threads` threads (0: every hardware thread; see
// facet/png.hpp); throws Error(output_failed).
void write_png(const std::filesystem::path& path, int width, int height,
               const std::vector<uint8_t>& rgba8, int threads = 0);


}  // namespace facet
