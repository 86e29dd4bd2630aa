// The hot loops, once per instruction-set path (facet/isa.hpp).
//
// rasterize.cpp, fragment.cpp, pixels.cpp, ao_kernels.cpp, shadow_kernels.cpp,
// sky_kernels.cpp, project_kernels.cpp, assembly_kernels.cpp and kernels.cpp
// are compiled once for each path, with that path's compiler flags and in a
// namespace of its own (FACET_KERNEL_NS: isa_portable, isa_avx2,
// isa_avx512), and each compilation exports one table of function
// pointers, facet_kernels_<path>.
// The rest of the core is built for the baseline and calls the kernels of
// its Pipeline's path through that table: one indirect call per tile, per
// band of rows, batch of vertices or chunk of triangles, never per pixel.
//
// The build links each path's objects into one relocatable object and
// makes every symbol but its table local (facet_isa_objects() in
// plugins/FacetShader.cmake): otherwise the linker would keep one copy of
// each inline function the paths share - std::min, a glm operator - and
// the SSE2 path could end up calling the AVX-512 copy.
#pragma once

#include "pipeline/block.hpp"

#include "facet/framebuffer.hpp"
#include "facet/isa.hpp"
#include "facet/texture.hpp"

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace facet {

struct FrameStats;
struct DrawQueue;
struct TriangleSetup;
struct Viewport;
struct WindowVertex;
struct WideAssembly;
struct SetupChunk;

struct AoFrame;
struct SkyRows;
struct ShadowDistanceRows;
struct ShadowPlaneRows;

struct Kernels {
    Isa isa;
    // Each of `count` clip positions' outcodes and window position
    // (WindowVertex, vertex.hpp: outcodes in `user`, kInvalid when not
    // finite, kNoWindow when w <= 0), as outcode() and project_vertex()
    // give them, bit for bit (project_kernels.cpp).
    void (*project_vertices)(const glm::vec4* clip, size_t count, const Viewport& viewport,
                             WindowVertex* out);
    // Primitive assembly and setup of a draw's triangles, eight at a time,
    // as Assembler::run does them, bit for bit (assembly_kernels.cpp; on
    // the portable path it takes none). Returns how many it took.
    size_t (*assemble_triangles)(const WideAssembly& a, const uint32_t* idx, size_t count,
                                 SetupChunk& chunk);
    // Rasterizes and shades the triangles queued for tile `tile` of `g`, in
    // submission order (pipeline.cpp), adding to `stats`.
    void (*draw_tile)(const DrawQueue& g, int tile, FrameStats& stats);
    // The blocks of `t` with coverage inside the pixel rectangle [x0, x1] x
    // [y0, y1] (corners multiples of 4), at `samples` per pixel, appended
    // to `out`. For tests and tools; draw_tile does the same inline.
    void (*cover)(const TriangleSetup& t, int x0, int y0, int x1, int y1, int samples,
                  EdgeWidth width, std::vector<Block>& out);
    // Clears the storage rectangle [x0, x1) x [y0, y1) (the padding past the
    // last column and row included where x1 is stride() and y1 rows()),
    // every sample, stencil too where it has one, with streaming stores past
    // the caches or (for the draws about to follow) into them.
    void (*clear_rect)(Framebuffer& fb, int x0, int y0, int x1, int y1, const glm::vec4& color,
                       float depth, uint8_t stencil, bool stream);
    // Framebuffer rows [first, first + count): average the samples into
    // each pixel; write 8-bit sRGB RGBA, `width * 4` bytes a row.
    void (*resolve_rows)(Framebuffer& fb, int first, int count);
    void (*srgb8_rows)(const Framebuffer& fb, int first, int count, uint8_t* out);
    // `count` pixels from linear RGBA to `format`'s bytes, and back: the
    // vector codecs the kernels above use (tests hold them to the scalar
    // ones of framebuffer.hpp).
    void (*encode_pixels)(ColorFormat format, const glm::vec4* linear, size_t count, uint8_t* out);
    void (*decode_pixels)(ColorFormat format, const uint8_t* in, size_t count, glm::vec4* linear);
    // AO rows [first, first + count) (ao_kernels.cpp): the view z and key
    // of each texel's surface; then, with every row's done, its raw
    // visibility (within columns [x_first, x_first + x_count), x_first a
    // multiple of kGroupWidth and first of kGroupRows; each texel's normal
    // worked out as its marches start, from z a row above and below) and
    // its blur, on the AO grid. At half size, the depth-aware upsample to
    // target rows [first, first + count), columns [x_first, x_first +
    // x_count) (multiples of the widest vector; first of 4), into 4x4
    // blocks of 16 floats, `across` a row: the fragment stage's, a tile at
    // a time (fragment.hpp's TileAo; here for tests).
    // ao_normal_rows writes the normals the occlusion works out (for tests).
    void (*ao_position_rows)(const AoFrame& f, int first, int count);
    void (*ao_normal_rows)(const AoFrame& f, int first, int count);
    void (*ao_occlusion_rows)(const AoFrame& f, int first, int count, int x_first, int x_count);
    void (*ao_blur_rows)(const AoFrame& f, int first, int count);
    void (*ao_upsample_rows)(const AoFrame& f, int first, int count, int x_first, int x_count,
                             float* blocks, int across);
    // Shadow map rows [first, first + count): window depth to distance
    // (shadow_kernels.cpp).
    void (*shadow_distance_rows)(const ShadowDistanceRows& rows, int first, int count);
    // Rows of tiles [first, first + count): each tile's planes.
    void (*shadow_plane_rows)(const ShadowPlaneRows& rows, int first, int count);
    // The texture sampler (sampler.hpp): 16 lanes of `mask`, with levels of
    // detail from the 2x2 quads; or `count` lanes, 2D or cube, with a level
    // per lane and, for a 2D texture, derivatives if given (the host's
    // textures service). The fragment stage calls its own path's directly;
    // here for the host's services and tests.
    void (*sample_block)(const TextureBinding& binding, const float* u, const float* v,
                         uint32_t mask, float* rgba);
    void (*sample_lanes)(const TextureBinding& binding, const float* coords, const float* lod,
                         const float* grads, uint32_t count, uint32_t mask, float* rgba);
    // The environment behind everything, target rows [first, first +
    // count): every pixel (or sample) still at the far depth takes its
    // radiance (sky.hpp).
    void (*sky_rows)(const SkyRows& sky, int first, int count);
};

// The kernels of a supported path; throws Error(isa_unavailable) otherwise.
const Kernels& kernels(Isa isa);

extern "C" {
extern const Kernels facet_kernels_portable;
extern const Kernels facet_kernels_avx2;
extern const Kernels facet_kernels_avx512;
}

}  // namespace facet
