// Fragment stage.
//
// Takes: one covered Block of a TriangleSetup, and the draw's constant state
// (DrawContext).
// Gives: the block's pixels depth-tested, shaded by the plugin in a single
// call, depth-written and blended into the framebuffer.
//
// Depth is tested before shading (the shader cannot change depth; a
// discarding shader only removes lanes), so a block whose lanes are all
// hidden is never shaded; the shader sees the surviving lanes in the mask.
// Only the varyings the shader declares are interpolated, and textures are
// sampled only for shaders that ask for them.
#pragma once

#include "rasterize.hpp"
#include "setup.hpp"

#include "facet/renderer.hpp"

#include <facet/shader_abi.h>

namespace facet {

// Everything that stays constant over one draw.
struct DrawContext {
    const facet_draw* abi = nullptr;
    const ShaderPlugin* shader = nullptr;
    const TextureBinding* textures = nullptr;  // by slot; slots past texture_count are unbound
    int texture_count = 0;
    bool sample_textures = false;
    uint32_t varying_floats = 0;
    const uint8_t* interpolation = nullptr;    // per varying float
    const float* ao = nullptr;                 // target-sized, if the shader needs AO
    bool needs_ao = false;                     // the shader asks for AO (all ones without a pass)
    PipelineState state;
    Framebuffer* target = nullptr;
};

void prepare_context(DrawContext& dc, const ShaderPlugin& shader, const TextureBinding* textures,
                     int texture_count);

void shade_block(const DrawContext& dc, const TriangleSetup& t, const Block& b,
                 FrameStats& stats);

// What the plugin sees of `call` drawn into a width x height target
// (draw.cpp). host_data points at `dc`, for the host's services.
facet_draw make_abi_draw(const DrawCall& call, int width, int height, const DrawContext& dc);

// The service table passed to plugins in facet_draw.host.
const facet_host* host_services();

}  // namespace facet
