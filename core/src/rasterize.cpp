#include "rasterize.hpp"

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

}  // namespace

uint32_t cover_block(const TriangleSetup& t, int bx, int by, Block& block) {
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
    block.x = bx;
    block.y = by;
    block.mask = inside;
    return inside;
}

}  // namespace facet
