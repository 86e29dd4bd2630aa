// Fragment stage (one of the per-ISA kernels, kernels.hpp).
//
// Takes: one covered Block of a TriangleSetup, and the draw's constant state
// (DrawContext).
// Gives: the block's pixels depth-tested, shaded by the plugin in a single
// call, depth-written and blended into the framebuffer in its format.
//
// Depth is tested before shading (the shader cannot change depth; a
// discarding shader only removes lanes), so a block whose lanes are all
// hidden is never shaded; the shader sees the surviving lanes in the mask.
// Only the varyings the shader declares are interpolated, and textures are
// sampled only for shaders that ask for them, at the lanes it will shade.
#pragma once

#include "draw_context.hpp"
#include "kernels.hpp"
#include "setup.hpp"

namespace facet::FACET_KERNEL_NS {

// What the fragment stage needs of one triangle, worked out once for all of
// its blocks: varying float k is v0[k] + w1 d1[k] + w2 d2[k], with the
// perspective-correct or the screen-linear weights of vertices 1 and 2
// (flat ones have d1 = d2 = 0: vertex 0's value).
struct TriangleVaryings {
    float v0[FACET_MAX_VARYING_FLOATS];
    float d1[FACET_MAX_VARYING_FLOATS];
    float d2[FACET_MAX_VARYING_FLOATS];
};

void prepare_varyings(const DrawContext& dc, const TriangleSetup& t, TriangleVaryings& out);

void shade_block(const DrawContext& dc, const TriangleSetup& t, const TriangleVaryings& tv,
                 const Block& b, FrameStats& stats);

}  // namespace facet::FACET_KERNEL_NS
