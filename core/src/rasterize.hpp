// Rasterization.
//
// Takes: a TriangleSetup (setup.hpp).
// Gives: the triangle's coverage, one 4x4 block of pixels at a time: the
// lanes whose pixel centre the triangle covers under the top-left rule, and
// for every lane (covered or not) the screen-space barycentric weights of
// the three vertices, computed from the exact integer edge functions.
//
// Lane i of a block is pixel (x + i % 4, y + i / 4), as in the plugin ABI.
#pragma once

#include "setup.hpp"

#include <facet/shader_abi.h>

#include <cstdint>

namespace facet {

struct Block {
    int x, y;                        // pixel of lane 0 (multiples of 4)
    uint32_t mask;                   // covered lanes inside the bounding box
    float bary[3][FACET_BLOCK_LANES];  // weight of vertex k at lane i
};

// Coverage of the block at (bx, by); fills `block` and returns its mask.
uint32_t cover_block(const TriangleSetup& t, int bx, int by, Block& block);

// Calls visit(const Block&) for every block of t's bounding box that the
// triangle covers at least partly.
template <class Visit>
void rasterize(const TriangleSetup& t, Visit&& visit) {
    Block block;
    for (int by = t.y0 & ~3; by <= t.y1; by += FACET_BLOCK_SIZE)
        for (int bx = t.x0 & ~3; bx <= t.x1; bx += FACET_BLOCK_SIZE)
            if (cover_block(t, bx, by, block)) visit(block);
}

}  // namespace facet
