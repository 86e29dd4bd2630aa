// The hot loops, once per instruction-set path (facet/isa.hpp).
//
// rasterize.cpp, fragment.cpp, pixels.cpp and kernels.cpp are compiled once
// for each path, with that path's compiler flags and in a namespace of its
// own (FACET_KERNEL_NS: isa_portable, isa_avx2, isa_avx512), and each
// compilation exports one table of function pointers, facet_kernels_<path>.
// The rest of the core is built for the baseline and calls the kernels of
// its Renderer's path through that table: one indirect call per tile, per
// band of rows, never per pixel.
//
// The build links each path's objects into one relocatable object and
// makes every symbol but its table local (facet_isa_objects() in
// plugins/FacetShader.cmake): otherwise the linker would keep one copy of
// each inline function the paths share - std::min, a glm operator - and
// the SSE2 path could end up calling the AVX-512 copy.
#pragma once

#include "setup.hpp"

#include "facet/framebuffer.hpp"
#include "facet/isa.hpp"

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace facet {

struct FrameStats;
struct Geometry;

// One 4x4 block of a triangle's coverage (rasterize.hpp).
struct Block {
    int32_t x, y;                    // pixel of lane 0 (multiples of 4), adjacent
    uint32_t mask;                   // covered lanes inside the bounding box
    alignas(64) float bary[3][FACET_BLOCK_LANES];  // weight of vertex k at lane i
    uint8_t samples[FACET_BLOCK_LANES];  // MSAA only: covered samples of lane i
};

// How a triangle's edge functions are evaluated inside a block (setup.hpp's
// TriangleSetup::narrow tells which applies).
enum class EdgeWidth {
    automatic,  // 32-bit lanes where the triangle allows it, else 64-bit
    wide,       // 64-bit lanes always (tests hold the two to the same coverage)
};

struct Kernels {
    Isa isa;
    // Rasterizes and shades the triangles queued for tile `tile` of `g`, in
    // submission order (draw.cpp), adding to `stats`.
    void (*draw_tile)(const Geometry& g, int tile, FrameStats& stats);
    // The blocks of `t` with coverage inside the pixel rectangle [x0, x1] x
    // [y0, y1] (corners multiples of 4), at `samples` per pixel, appended
    // to `out`. For tests and tools; draw_tile does the same inline.
    void (*cover)(const TriangleSetup& t, int x0, int y0, int x1, int y1, int samples,
                  EdgeWidth width, std::vector<Block>& out);
    // Framebuffer rows [first, first + count): clear; average the samples
    // into each pixel; write 8-bit sRGB RGBA, `width * 4` bytes a row.
    void (*clear_rows)(Framebuffer& fb, int first, int count, const glm::vec4& color,
                       float depth);
    void (*resolve_rows)(Framebuffer& fb, int first, int count);
    void (*srgb8_rows)(const Framebuffer& fb, int first, int count, uint8_t* out);
    // `count` pixels from linear RGBA to `format`'s bytes, and back: the
    // vector codecs the kernels above use (tests hold them to the scalar
    // ones of framebuffer.hpp).
    void (*encode_pixels)(ColorFormat format, const glm::vec4* linear, size_t count, uint8_t* out);
    void (*decode_pixels)(ColorFormat format, const uint8_t* in, size_t count, glm::vec4* linear);
};

// The kernels of a supported path; throws Error(isa_unavailable) otherwise.
const Kernels& kernels(Isa isa);

extern "C" {
extern const Kernels facet_kernels_portable;
extern const Kernels facet_kernels_avx2;
extern const Kernels facet_kernels_avx512;
}

}  // namespace facet
