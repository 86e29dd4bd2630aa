// Rasterization.
//
// Takes: a TriangleSetup (setup.hpp).
// Gives: the triangle's coverage, one 4x4 block of pixels at a time: the
// lanes whose pixel centre the triangle covers under the top-left rule, and
// for every lane (covered or not) the screen-space barycentric weights of
// the three vertices, computed from the exact integer edge functions.
//
// Lane i of a block is pixel (x + i % 4, y + i / 4), as in the plugin ABI.
//
// With MSAA (samples > 1) coverage is tested at each of the pixel's sample
// positions (Framebuffer's sample_offset()) instead of its centre, under the
// same top-left rule: `samples[i]` has bit s set when lane i's sample s is
// covered, and a lane is in `mask` when any of its samples is. The weights
// stay those of the pixel centre, where the shader runs, even when the
// centre itself is outside the triangle (no centroid interpolation: values
// there are extrapolated, by less than half a pixel).
#pragma once

#include "setup.hpp"
#include "simd.hpp"

#include <facet/shader_abi.h>

#include <algorithm>
#include <cstdint>

namespace facet {

struct Block {
    int32_t x, y;                    // pixel of lane 0 (multiples of 4), adjacent
    uint32_t mask;                   // covered lanes inside the bounding box
    alignas(64) float bary[3][FACET_BLOCK_LANES];  // weight of vertex k at lane i
    uint8_t samples[FACET_BLOCK_LANES];  // MSAA only: covered samples of lane i
};

// What covering blocks of one triangle needs, worked out once: each edge
// function at the centre of pixel (0, 0) and its steps per pixel, the
// offsets of the 16 lanes, and the corners that decide trivial accept and
// reject. Edge values stay exact 64-bit integers throughout.
class BlockCoverage {
public:
    // `samples` per pixel: 1, 2, 4 or 8.
    BlockCoverage(const TriangleSetup& t, int samples);

    // Coverage of the block at (bx, by); fills `block` and returns its mask.
    uint32_t operator()(int bx, int by, Block& block) const;

private:
    uint32_t box_mask(int bx, int by) const;
    uint32_t cover_samples(const int64_t* e0, uint8_t* lane_samples) const;
    uint32_t covered(int k, int64_t at_lane0) const;  // lanes where edge k holds
    void weights(int k, int64_t at_lane0, float* out) const;

    const TriangleSetup& t_;
    int samples_;
    double inv_area_;
    int64_t centre_[3];         // edge k at the centre of pixel (0, 0)
    int64_t step_x_[3], step_y_[3];  // per pixel
    int64_t threshold_[3];      // covered where edge >= threshold (top-left rule)
    int64_t best_[3], worst_[3];  // offsets from lane 0 to the block's extreme corners
    simd::i64x8 lanes_lo_[3], lanes_hi_[3];  // offsets from lane 0 to lanes 0..7, 8..15
};

// Calls visit(const Block&) for every block of t's bounding box, within the
// rectangle [x0, x1] x [y0, y1] (a tile, whose corners are multiples of 4),
// that the triangle covers at least partly.
template <class Visit>
void rasterize(const TriangleSetup& t, int x0, int y0, int x1, int y1, int samples,
               Visit&& visit) {
    const BlockCoverage cover(t, samples);
    Block block;
    const int bx0 = std::max(t.x0, x0) & ~3, by0 = std::max(t.y0, y0) & ~3;
    const int bx1 = std::min(t.x1, x1), by1 = std::min(t.y1, y1);
    for (int by = by0; by <= by1; by += FACET_BLOCK_SIZE)
        for (int bx = bx0; bx <= bx1; bx += FACET_BLOCK_SIZE)
            if (cover(bx, by, block)) visit(block);
}

// The same over the whole bounding box.
template <class Visit>
void rasterize(const TriangleSetup& t, int samples, Visit&& visit) {
    rasterize(t, t.x0, t.y0, t.x1, t.y1, samples, visit);
}
template <class Visit>
void rasterize(const TriangleSetup& t, Visit&& visit) {
    rasterize(t, t.x0, t.y0, t.x1, t.y1, 1, visit);
}

}  // namespace facet
