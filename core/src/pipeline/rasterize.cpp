#include "pipeline/rasterize.hpp"

#include "facet/framebuffer.hpp"

#include <bit>
#include <cstdlib>
#include <cstring>

namespace facet::FACET_KERNEL_NS {

using simd::Float;
using simd::Int;
using simd::Long;
using simd::kParts;
using simd::kWidth;

BlockCoverage::BlockCoverage(const TriangleSetup& t, int samples, EdgeWidth width)
    : t_(t), samples_(samples), narrow_(t.narrow && width == EdgeWidth::automatic),
      clamp_weights_(t.clamp_weights && samples == 1) {
    const int64_t half = kSubpixelOne / 2;
    for (int k = 0; k < 3; ++k) {
        const EdgeFunction& e = t.edge[k];
        centre_[k] = e.at(half, half);
        step_x_[k] = -e.dy * kSubpixelOne;
        step_y_[k] = e.dx * kSubpixelOne;
        threshold_[k] = -e.bias;
        // MSAA samples lie up to half a pixel from the lane's centre.
        const int64_t reach = samples > 1 ? (std::abs(step_x_[k]) + std::abs(step_y_[k])) / 2 : 0;
        best_[k] = std::max<int64_t>(0, 3 * step_x_[k]) + std::max<int64_t>(0, 3 * step_y_[k]) + reach;
        worst_[k] = std::min<int64_t>(0, 3 * step_x_[k]) + std::min<int64_t>(0, 3 * step_y_[k]) - reach;
        for (int s = 0; s < samples && samples > 1; ++s) {
            // Sample offsets are in 1/16 pixel; the steps are whole pixels.
            static_assert(kSubpixelOne % 16 == 0);
            const glm::ivec2 o = sample_offset(samples, s);
            sample_[k][s] = (o.x * step_x_[k] + o.y * step_y_[k]) / 16;
        }
        const int v = (k + 2) % 3;  // edge k gives the weight of vertex k + 2
        for (int p = 0; p < kParts; ++p) {
            const Int column = simd::column(), row = simd::row(p);
            weight_lanes_[k][p] = simd::to_float(column) * t.bary_dx[v] +
                                  simd::to_float(row) * t.bary_dy[v];
            if (narrow_) {  // |steps| < 2^28 here, so each lane's offset fits too
                lanes32_[k][p] = column * int32_t(step_x_[k]) + row * int32_t(step_y_[k]);
                continue;
            }
            for (int h = 0; h < 2; ++h)
                for (int j = 0; j < kWidth / 2; ++j) {
                    const int lane = p * kWidth + h * kWidth / 2 + j;
                    lanes64_[k][2 * p + h][j] = lane % 4 * step_x_[k] + lane / 4 * step_y_[k];
                }
        }
    }
}

// Per-lane sample coverage: bit s of lane_samples[i] is set when every edge
// covers lane i's sample s; edges not in `partial` cover every sample.
// Returns the lanes with any sample covered.
uint32_t BlockCoverage::cover_samples(const int64_t* e0, uint32_t partial,
                                      uint8_t* lane_samples) const {
    std::memset(lane_samples, 0, FACET_BLOCK_LANES);
    uint32_t any = 0;
    for (int s = 0; s < samples_; ++s) {
        uint32_t in = 0xFFFFu;
        for (uint32_t p = partial; p; p &= p - 1) {
            const int k = std::countr_zero(p);
            in &= covered(k, e0[k] + sample_[k][s]);
        }
        any |= in;
        for (uint32_t m = in; m; m &= m - 1) lane_samples[std::countr_zero(m)] |= uint8_t(1u << s);
    }
    return any;
}

void BlockCoverage::clamp_covered_weights(uint32_t inside, Block& block) {
    for (int p = 0; p < kParts; ++p) {
        const Int covered = simd::part_lanes(inside, p);
        for (int v = 0; v < 3; ++v) {
            const Float w = simd::load<Float>(block.bary[v] + p * kWidth);
            simd::store(block.bary[v] + p * kWidth, covered ? simd::max(w, Float{}) : w);
        }
    }
}

uint32_t BlockCoverage::operator()(int bx, int by, uint32_t inside, Block& block) const {
    block.x = bx;
    block.y = by;
    block.mask = 0;

    // Trivial reject: an edge below its threshold at the block's best corner
    // (widened by half a pixel, where MSAA samples may lie) covers nothing.
    // Trivial accept: an edge that holds at the worst corner covers all.
    int64_t e0[3];
    uint32_t partial = 0;
    for (int k = 0; k < 3; ++k) {
        e0[k] = centre_[k] + bx * step_x_[k] + by * step_y_[k];
        if (e0[k] + best_[k] < threshold_[k]) return 0;
        if (e0[k] + worst_[k] < threshold_[k]) partial |= 1u << k;
    }
    if (samples_ == 1) {
        for (uint32_t p = partial; p; p &= p - 1) {
            const int k = std::countr_zero(p);
            inside &= covered(k, e0[k]);
        }
    } else {
        inside &= cover_samples(e0, partial, block.samples);
    }
    if (!inside) return 0;
    // The weight of the vertex opposite edge k: the exact edge value at lane
    // 0 over the exact area, then the plane's step to each lane. With one
    // sample a covered lane's centre is inside, where no exact weight is
    // negative, but the float plane's rounding can make one a little so on
    // an edge: held at 0 there (clamp_weights_), a vertex whose 1/w is far
    // larger than the others' cannot pull the perspective weights out of
    // [0, 1] (lane_weights). Lanes not covered keep the plane's values, whose
    // differences are the quads' derivatives; so do MSAA lanes, whose
    // centres may lie outside, where the weights extrapolate.
    for (int k = 0; k < 3; ++k) {
        const float at_lane0 = float(double(e0[k]) * t_.inv_area2);
        for (int p = 0; p < kParts; ++p)
            simd::store(block.bary[(k + 2) % 3] + p * kWidth, at_lane0 + weight_lanes_[k][p]);
    }
    if (clamp_weights_) clamp_covered_weights(inside, block);
    block.mask = inside;
    return inside;
}

}  // namespace facet::FACET_KERNEL_NS
