#include "rasterize.hpp"

#include "simd.hpp"

#include "facet/framebuffer.hpp"

#include <bit>
#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace facet {

namespace {

using simd::f32x8;
using simd::f64x8;
using simd::i64x8;

constexpr int N = FACET_BLOCK_LANES;

}  // namespace

BlockCoverage::BlockCoverage(const TriangleSetup& t, int samples)
    : t_(t), samples_(samples), inv_area_(1.0 / double(t.area2)) {
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
        const i64x8 column = {0, 1, 2, 3, 0, 1, 2, 3}, row = {0, 0, 0, 0, 1, 1, 1, 1};
        lanes_lo_[k] = column * step_x_[k] + row * step_y_[k];
        lanes_hi_[k] = lanes_lo_[k] + 2 * step_y_[k];
    }
}

uint32_t BlockCoverage::covered(int k, int64_t at_lane0) const {
    return simd::bits(lanes_lo_[k] + at_lane0 >= threshold_[k]) |
           simd::bits(lanes_hi_[k] + at_lane0 >= threshold_[k]) << 8;
}

// Edge k's value over the area at each lane, rounded once to double and
// once to float: exactly 0 where the edge value is 0. One 16-lane store, so
// the fragment stage's 16-lane loads are forwarded from it.
void BlockCoverage::weights(int k, int64_t at_lane0, float* out) const {
    const auto weight = [&](const i64x8& lanes) {
        return __builtin_convertvector(__builtin_convertvector(lanes + at_lane0, f64x8) * inv_area_,
                                       f32x8);
    };
    const f32x8 lo = weight(lanes_lo_[k]), hi = weight(lanes_hi_[k]);
    simd::store(out, simd::f32x16(__builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9,
                                                          10, 11, 12, 13, 14, 15)));
}

// Lanes of the block at (bx, by) inside the inclusive box [x0, x1] x [y0, y1].
uint32_t BlockCoverage::box_mask(int bx, int by) const {
    const auto span = [](int first, int lo, int hi) {  // bits of first..first+3 in [lo, hi]
        const int skip = std::clamp(lo - first, 0, 4), keep = std::clamp(hi - first + 1, 0, 4);
        return skip >= keep ? 0u : ((1u << keep) - 1u) & ~((1u << skip) - 1u);
    };
    const uint32_t row = span(bx, t_.x0, t_.x1), rows = span(by, t_.y0, t_.y1);
    uint32_t mask = 0;
    for (int j = 0; j < 4; ++j)
        if (rows >> j & 1u) mask |= row << (4 * j);
    return mask;
}

// Per-lane sample coverage: bit s of lane_samples[i] is set when every edge
// covers lane i's sample s. Returns the lanes with any sample covered.
uint32_t BlockCoverage::cover_samples(const int64_t* e0, uint8_t* lane_samples) const {
    std::fill(lane_samples, lane_samples + N, uint8_t(0));
    uint32_t any = 0;
    for (int s = 0; s < samples_; ++s) {
        const glm::ivec2 o = sample_offset(samples_, s);
        uint32_t in = ~0u;
        for (int k = 0; k < 3; ++k) {
            // Sample offsets are in 1/16 pixel; the steps are whole pixels.
            static_assert(kSubpixelOne % 16 == 0);
            const int64_t at = e0[k] + (o.x * step_x_[k] + o.y * step_y_[k]) / 16;
            in &= covered(k, at);
        }
        any |= in;
        for (uint32_t m = in; m; m &= m - 1) lane_samples[std::countr_zero(m)] |= uint8_t(1u << s);
    }
    return any;
}

uint32_t BlockCoverage::operator()(int bx, int by, Block& block) const {
    // x and y in one store, so a later 8-byte load of both is forwarded
    // from it rather than stalling.
    static_assert(offsetof(Block, y) == offsetof(Block, x) + sizeof(int32_t));
    const int32_t xy[2] = {bx, by};
    std::memcpy(&block.x, xy, sizeof xy);
    block.mask = 0;

    // Trivial reject: an edge below its threshold at the block's best corner
    // (widened by half a pixel, where MSAA samples may lie) covers nothing.
    // Trivial accept: an edge that holds at the worst corner covers all.
    int64_t e0[3];
    bool all_in = true;
    uint32_t inside = box_mask(bx, by);
    for (int k = 0; k < 3; ++k) {
        e0[k] = centre_[k] + bx * step_x_[k] + by * step_y_[k];
        if (e0[k] + best_[k] < threshold_[k]) return 0;
        if (e0[k] + worst_[k] >= threshold_[k]) continue;
        all_in = false;
        if (samples_ == 1) inside &= covered(k, e0[k]);
    }
    if (samples_ > 1) {
        if (all_in) {  // every sample of every lane
            for (int i = 0; i < N; ++i)
                block.samples[i] = uint8_t((inside >> i) & 1u ? (1u << samples_) - 1u : 0u);
        } else {
            inside &= cover_samples(e0, block.samples);
        }
    }
    if (!inside) return 0;
    // The weight of the vertex opposite edge k: the exact edge value over
    // the exact area, so it is exactly 0 on the edge.
    for (int k = 0; k < 3; ++k) weights(k, e0[k], block.bary[(k + 2) % 3]);
    block.mask = inside;
    return inside;
}

}  // namespace facet
