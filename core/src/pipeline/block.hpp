// The rasterizer's unit of work: a 4x4 block of pixels of one triangle,
// its coverage and barycentric weights (rasterize.hpp gives them, the
// fragment stage shades them).
#pragma once

#include <facet/shader_abi.h>

#include <cstdint>

namespace facet {

// One 4x4 block of a triangle's coverage (rasterize.hpp).
struct Block {
    int32_t x, y;                    // pixel of lane 0 (multiples of 4), adjacent
    uint32_t mask;                   // covered lanes inside the bounding box
    alignas(64) float bary[3][FACET_BLOCK_LANES];  // weight of vertex k at lane i
    uint8_t samples[FACET_BLOCK_LANES];  // MSAA only: covered samples of lane i
};

// How a triangle's edge functions are evaluated inside a block (setup.hpp's
// TriangleSetup::narrow tells which applies).
enum class EdgeWidth {
    automatic,  // 32-bit lanes where the triangle allows it, else 64-bit
    wide,       // 64-bit lanes always (tests hold the two to the same coverage)
};

}  // namespace facet
