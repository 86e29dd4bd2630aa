// The coverage of a narrow triangle at one sample per pixel (one of the
// per-ISA kernels' headers).
//
// Nearly every triangle of a detailed mesh is narrow (TriangleSetup::narrow:
// every edge spans less than 4096 pixels) and most frames have one sample a
// pixel. For them this gives what BlockCoverage gives (rasterize.hpp), bit
// for bit: the same masks from the same exact edge values, and the same
// weights from the same float operations. It works out only what that case
// needs (no MSAA offsets, no 64-bit lanes), steps the edge values from
// block to block by addition, and is inline in the tile's loop, so that a
// triangle which covers a block or two (most of them, on a mesh far from
// the eye) costs little more than those blocks.
#pragma once

#include "pipeline/block.hpp"
#include "pipeline/rasterize.hpp"
#include "pipeline/setup.hpp"
#include "base/simd.hpp"

#include <algorithm>
#include <cstdint>

namespace facet::FACET_KERNEL_NS {

class NarrowCoverage {
public:
    // t.narrow must hold.
    explicit NarrowCoverage(const TriangleSetup& t) : t_(t) {
        const int64_t half = kSubpixelOne / 2;
        for (int k = 0; k < 3; ++k) {
            const EdgeFunction& e = t.edge[k];
            const int64_t step_x = -e.dy * kSubpixelOne, step_y = e.dx * kSubpixelOne;
            centre_[k] = e.at(half, half);
            step_x_[k] = step_x;
            step_y_[k] = step_y;
            threshold_[k] = -e.bias;
            best_[k] = std::max<int64_t>(0, 3 * step_x) + std::max<int64_t>(0, 3 * step_y);
            worst_[k] = std::min<int64_t>(0, 3 * step_x) + std::min<int64_t>(0, 3 * step_y);
            const int v = (k + 2) % 3;  // edge k gives the weight of vertex k + 2
            for (int p = 0; p < simd::kParts; ++p) {
                const simd::Int column = simd::column(), row = simd::row(p);
                weight_lanes_[k][p] = simd::to_float(column) * t.bary_dx[v] +
                                      simd::to_float(row) * t.bary_dy[v];
                // |steps| < 2^28 for a narrow triangle, so each offset fits.
                lanes_[k][p] = column * int32_t(step_x) + row * int32_t(step_y);
            }
        }
    }

    // Calls visit(bx, by, mask, e) for every block of the triangle's
    // bounding box within the tile [x0, x1] x [y0, y1] that it covers
    // (mask: its covered lanes), e[k] being edge k's exact value at the
    // block's lane 0, in rasterize()'s order.
    template <class Visit>
    void for_each_block(int x0, int y0, int x1, int y1, Visit&& visit) const {
        const TriangleSetup& t = t_;
        const int bx0 = std::max(t.x0, x0) & ~3, by0 = std::max(t.y0, y0) & ~3;
        const int bx1 = std::min(t.x1, x1), by1 = std::min(t.y1, y1);
        int64_t row[3];
        for (int k = 0; k < 3; ++k) row[k] = centre_[k] + bx0 * step_x_[k] + by0 * step_y_[k];
        for (int by = by0; by <= by1; by += FACET_BLOCK_SIZE) {
            int64_t e[3] = {row[0], row[1], row[2]};
            for (int bx = bx0; bx <= bx1; bx += FACET_BLOCK_SIZE) {
                if (const uint32_t mask = covered(bx, by, e)) visit(bx, by, mask, e);
                for (int k = 0; k < 3; ++k) e[k] += FACET_BLOCK_SIZE * step_x_[k];
            }
            for (int k = 0; k < 3; ++k) row[k] += FACET_BLOCK_SIZE * step_y_[k];
        }
    }

    // The weight of vertex k + 2 (edge k's) at part p's lanes of a block
    // whose covered lanes are `mask` and where edge k is e at lane 0, as
    // BlockCoverage gives it: the exact value over the exact area, plus
    // the plane's step; at the covered lanes held at 0 or above when the
    // setup asks (TriangleSetup::clamp_weights), for the shaded and the
    // depth-only routes alike (a pre-pass's depth must be the main pass's).
    float at_lane0(int64_t e) const { return float(double(e) * t_.inv_area2); }
    simd::Float weights(int k, float at_lane0, int p, uint32_t mask) const {
        const simd::Float w = at_lane0 + weight_lanes_[k][p];
        if (!t_.clamp_weights) return w;
        return simd::part_lanes(mask, p) ? simd::max(w, simd::Float{}) : w;
    }

    // The block BlockCoverage::operator() fills for one visit: its corner,
    // mask and weights.
    void fill(int bx, int by, uint32_t mask, const int64_t e[3], Block& block) const {
        block.x = bx;
        block.y = by;
        block.mask = mask;
        for (int k = 0; k < 3; ++k) {
            const float at = at_lane0(e[k]);
            for (int p = 0; p < simd::kParts; ++p)
                simd::store(block.bary[(k + 2) % 3] + p * simd::kWidth, weights(k, at, p, mask));
        }
    }

private:
    // The lanes of the block at (bx, by) that the triangle covers, edge k
    // being e[k] at lane 0: none when an edge fails at the block's best
    // corner, and only the edges that fail at its worst tested per lane, in
    // 32 bits (exact there: setup.hpp).
    uint32_t covered(int bx, int by, const int64_t e[3]) const {
        for (int k = 0; k < 3; ++k)
            if (e[k] + best_[k] < threshold_[k]) return 0;
        const TriangleSetup& t = t_;
        uint32_t mask =
            bx + 3 <= t.x1 && by + 3 <= t.y1 ? 0xFFFFu : lanes_within(bx, by, t.x1, t.y1);
        for (int k = 0; k < 3; ++k) {
            if (e[k] + worst_[k] >= threshold_[k]) continue;
            const int32_t at = int32_t(e[k]), threshold = int32_t(threshold_[k]);
            uint32_t in = 0;
            for (int p = 0; p < simd::kParts; ++p)
                in |= simd::bits(lanes_[k][p] + at >= threshold) << (p * simd::kWidth);
            mask &= in;
        }
        return mask;
    }

    const TriangleSetup& t_;
    int64_t centre_[3];              // edge k at the centre of pixel (0, 0)
    int64_t step_x_[3], step_y_[3];  // per pixel
    int64_t threshold_[3];           // covered where edge >= threshold (top-left rule)
    int64_t best_[3], worst_[3];     // offsets from lane 0 to the block's extreme corners
    simd::Int lanes_[3][simd::kParts];           // offsets from lane 0 to each lane
    simd::Float weight_lanes_[3][simd::kParts];  // the weights' change from lane 0
};

}  // namespace facet::FACET_KERNEL_NS
