// The hot loops, once per instruction-set path (facet/isa.hpp).
//
// rasterize.cpp, fragment.cpp, pixels.cpp, ao_kernels.cpp, shadow_kernels.cpp
// and kernels.cpp are compiled once for each path, with that path's compiler flags and in a
// namespace of its own (FACET_KERNEL_NS: isa_portable, isa_avx2,
// isa_avx512), and each compilation exports one table of function
// pointers, facet_kernels_<path>.
// The rest of the core is built for the baseline and calls the kernels of
// its Pipeline's path through that table: one indirect call per tile, per
// band of rows, never per pixel.
//
// The build links each path's objects into one relocatable object and
// makes every symbol but its table local (facet_isa_objects() in
// plugins/FacetShader.cmake): otherwise the linker would keep one copy of
// each inline function the paths share - std::min, a glm operator - and
// the SSE2 path could end up calling the AVX-512 copy.
#pragma once

#include "pipeline/setup.hpp"

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

// What the AO pass's kernels read and write (ao.hpp): buffers of the AO
// grid, `scale` times coarser per side than the target (texel i stands for
// target pixel i * scale), row-major, and the target's own buffers.
struct AoFrame {
    // March steps along each direction. Six rather than four: against
    // ray-traced AO, 5 directions of 6 steps beat 16 of 4
    // (facet-bench-shadow-ao) with under half the loads.
    static constexpr int kSteps = 6;
    int width = 0, height = 0;        // the AO grid
    int scale = 1;                    // 1 or 2
    int target_width = 0, target_height = 0;
    int samples = 0;                  // directions per texel
    float radius = 0.0f;              // world (view) units
    glm::mat4 projection{1.0f};
    // The view-space z of each texel's surface, 0 where nothing was drawn;
    // read a row and a vector past the grid on either side (zeros).
    float* z = nullptr;
    // Its x and y follow from z, on the ray of the texel's target pixel
    // (column px = min(i * scale, target_width - 1), row py the same):
    // x = (x0 + x1 * px) * z with a perspective projection, x0 + x1 * px
    // with an orthographic one, and y likewise from py. (Neither is stored:
    // at half size on a 1920x1080 target they were 4 MB to write and 4 MB
    // to read again each frame.)
    float x0 = 0.0f, x1 = 0.0f, y0 = 0.0f, y1 = 0.0f;
    // Sets perspective and x0 .. y1 for `proj` (facet::perspective's or
    // facet::orthographic's form: no skew, and in perspective the eye at
    // the origin) and the target's size (frame/ao.cpp).
    void set_pixel_rays(const glm::mat4& proj);
    // What the marches compare, per texel: 1 / -z with a perspective
    // projection, z with an orthographic one; 0 where nothing was drawn,
    // and in a border of kBorder texels around the grid: texel (i, j) at
    // key[j * key_stride + i], for -kBorder <= i < width + kBorder and the
    // same for j. A march that stays within it needs no clamping.
    static constexpr int kBorder = 32;
    // The occlusion decides whether texels are open in groups of 16 texels
    // of each of 4 rows, whatever the path: its columns start at multiples
    // of kGroupWidth, its rows at multiples of kGroupRows.
    static constexpr int kGroupWidth = 16, kGroupRows = 4;
    float* key = nullptr;
    int key_stride = 0;               // at least width + 2 kBorder; may be padded
    bool perspective = true;
    // View-space unit normals, which ao_normal_rows writes; the occlusion
    // works out its texels' own as it starts their marches (no pass writes
    // them for it: at half size on a 1920x1080 target they were 6 MB to
    // write and read again).
    float* nx = nullptr;
    float* ny = nullptr;
    float* nz = nullptr;
    // Hemisphere directions around +Z, turned for texel (x, y) by
    // (x & 3) * 4 + (y & 3): [y & 3][samples][x, y, z][x & 3], so that the
    // four turns along a row are four floats in a row.
    const float* directions = nullptr;
    float* raw = nullptr;             // visibility before the blur
    float* blurred = nullptr;         // ... after it
    // The target's window depth (rows target_stride floats apart), whose
    // `background` value means nothing was drawn, and the rows of the
    // inverse projection that give a pixel's view z: z = dot(z_row, ndc) /
    // dot(w_row, ndc), ndc = (x, y, depth, 1).
    const float* target_depth = nullptr;
    int target_stride = 0;
    float background = 0.0f;
    glm::vec4 z_row{0.0f}, w_row{0.0f};
};

// What the shadow pass's kernel reads and writes (frame/shadow.hpp): a
// shadow map's window depths and the same texels as 16-bit distances
// (facet_shadow_distances), both row-major.
struct ShadowDistanceRows {
    const float* depth = nullptr;  // window depth, 0..1, standard (near 0)
    int depth_stride = 0;          // floats from one row to the next
    uint16_t* distances = nullptr; // texel (0, 0) of the distances
    int distance_stride = 0;       // texels from one row to the next
    int width = 0;                 // a multiple of 16
    bool orthographic = true;
    float near_plane = 0.0f, far_plane = 1.0f;
};

// What the shadow pass's other kernel reads and writes: a map's distances,
// stored FACET_SHADOW_BORDER texels past each side, and the planes that
// bound them tile by tile (facet_shadow_planes), width / FACET_SHADOW_TILE
// tiles a row.
struct ShadowPlaneRows {
    const uint16_t* distances = nullptr;  // texel (0, 0)
    int stride = 0;                       // texels from one row to the next
    int width = 0;                        // the map's: a multiple of FACET_SHADOW_TILE
    float* tiles = nullptr;               // tile (0, 0)'s four floats
};

struct Kernels {
    Isa isa;
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
    // every sample, with streaming stores past the caches or (for the draws
    // about to follow) into them.
    void (*clear_rect)(Framebuffer& fb, int x0, int y0, int x1, int y1, const glm::vec4& color,
                       float depth, bool stream);
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
    // per lane (the host's textures service). The fragment stage
    // calls its own path's directly; here for the host's services and tests.
    void (*sample_block)(const TextureBinding& binding, const float* u, const float* v,
                         uint32_t mask, float* rgba);
    void (*sample_lanes)(const TextureBinding& binding, const float* coords, const float* lod,
                         uint32_t count, uint32_t mask, float* rgba);
};

// The kernels of a supported path; throws Error(isa_unavailable) otherwise.
const Kernels& kernels(Isa isa);

extern "C" {
extern const Kernels facet_kernels_portable;
extern const Kernels facet_kernels_avx2;
extern const Kernels facet_kernels_avx512;
}

}  // namespace facet
