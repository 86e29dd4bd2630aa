// What stays constant over one draw, as the fragment stage reads it, and the
// host's side of the plugin ABI (host.cpp): the facet_draw a plugin sees and
// the service table it calls back into.
#pragma once

#include "facet/isa.hpp"
#include "facet/pipeline.hpp"

#include <facet/shader_abi.h>

namespace facet {

struct DrawContext {
    const facet_draw* abi = nullptr;
    const ShaderPlugin* shader = nullptr;
    facet_fragment_fn fragment = nullptr;      // the plugin's loop for the pipeline's path
    const TextureBinding* textures = nullptr;  // by slot; slots past texture_count are unbound
    int texture_count = 0;
    bool sample_textures = false;
    uint32_t varying_floats = 0;
    const uint8_t* interpolation = nullptr;    // per varying float
    bool perspective_only = true;              // no varying float is screen-linear
    bool packable = false;                     // fragments may be packed (fragment.hpp)
    const float* ao = nullptr;                 // target-sized, if the shader needs AO
    bool needs_ao = false;                     // the shader asks for AO (all ones without a pass)
    PipelineState state;
    Framebuffer* target = nullptr;
};

// Fills the shader's part of `dc`, with its fragment loop for `isa`.
void prepare_context(DrawContext& dc, const ShaderPlugin& shader, Isa isa,
                     const TextureBinding* textures, int texture_count);

// What the plugin sees of `call` drawn into a width x height target.
// host_data points at `dc`, for the host's services.
facet_draw make_abi_draw(const DrawCall& call, int width, int height, const DrawContext& dc);

// The service table passed to plugins in facet_draw.host.
const facet_host* host_services();

}  // namespace facet
