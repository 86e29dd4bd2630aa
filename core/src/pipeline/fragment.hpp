// Fragment stage (one of the per-ISA kernels, kernels.hpp).
//
// Takes: one covered Block of a TriangleSetup, and the draw's constant state
// (DrawContext).
// Gives: the block's pixels depth-tested, shaded by the plugin in a single
// call, depth-written and blended into the framebuffer in its format.
//
// Depth is tested before shading (the shader cannot change depth; a
// discarding shader only removes lanes), so a block whose lanes are all
// hidden is never shaded; the shader sees the surviving lanes in the mask.
// Only the varyings the shader declares are interpolated, and textures are
// sampled only for shaders that ask for them, at the lanes it will shade.
//
// Small triangles cover a few pixels of each block they touch. For shaders
// that allow it (FACET_SHADER_PACKABLE), the covered fragments of a draw's
// blocks are packed into full batches (PackedBatch) instead, so that each
// shader call shades 16 fragments rather than the three or four a block of
// a small triangle has.
#pragma once

#include "pipeline/bin.hpp"
#include "pipeline/draw_context.hpp"
#include "pipeline/ao_frame.hpp"
#include "pipeline/block.hpp"
#include "pipeline/setup.hpp"
#include "base/simd.hpp"

#include <algorithm>

namespace facet::FACET_KERNEL_NS {

// What the fragment stage needs of one triangle, worked out once for all of
// its blocks: varying float k is v0[k] + w1 d1[k] + w2 d2[k], with the
// perspective-correct or the screen-linear weights of vertices 1 and 2
// (flat ones have d1 = d2 = 0: vertex 0's value).
struct TriangleVaryings {
    float v0[FACET_MAX_VARYING_FLOATS];
    float d1[FACET_MAX_VARYING_FLOATS];
    float d2[FACET_MAX_VARYING_FLOATS];
    float inv_w[3];  // the setup's, for the perspective-correct weights
};

void prepare_varyings(const DrawContext& dc, const TriangleSetup& t, TriangleVaryings& out);

// The weights of vertices 1 and 2 at part p of a block's lanes: screen-linear
// (l1, l2), and perspective-correct (p1, p2: each over its vertex's w,
// normalised per lane).
struct LaneWeights {
    simd::Float l1, l2, p1, p2;
};

inline LaneWeights lane_weights(const TriangleVaryings& tv, const Block& b, int p) {
    const int first = p * simd::kWidth;
    const simd::Float l1 = simd::load<simd::Float>(b.bary[1] + first);
    const simd::Float l2 = simd::load<simd::Float>(b.bary[2] + first);
    const simd::Float a = simd::load<simd::Float>(b.bary[0] + first) * tv.inv_w[0];
    const simd::Float c = l1 * tv.inv_w[1], d = l2 * tv.inv_w[2];
    const simd::Float w = 1.0f / (a + c + d);
    return {l1, l2, c * w, d * w};
}

// Varying float k where vertices 1 and 2 weigh w1 and w2: relative to
// vertex 0, which is exact for a constant attribute and better conditioned.
// Every route to a shader computes it this way, so that each gives the same
// floats.
inline simd::Float interpolate(const TriangleVaryings& tv, uint32_t k, const simd::Float& w1,
                               const simd::Float& w2) {
    return tv.v0[k] + w1 * tv.d1[k] + w2 * tv.d2[k];
}

// Whether varying float k of the draw is screen-linear.
inline bool screen_linear(const DrawContext& dc, uint32_t k) {
    return !dc.perspective_only && dc.interpolation[k] == FACET_INTERP_LINEAR;
}

void ao_upsample_rows(const AoFrame& f, int first, int count, int x_first, int x_count,
                      float* blocks, int across);  // ao_kernels.cpp

// Half-size AO upsampled over one tile (draw_tile) where a draw needs it:
// for the whole tile at once, at the first block that does, from the depth
// the AO pass read (the frame's pre-pass, which the opaque parts of the
// main pass only test against; a blended part that writes depth comes
// after them). A pass over the whole target would write a target-sized
// buffer that the main pass then reads back from memory (1.3 ms of a
// 1920x1080 frame on 2 threads); a tile's stays in the cache.
struct TileAo {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // the tile's pixels, inclusive
    bool ready = false;
    // The tile's 4x4 blocks, 16 floats each in lane order, kTileSize / 4 a
    // row: a block's visibility is a batch's `ao` as it is.
    float* visibility = nullptr;

    // The visibility of the 16 pixels of block b (1 past the target).
    const float* block(const AoFrame& f, const Block& b) {
        if (!ready) upsample(f);
        return visibility + size_t((b.y - y0) / 4 * (kTileSize / 4) + (b.x - x0) / 4) * 16;
    }

private:
    void upsample(const AoFrame& f);
};

// Covered fragments of one draw's blocks, of one facing, waiting to be
// shaded together: each batch of 16 is one call of the shader. Their depth
// is written when they pass the test, so the fragments that follow test
// against it; their colours are written, in the order the fragments came,
// when the batch is shaded, and before any other draw writes a pixel. So
// the image is the one that shading each block on its own gives, overlaps
// and blending included. One per thread (a tile at a time).
class PackedBatch {
public:
    // Appends the fragments of `mask` (depth-tested and written) of block b,
    // their inputs laid out as for a block's batch: after what waits of the
    // same draw and facing (shading what waits of another), shading each
    // batch they fill.
    void add(const DrawContext& dc, bool front_facing, const Block& b, uint32_t mask,
             const float* varyings, const float* depth, const float* texels, const float* ao,
             FrameStats& stats);
    // Shades and writes what waits.
    void flush(FrameStats& stats);
    bool empty() const { return count_ == 0; }

private:
    static constexpr int N = FACET_BLOCK_LANES;
    static constexpr int kRow = 2 * N;  // room to compress a block past a full batch
    // The fragments of `mask` into the batch, which has room for them.
    void append(const Block& b, uint32_t mask, const float* varyings, const float* depth,
                const float* texels, const float* ao);

    const DrawContext* dc_ = nullptr;
    bool front_facing_ = true;
    int count_ = 0;
    alignas(64) float varyings_[FACET_MAX_VARYING_FLOATS][kRow];
    alignas(64) float texels_[FACET_MAX_TEXTURES * 4][kRow];
    alignas(64) float depth_[kRow];
    alignas(64) float ao_[kRow];
    alignas(64) int32_t position_[kRow];  // x | y << 16 of each fragment's pixel
};

inline size_t pixel_index(const Framebuffer& fb, int x, int y) {
    return size_t(y) * size_t(fb.stride()) + size_t(x);
}

// Whether window depth z passes `compare` against the stored `stored`.
inline bool depth_test_passes(DepthCompare compare, float z, float stored) {
    switch (compare) {
        case DepthCompare::never: return false;
        case DepthCompare::less: return z < stored;
        case DepthCompare::less_equal: return z <= stored;
        case DepthCompare::greater: return z > stored;
        case DepthCompare::greater_equal: return z >= stored;
        case DepthCompare::equal: return z == stored;
        case DepthCompare::always: return true;
    }
    return false;
}

// Window depth at lane i of block b, from the exact weights, unclamped:
// the arithmetic of the per-part interpolation, lane by lane.
inline float centre_depth(const TriangleSetup& t, const Block& b, int i) {
    return t.z[0] + b.bary[1][i] * (t.z[1] - t.z[0]) + b.bary[2][i] * (t.z[2] - t.z[0]);
}

// MSAA: the depth plane's change per pixel in x and y, from the exact
// edge functions (vertex k+2's weight is edge k over twice the area).
glm::vec2 depth_gradient(const TriangleSetup& t);

// Depth at sample s of n (with one sample, the centre's), clamped like
// std::clamp (NaN stays NaN).
inline float sample_depth(float centre, glm::vec2 dz, int n, int s) {
    if (n == 1) return std::clamp(centre, 0.0f, 1.0f);
    const glm::vec2 o = glm::vec2(sample_offset(n, s)) * (1.0f / 16.0f);
    return std::clamp(centre + dz.x * o.x + dz.y * o.y, 0.0f, 1.0f);
}

// Per-sample depth of one block's lanes, and each lane's samples that
// passed (or, going in, the samples to test).
struct SampleDepth {
    float z[Framebuffer::kMaxSamples][FACET_BLOCK_LANES];
    uint8_t passed[FACET_BLOCK_LANES];
};

// Whether a draw writes depth only, with no shader call: no colour, no
// discard, no alpha to coverage, one sample per pixel, no stencil (shadow
// maps, pre-passes).
bool depth_only(const DrawContext& dc);

class NarrowCoverage;

// A depth-only draw of narrow triangle t (narrow_coverage.hpp) within the tile
// [x0, x1] x [y0, y1]: each covered block depth-tested and written, with
// the depths shade_block would give, in one pass with nothing stored
// between the stages.
void draw_depth_only(const DrawContext& dc, const NarrowCoverage& cover, const TriangleSetup& t,
                     int x0, int y0, int x1, int y1, FrameStats& stats);

// Shades one covered block of the tile `tile_ao` is for: through `packed`
// when the draw's shader allows it, else on its own (first shading what
// `packed` holds, to keep order).
void shade_block(const DrawContext& dc, const TriangleSetup& t, const TriangleVaryings& tv,
                 const Block& b, PackedBatch& packed, TileAo& tile_ao, FrameStats& stats);

}  // namespace facet::FACET_KERNEL_NS
