#include "rasterize.hpp"

#include "facet/framebuffer.hpp"

#include <cstdlib>

namespace facet {

namespace {

// Lanes of a 4x4 block at (bx, by) inside the inclusive box [x0,x1] x [y0,y1].
uint32_t box_mask(const TriangleSetup& t, int bx, int by) {
    uint32_t row = 0;
    for (int i = 0; i < 4; ++i)
        if (bx + i >= t.x0 && bx + i <= t.x1) row |= 1u << i;
    uint32_t mask = 0;
    for (int j = 0; j < 4; ++j)
        if (by + j >= t.y0 && by + j <= t.y1) mask |= row << (4 * j);
    return mask;
}

// Per-lane sample coverage: bit s of samples[i] is set when every edge
// covers lane i's sample s. Returns the lanes with any sample covered.
uint32_t cover_samples(const TriangleSetup& t, int64_t px, int64_t py, int samples,
                       uint8_t* covered) {
    constexpr int N = FACET_BLOCK_LANES;
    constexpr int64_t sixteenth = kSubpixelOne / 16;
    std::fill(covered, covered + N, uint8_t(0));
    for (int s = 0; s < samples; ++s) {
        const glm::ivec2 o = sample_offset(samples, s);
        const int64_t sx = px + o.x * sixteenth, sy = py + o.y * sixteenth;
        uint32_t in = ~0u;
        for (const EdgeFunction& e : t.edge) {
            const int64_t e0 = e.at(sx, sy) + e.bias;
            const int64_t step_x = -e.dy * kSubpixelOne, step_y = e.dx * kSubpixelOne;
            uint32_t edge_mask = 0;
            for (int i = 0; i < N; ++i)
                edge_mask |= uint32_t(e0 + (i % 4) * step_x + (i / 4) * step_y >= 0) << i;
            in &= edge_mask;
        }
        for (int i = 0; i < N; ++i) covered[i] |= uint8_t(((in >> i) & 1u) << s);
    }
    uint32_t lanes = 0;
    for (int i = 0; i < N; ++i) lanes |= uint32_t(covered[i] != 0) << i;
    return lanes;
}

}  // namespace

uint32_t cover_block(const TriangleSetup& t, int bx, int by, int samples, Block& block) {
    constexpr int N = FACET_BLOCK_LANES;
    const int64_t half = kSubpixelOne / 2;
    const int64_t px = int64_t(bx) * kSubpixelOne + half;  // centre of lane 0
    const int64_t py = int64_t(by) * kSubpixelOne + half;
    block.x = bx;
    block.y = by;
    block.mask = 0;

    // Trivial reject: an edge that is negative at the block's best corner
    // (widened by half a pixel, where MSAA samples may lie) covers nothing.
    // Trivial accept: an edge that holds at the worst corner covers all.
    int64_t e0[3], step_x[3], step_y[3];
    bool all_in[3];
    for (int k = 0; k < 3; ++k) {
        const EdgeFunction& e = t.edge[k];
        e0[k] = e.at(px, py);
        step_x[k] = -e.dy * kSubpixelOne;
        step_y[k] = e.dx * kSubpixelOne;
        const int64_t reach = samples > 1 ? (std::abs(step_x[k]) + std::abs(step_y[k])) / 2 : 0;
        const int64_t best = e0[k] + std::max<int64_t>(0, 3 * step_x[k]) +
                             std::max<int64_t>(0, 3 * step_y[k]) + e.bias + reach;
        if (best < 0) return 0;
        const int64_t worst = e0[k] + std::min<int64_t>(0, 3 * step_x[k]) +
                              std::min<int64_t>(0, 3 * step_y[k]) + e.bias - reach;
        all_in[k] = worst >= 0;
    }

    uint32_t inside = box_mask(t, bx, by);
    const double inv_area = 1.0 / double(t.area2);
    for (int k = 0; k < 3; ++k) {
        if (!all_in[k]) {
            uint32_t edge_mask = 0;
            for (int i = 0; i < N; ++i)
                edge_mask |= uint32_t(e0[k] + (i % 4) * step_x[k] + (i / 4) * step_y[k] +
                                          t.edge[k].bias >= 0) << i;
            inside &= edge_mask;
        }
        // The weight of the vertex opposite the edge: the exact edge value
        // over the exact area, so it is exactly 0 on the edge.
        float* weight = block.bary[(k + 2) % 3];
        for (int i = 0; i < N; ++i)
            weight[i] = float(double(e0[k] + (i % 4) * step_x[k] + (i / 4) * step_y[k]) * inv_area);
    }
    if (samples > 1) {
        if (all_in[0] && all_in[1] && all_in[2]) {  // every sample of every lane
            for (int i = 0; i < N; ++i)
                block.samples[i] = uint8_t((inside >> i) & 1u ? (1u << samples) - 1u : 0u);
        } else {
            inside = box_mask(t, bx, by) & cover_samples(t, px, py, samples, block.samples);
        }
    }
    block.mask = inside;
    return inside;
}

}  // namespace facet
