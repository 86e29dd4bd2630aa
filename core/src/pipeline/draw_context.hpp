// What stays constant over one draw, as the fragment stage reads it, and the
// host's side of the plugin ABI (host.cpp): the facet_draw a plugin sees and
// the service table it calls back into.
#pragma once

#include "base/thread_pool.hpp"

#include "facet/framebuffer.hpp"
#include "facet/isa.hpp"
#include "facet/pipeline.hpp"

#include <facet/shader_abi.h>

#include <vector>

namespace facet {

struct Kernels;

struct DrawContext {
    const facet_draw* abi = nullptr;
    const ShaderPlugin* shader = nullptr;
    facet_fragment_fn fragment = nullptr;      // the plugin's loop for the pipeline's path
    const Kernels* kernels = nullptr;          // the pipeline's path (the textures service)
    const TextureBinding* textures = nullptr;  // by slot; slots past texture_count are unbound
    int texture_count = 0;
    bool sample_textures = false;
    // The varying floats interpolated: all of them, or without the
    // conditional ones the material does not read (ShaderPlugin::read_floats),
    // which fragment batches leave unset.
    uint32_t varying_floats = 0;
    uint32_t vertex_floats = 0;                // all of them: a shaded vertex's stride
    const uint8_t* interpolation = nullptr;    // per varying float
    bool perspective_only = true;              // no varying float is screen-linear
    bool packable = false;                     // fragments may be packed (fragment.hpp)
    bool may_discard = false;                  // the shader may clear mask bits
    bool stencil = false;                      // tests and writes the target's stencil
    const float* ao = nullptr;                 // target-sized, if the shader needs AO
    const AoFrame* ao_grid = nullptr;          // or half-size, upsampled by tiles
    bool needs_ao = false;                     // the shader asks for AO (all ones without a pass)
    const facet_environment* environment = nullptr;  // "facet.environment"'s answer
    PipelineState state;
    Framebuffer* target = nullptr;
    int first_row = 0;  // the target's first row in the image (DrawCall::first_row)
};

// A screen pass's scratch buffer (facet_pass_service.scratch), kept between frames.
using PostScratch = std::vector<uint8_t, CacheLineAllocator<uint8_t>>;

// What the host's services for a screen pass see through
// facet_pass_frame.host_data: the threads its tasks run on, and its scratch
// buffers. A task runs inside InPlugin (plugin_calls.hpp), so that a crash
// in it names the pass.
struct PostContext {
    const ShaderPlugin* plugin = nullptr;
    ThreadPool* pool = nullptr;
    PostScratch* scratch = nullptr;  // [FACET_PASS_SCRATCH_SLOTS]
};

// Fills the shader's part of `dc`, with its fragment loop for `isa`, for
// a draw with parameter block `params` whose fragments the shader
// `may_discard` (DrawCall::may_discard, if the shader needs
// FACET_NEED_DISCARD) under `state`.
void prepare_context(DrawContext& dc, const ShaderPlugin& shader, Isa isa, const void* params,
                     const TextureBinding* textures, int texture_count, bool may_discard,
                     const PipelineState& state);

// What the plugin sees of `call` drawn into a width x height target.
// host_data points at `dc`, for the host's services.
facet_draw make_abi_draw(const DrawCall& call, int width, int height, const DrawContext& dc);

// The service table passed to plugins in facet_draw.host and
// facet_pass_frame.host.
const facet_host* host_services();

}  // namespace facet
