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

void shade_block(const DrawContext& dc, const TriangleSetup& t, const Block& b,
                 FrameStats& stats);

}  // namespace facet::FACET_KERNEL_NS
