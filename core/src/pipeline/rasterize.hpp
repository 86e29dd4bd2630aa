// Rasterization (one of the per-ISA kernels, kernels.hpp).
//
// Takes: a TriangleSetup (setup.hpp).
// Gives: the triangle's coverage, one 4x4 block of pixels at a time: the
// lanes whose pixel centre the triangle covers under the top-left rule, and
// for every lane (covered or not) the screen-space barycentric weights of
// the three vertices.
//
// Each block's corner is tested in exact 64-bit arithmetic against every
// edge: outside one edge rejects the block, inside all three accepts it
// whole with no per-lane test. Only the edges that cross the block are
// evaluated per lane, relative to the corner, and for a triangle narrower
// than kNarrowEdgeSpan those values fit 32 bits exactly, so a register holds
// 16 lanes with AVX-512, 8 with AVX2 and 4 with SSE2; wider triangles use
// 64-bit lanes, which give the same coverage (tests hold the two to it).
//
// The weights are planes set up once per triangle: the exact edge value at
// the block's corner over the exact area, in double, plus a per-lane step
// that does not depend on the block. They are within a few units in the
// last place of the exact quotients, and no integer is converted per lane.
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

#include "pipeline/block.hpp"
#include "pipeline/setup.hpp"
#include "base/simd.hpp"

#include <algorithm>
#include <cstdint>

namespace facet::FACET_KERNEL_NS {

// What covering blocks of one triangle needs, worked out once: each edge
// function at the centre of pixel (0, 0) and its steps per pixel, the
// offsets of the 16 lanes (and of the MSAA samples), and the corners that
// decide trivial accept and reject.
class BlockCoverage {
public:
    // `samples` per pixel: 1, 2, 4 or 8.
    BlockCoverage(const TriangleSetup& t, int samples, EdgeWidth width = EdgeWidth::automatic);

    // Coverage of the block at (bx, by), within the lanes of `inside`;
    // fills `block` and returns its mask.
    uint32_t operator()(int bx, int by, uint32_t inside, Block& block) const;

private:
    uint32_t covered(int k, int64_t at_lane0) const;  // lanes where edge k holds
    uint32_t cover_samples(const int64_t* e0, uint32_t partial, uint8_t* lane_samples) const;
    static void clamp_covered_weights(uint32_t inside, Block& block);

    const TriangleSetup& t_;
    int samples_;
    bool narrow_;                    // 32-bit lanes
    bool clamp_weights_;             // covered lanes' weights held >= 0 (operator())
    int64_t centre_[3];              // edge k at the centre of pixel (0, 0)
    int64_t step_x_[3], step_y_[3];  // per pixel
    int64_t threshold_[3];           // covered where edge >= threshold (top-left rule)
    int64_t best_[3], worst_[3];     // offsets from lane 0 to the block's extreme corners
    int64_t sample_[3][8];           // offsets from a pixel's centre to its samples
    // Offsets from lane 0 to each lane of each part: 32-bit (narrow) or
    // 64-bit, half a part per vector (wide); and the change of the weight
    // edge k gives from lane 0.
    simd::Int lanes32_[3][simd::kParts];
    simd::Long lanes64_[3][2 * simd::kParts];
    simd::Float weight_lanes_[3][simd::kParts];
};

// The lanes of the block at (bx, by) at most at column x1 and row y1.
inline uint32_t lanes_within(int bx, int by, int x1, int y1) {
    const int columns = std::clamp(x1 - bx + 1, 0, 4), rows = std::clamp(y1 - by + 1, 0, 4);
    return (0x1111u * ((1u << columns) - 1u)) & ((1u << 4 * rows) - 1u);
}

// Calls visit(const Block&) for every block of t's bounding box, within the
// rectangle [x0, x1] x [y0, y1] (a tile, whose corners are multiples of 4),
// that the triangle covers at least partly. The bounding box holds every
// covered sample, so only where it was clipped to the viewport (x1, y1:
// its last column and row) must lanes past it be masked.
template <class Visit>
void rasterize(const BlockCoverage& cover, const TriangleSetup& t, int x0, int y0, int x1,
               int y1, Visit&& visit) {
    Block block;
    const int bx0 = std::max(t.x0, x0) & ~3, by0 = std::max(t.y0, y0) & ~3;
    const int bx1 = std::min(t.x1, x1), by1 = std::min(t.y1, y1);
    for (int by = by0; by <= by1; by += FACET_BLOCK_SIZE)
        for (int bx = bx0; bx <= bx1; bx += FACET_BLOCK_SIZE) {
            const uint32_t inside = bx + 3 <= t.x1 && by + 3 <= t.y1
                                        ? 0xFFFFu
                                        : lanes_within(bx, by, t.x1, t.y1);
            if (cover(bx, by, inside, block)) visit(block);
        }
}

// Lanes where edge k is at or above its threshold, given its value at lane
// 0. Narrow triangles only reach here for blocks the edge crosses, where
// every lane's value fits 32 bits (setup.hpp).
inline uint32_t BlockCoverage::covered(int k, int64_t at_lane0) const {
    uint32_t mask = 0;
    if (narrow_) {
        const int32_t at = int32_t(at_lane0), threshold = int32_t(threshold_[k]);
        for (int p = 0; p < simd::kParts; ++p)
            mask |= simd::bits(lanes32_[k][p] + at >= threshold) << (p * simd::kWidth);
        return mask;
    }
    for (int h = 0; h < 2 * simd::kParts; ++h) {
        // Cast: clang types a comparison of 64-bit lanes as long long lanes.
        const simd::Long inside = simd::Long(lanes64_[k][h] + at_lane0 >= threshold_[k]);
        mask |= simd::bits(inside) << (h * simd::kWidth / 2);
    }
    return mask;
}

}  // namespace facet::FACET_KERNEL_NS
