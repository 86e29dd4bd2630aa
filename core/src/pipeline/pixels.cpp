// Framebuffer row kernels (clear, MSAA resolve, 8-bit output) and the bulk
// codecs, kWidth pixels at a time; one of the per-ISA kernel sources.
#include "pipeline/pixels.hpp"

#include "pipeline/framebuffer_access.hpp"

#include <algorithm>
#include <cstring>

namespace facet::FACET_KERNEL_NS {

namespace {

// Copies of one pixel of `size` bytes (dividing 16) across a register.
struct Pattern {
    const uint8_t* pixel;
    size_t size;
    simd::Int v;
    Pattern(const uint8_t* px, size_t bytes) : pixel(px), size(bytes) {
        uint8_t copies[sizeof v];
        for (size_t i = 0; i < sizeof v; i += size) std::memcpy(copies + i, pixel, size);
        std::memcpy(&v, copies, sizeof v);
    }
};

// Fills `bytes` bytes at p with copies of the pattern's pixel (p a multiple
// of its size into its buffer). With `stream`, where the path has SSE2,
// past the caches: a streaming store skips reading each line in before
// overwriting it, for data not read back soon. Without, a register at a
// time into the cache, for the draws that follow.
void fill(uint8_t* p, size_t bytes, const Pattern& pattern, bool stream) {
    size_t i = 0;
#if defined(__SSE2__)
    if (stream) {
        for (; i < bytes && reinterpret_cast<uintptr_t>(p + i) % 16 != 0; i += pattern.size)
            std::memcpy(p + i, pattern.pixel, pattern.size);
        __m128i v;
        std::memcpy(&v, &pattern.v, 16);  // a whole number of pixels, so any phase is the same
        for (; i + 16 <= bytes; i += 16) _mm_stream_si128(reinterpret_cast<__m128i*>(p + i), v);
        _mm_sfence();
    }
#else
    (void)stream;  // no streaming stores on this path
#endif
    for (; i + sizeof pattern.v <= bytes; i += sizeof pattern.v) simd::store(p + i, pattern.v);
    for (; i < bytes; i += pattern.size) std::memcpy(p + i, pattern.pixel, pattern.size);
}

// Up to kWidth pixels of `size` bytes from `in` (`step` bytes apart), decoded.
// A run of `count` pixels of Bytes each, zeros after it: a copy of constant
// size in the common case of a whole run (a variable one is a slow rep movs).
template <size_t Bytes>
void copy_run(uint8_t* dst, const uint8_t* src, int count) {
    if (count == kWidth) {
        std::memcpy(dst, src, Bytes * kWidth);
        return;
    }
    std::memcpy(dst, src, Bytes * size_t(count));
    std::memset(dst + Bytes * size_t(count), 0, Bytes * size_t(kWidth - count));
}

Rgba gather_pixels(ColorFormat format, const uint8_t* in, size_t step, size_t size, int count) {
    Packed packed;
    if (step != size) {
        for (int i = 0; i < count; ++i)
            std::memcpy(packed.bytes + size_t(i) * size, in + size_t(i) * step, size);
        std::memset(packed.bytes + size * size_t(count), 0, size * size_t(kWidth - count));
    } else if (size == 4) {
        copy_run<4>(packed.bytes, in, count);
    } else if (size == 8) {
        copy_run<8>(packed.bytes, in, count);
    } else {
        copy_run<16>(packed.bytes, in, count);
    }
    return unpack(format, packed.bytes);
}

void put_pixels(ColorFormat format, const Rgba& c, uint8_t* out, int count) {
    Packed packed;
    pack(format, c, packed.bytes);
    const size_t bytes = size_t(bytes_per_pixel(format));
    if (count == kWidth && bytes == 4) std::memcpy(out, packed.bytes, 4 * kWidth);
    else std::memcpy(out, packed.bytes, size_t(count) * bytes);
}

}  // namespace

void clear_rect(Framebuffer& fb, int x0, int y0, int x1, int y1, const glm::vec4& color,
                float depth, uint8_t stencil, bool stream) {
    const size_t n = size_t(fb.samples()), bytes = size_t(bytes_per_pixel(fb.format()));
    const size_t stride = size_t(fb.stride());
    uint8_t encoded[16] = {};
    if (fb.has_color()) encode_pixel(fb.format(), color, encoded);
    const Pattern z(reinterpret_cast<const uint8_t*>(&depth), 4), c(encoded, bytes ? bytes : 4);
    // Whole rows are one run of storage; otherwise a run a row.
    const bool whole = x0 == 0 && size_t(x1) == stride;
    const size_t run = size_t(x1 - x0) * (whole ? size_t(y1 - y0) : 1);
    auto* const depths = reinterpret_cast<uint8_t*>(FramebufferAccess::depth(fb));
    auto* const sample_depths = reinterpret_cast<uint8_t*>(FramebufferAccess::sample_depth(fb));
    uint8_t* const colors = FramebufferAccess::color(fb);
    uint8_t* const sample_colors = FramebufferAccess::sample_color(fb);
    for (int y = y0; y < (whole ? y0 + 1 : y1); ++y) {
        const size_t at = size_t(y) * stride + size_t(x0);
        fill(depths + at * 4, run * 4, z, stream);
        if (n > 1) fill(sample_depths + at * n * 4, run * n * 4, z, stream);
        if (fb.has_stencil()) {
            std::memset(FramebufferAccess::stencil(fb) + at, stencil, run);
            if (n > 1)
                std::memset(FramebufferAccess::sample_stencil(fb) + at * n, stencil, run * n);
        }
        if (!fb.has_color()) continue;
        fill(colors + at * bytes, run * bytes, c, stream);
        if (n > 1) fill(sample_colors + at * n * bytes, run * n * bytes, c, stream);
    }
}

void resolve_rows(Framebuffer& fb, int first, int count) {
    const int n = fb.samples();
    if (n == 1) return;
    const ColorFormat format = fb.format();
    const size_t bytes = size_t(bytes_per_pixel(format));
    const float weight = 1.0f / float(n);
    float* const depth = FramebufferAccess::depth(fb);
    const float* const sample_depth = FramebufferAccess::sample_depth(fb);
    uint8_t* const color = FramebufferAccess::color(fb);
    const uint8_t* const sample_color = FramebufferAccess::sample_color(fb);
    for (int y = first; y < first + count; ++y) {
        const size_t row = size_t(y) * size_t(fb.stride());
        for (int x = 0; x < fb.width(); x += kWidth) {
            const int k = std::min(kWidth, fb.width() - x);
            const size_t at = row + size_t(x);
            for (int i = 0; i < k; ++i) depth[at + i] = sample_depth[(at + i) * n];
            if (!fb.has_color()) continue;
            Rgba sum = {Float{}, Float{}, Float{}, Float{}};
            for (int s = 0; s < n; ++s) {
                const Rgba c = gather_pixels(format, sample_color + (at * n + s) * bytes,
                                             n * bytes, bytes, k);
                sum = {sum.r + c.r, sum.g + c.g, sum.b + c.b, sum.a + c.a};
            }
            put_pixels(format, {sum.r * weight, sum.g * weight, sum.b * weight, sum.a * weight},
                       color + at * bytes, k);
        }
    }
}

// Rows of a `format` image to 8-bit sRGB: whole runs of kWidth pixels
// straight from the row into registers and out, then the row's tail.
template <ColorFormat format>
void srgb8_rows_of(const Framebuffer& fb, int first, int count, uint8_t* out) {
    constexpr size_t bytes = size_t(bytes_per_pixel(format));
    const int width = fb.width(), whole = width - width % kWidth;
    for (int y = first; y < first + count; ++y) {
        const uint8_t* row = fb.color_data() + size_t(y) * size_t(fb.stride()) * bytes;
        uint8_t* dst = out + size_t(y) * size_t(width) * 4;
        for (int x = 0; x < whole; x += kWidth)
            pack(ColorFormat::srgb8, unpack(format, row + size_t(x) * bytes), dst + size_t(x) * 4);
        if (whole < width) {
            const Rgba c = gather_pixels(format, row + size_t(whole) * bytes, bytes, bytes,
                                         width - whole);
            put_pixels(ColorFormat::srgb8, c, dst + size_t(whole) * 4, width - whole);
        }
    }
}

void srgb8_rows(const Framebuffer& fb, int first, int count, uint8_t* out) {
    switch (fb.format()) {
        case ColorFormat::srgb8: return srgb8_rows_of<ColorFormat::srgb8>(fb, first, count, out);
        case ColorFormat::rgba16f: return srgb8_rows_of<ColorFormat::rgba16f>(fb, first, count, out);
        case ColorFormat::rgba32f: return srgb8_rows_of<ColorFormat::rgba32f>(fb, first, count, out);
        case ColorFormat::none: return;
    }
}

void encode_pixels(ColorFormat format, const glm::vec4* linear, size_t count, uint8_t* out) {
    const size_t bytes = size_t(bytes_per_pixel(format));
    for (size_t i = 0; i < count; i += kWidth) {
        const int k = int(std::min<size_t>(kWidth, count - i));
        const Rgba c = gather_pixels(ColorFormat::rgba32f, reinterpret_cast<const uint8_t*>(linear + i),
                                     16, 16, k);
        put_pixels(format, c, out + i * bytes, k);
    }
}

void decode_pixels(ColorFormat format, const uint8_t* in, size_t count, glm::vec4* linear) {
    const size_t bytes = size_t(bytes_per_pixel(format));
    for (size_t i = 0; i < count; i += kWidth) {
        const int k = int(std::min<size_t>(kWidth, count - i));
        const Rgba c = gather_pixels(format, in + i * bytes, bytes, bytes, k);
        put_pixels(ColorFormat::rgba32f, c, reinterpret_cast<uint8_t*>(linear + i), k);
    }
}

}  // namespace facet::FACET_KERNEL_NS
