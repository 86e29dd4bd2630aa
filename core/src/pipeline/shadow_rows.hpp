// What the shadow pass's per-path kernels (shadow_kernels.cpp) read and
// write: a shadow map's depths, its 16-bit distances and their planes.
#pragma once

#include <cstdint>

namespace facet {

// What the shadow pass's kernel reads and writes (frame/shadow.hpp): a
// shadow map's window depths and the same texels as 16-bit distances
// (facet_shadow_distances), both row-major.
struct ShadowDistanceRows {
    const float* depth = nullptr;  // window depth, 0..1, standard (near 0)
    int depth_stride = 0;          // floats from one row to the next
    uint16_t* distances = nullptr; // texel (0, 0) of the distances
    int distance_stride = 0;       // texels from one row to the next
    int width = 0;                 // a multiple of 16
    bool orthographic = true;
    float near_plane = 0.0f, far_plane = 1.0f;
};

// What the shadow pass's other kernel reads and writes: a map's distances,
// stored FACET_SHADOW_BORDER texels past each side, and the planes that
// bound them tile by tile (facet_shadow_planes), width / FACET_SHADOW_TILE
// tiles a row.
struct ShadowPlaneRows {
    const uint16_t* distances = nullptr;  // texel (0, 0)
    int stride = 0;                       // texels from one row to the next
    int width = 0;                        // the map's: a multiple of FACET_SHADOW_TILE
    float* tiles = nullptr;               // tile (0, 0)'s four floats
};

}  // namespace facet
