#include "rasterize.hpp"

#include "facet/framebuffer.hpp"

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
    const double inv_area = 1.0 / double(t.area2);

    uint32_t inside = box_mask(t, bx, by);
    for (int k = 0; k < 3; ++k) {
        const EdgeFunction& e = t.edge[k];
        const int64_t e0 = e.at(px, py);
        const int64_t step_x = -e.dy * kSubpixelOne;
        const int64_t step_y = e.dx * kSubpixelOne;
        float* weight = block.bary[(k + 2) % 3];
        uint32_t edge_mask = 0;
        for (int i = 0; i < N; ++i) {
            const int64_t value = e0 + (i % 4) * step_x + (i / 4) * step_y;
            edge_mask |= uint32_t(value + e.bias >= 0) << i;
            weight[i] = float(double(value) * inv_area);
        }
        inside &= edge_mask;
    }
    if (samples > 1) inside = box_mask(t, bx, by) & cover_samples(t, px, py, samples, block.samples);
    block.x = bx;
    block.y = by;
    block.mask = inside;
    return inside;
}

}  // namespace facet
