// What the AO pass's per-path kernels (ao_kernels.cpp) read and write: the
// AO grid's buffers and the target's depth (frame/ao.hpp fills it).
#pragma once

#include <glm/glm.hpp>

namespace facet {

// What the AO pass's kernels read and write (ao.hpp): buffers of the AO
// grid, `scale` times coarser per side than the target (texel i stands for
// target pixel i * scale), row-major, and the target's own buffers.
struct AoFrame {
    // March steps along each direction. Six rather than four: against
    // ray-traced AO, 5 directions of 6 steps beat 16 of 4
    // (facet-bench-shadow-ao) with under half the loads.
    static constexpr int kSteps = 6;
    int width = 0, height = 0;        // the AO grid
    int scale = 1;                    // 1 or 2
    int target_width = 0, target_height = 0;
    int samples = 0;                  // directions per texel
    float radius = 0.0f;              // world (view) units
    glm::mat4 projection{1.0f};
    // The view-space z of each texel's surface, 0 where nothing was drawn;
    // read a row and a vector past the grid on either side (zeros).
    float* z = nullptr;
    // Its x and y follow from z, on the ray of the texel's target pixel
    // (column px = min(i * scale, target_width - 1), row py the same):
    // x = (x0 + x1 * px) * z with a perspective projection, x0 + x1 * px
    // with an orthographic one, and y likewise from py. (Neither is stored:
    // at half size on a 1920x1080 target they were 4 MB to write and 4 MB
    // to read again each frame.)
    float x0 = 0.0f, x1 = 0.0f, y0 = 0.0f, y1 = 0.0f;
    // Sets perspective and x0 .. y1 for `proj` (facet::perspective's or
    // facet::orthographic's form: no skew, and in perspective the eye at
    // the origin) and the target's size (frame/ao.cpp).
    void set_pixel_rays(const glm::mat4& proj);
    // What the marches compare, per texel: 1 / -z with a perspective
    // projection, z with an orthographic one; 0 where nothing was drawn,
    // and in a border of kBorder texels around the grid: texel (i, j) at
    // key[j * key_stride + i], for -kBorder <= i < width + kBorder and the
    // same for j. A march that stays within it needs no clamping.
    static constexpr int kBorder = 32;
    // The occlusion decides whether texels are open in groups of 16 texels
    // of each of 4 rows, whatever the path: its columns start at multiples
    // of kGroupWidth, its rows at multiples of kGroupRows.
    static constexpr int kGroupWidth = 16, kGroupRows = 4;
    float* key = nullptr;
    int key_stride = 0;               // at least width + 2 kBorder; may be padded
    bool perspective = true;
    // View-space unit normals, which ao_normal_rows writes; the occlusion
    // works out its texels' own as it starts their marches (no pass writes
    // them for it: at half size on a 1920x1080 target they were 6 MB to
    // write and read again).
    float* nx = nullptr;
    float* ny = nullptr;
    float* nz = nullptr;
    // Hemisphere directions around +Z, turned for texel (x, y) by
    // (x & 3) * 4 + (y & 3): [y & 3][samples][x, y, z][x & 3], so that the
    // four turns along a row are four floats in a row.
    const float* directions = nullptr;
    float* raw = nullptr;             // visibility before the blur
    float* blurred = nullptr;         // ... after it
    // The target's window depth (rows target_stride floats apart), whose
    // `background` value means nothing was drawn, and the rows of the
    // inverse projection that give a pixel's view z: z = dot(z_row, ndc) /
    // dot(w_row, ndc), ndc = (x, y, depth, 1).
    const float* target_depth = nullptr;
    int target_stride = 0;
    float background = 0.0f;
    glm::vec4 z_row{0.0f}, w_row{0.0f};
};

}  // namespace facet
