// The host's side of the plugin ABI: the facet_draw a plugin sees of a draw
// call, and the services it may call back: log, and by extension
// "facet.textures" (sampling anywhere), "facet.environment" (image-based
// lighting) and, for screen passes, "facet.pass" (threads and scratch
// memory).
#include "pipeline/draw_context.hpp"

#include "pipeline/kernels.hpp"

#include "facet/math.hpp"
#include "facet/memory.hpp"
#include "facet/plugin.hpp"
#include "facet/texture.hpp"
#include "plugin/plugin_calls.hpp"

#include <spdlog/spdlog.h>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cstring>

namespace facet {

namespace {

void copy_matrix(float* dst, const glm::mat4& m) { std::memcpy(dst, glm::value_ptr(m), 64); }

void host_log(int level, const char* shader, const char* message) {
    const spdlog::level::level_enum levels[] = {spdlog::level::debug, spdlog::level::info,
                                                spdlog::level::warn, spdlog::level::err};
    spdlog::log(levels[std::clamp(level, 0, 3)], "[{}] {}", shader ? shader : "?",
                message ? message : "");
}

// ---- "facet.textures": the draw's textures where the shader wants them

// The binding at `slot` of the draw, or null where nothing is bound.
const TextureBinding* bound(const facet_draw* draw, uint32_t slot) {
    const auto* dc = static_cast<const DrawContext*>(draw->host_data);
    if (slot >= uint32_t(dc->texture_count) || !dc->textures[slot].texture) return nullptr;
    return &dc->textures[slot];
}

void textures_info(const facet_draw* draw, uint32_t slot, facet_texture_info* out) {
    *out = {};
    const TextureBinding* b = bound(draw, slot);
    if (!b) return;
    const Texture& t = *b->texture;
    out->kind = t.faces == 6 ? FACET_TEXTURE_CUBE : FACET_TEXTURE_2D;
    out->width = uint32_t(t.width);
    out->height = uint32_t(t.height);
    out->levels = mipmapped(b->filter) ? uint32_t(t.levels()) : 1u;
}

// As GLSL's textureGrad (facet_textures_service.sample_grad); null grads:
// as textureLod (.sample).
void textures_sample_grad(const facet_draw* draw, uint32_t slot, const float* coords,
                          const float* lod, const float* grads, uint32_t count, uint32_t mask,
                          float* rgba) {
    count = std::min(count, uint32_t(FACET_BLOCK_LANES));
    const TextureBinding* b = bound(draw, slot);
    if (!b) {
        for (uint32_t c = 0; c < 4; ++c)  // unbound: white
            for (uint32_t i = 0; i < count; ++i) rgba[c * count + i] = mask >> i & 1u ? 1.0f : 0.0f;
        return;
    }
    const auto* dc = static_cast<const DrawContext*>(draw->host_data);
    if (b->filter != Filter::anisotropic) grads = nullptr;  // only it reads them
    if (b->transform.identity() || b->texture->faces == 6) {
        dc->kernels->sample_lanes(*b, coords, lod, grads, count, mask, rgba);
        return;
    }
    // The shader's UVs and derivatives, placed by the binding's transform;
    // a level the shader gave, shifted by the transform's scale (one it did
    // not give is level 0, as asked).
    float placed[2 * FACET_BLOCK_LANES], shifted[FACET_BLOCK_LANES];
    float turned[4 * FACET_BLOCK_LANES];
    b->transform.apply(coords, coords + count, int(count), placed, placed + count);
    const float shift = b->transform.lod_shift();
    for (uint32_t i = 0; i < count; ++i) shifted[i] = lod ? lod[i] + shift : 0.0f;
    if (grads) {  // the derivatives turn and scale with the UVs, and do not move
        const std::array<float, 4> m = b->transform.matrix();
        for (int k = 0; k < 2; ++k)  // d/dx, then d/dy
            for (uint32_t i = 0; i < count; ++i) {
                const float du = grads[(2 * k) * count + i], dv = grads[(2 * k + 1) * count + i];
                turned[(2 * k) * count + i] = m[0] * du + m[1] * dv;
                turned[(2 * k + 1) * count + i] = m[2] * du + m[3] * dv;
            }
    }
    dc->kernels->sample_lanes(*b, placed, shifted, grads ? turned : nullptr, count, mask, rgba);
}

void textures_sample(const facet_draw* draw, uint32_t slot, const float* coords, const float* lod,
                     uint32_t count, uint32_t mask, float* rgba) {
    textures_sample_grad(draw, slot, coords, lod, nullptr, count, mask, rgba);
}

// ---- "facet.pass": threads and scratch memory for a screen pass

// Whether this thread runs a screen pass's task. The services below are
// for the pass's post function only (shader_abi.h): the pool runs one job
// at a time, and the scratch buffers are not locked.
thread_local bool t_in_post_task = false;

void host_parallel_for(const facet_pass_frame* frame, uint32_t count,
                       void (*task)(void* context, uint32_t index, uint32_t worker),
                       void* context) {
    const auto* pc = static_cast<const PostContext*>(frame->host_data);
    if (t_in_post_task) {  // from a task: run it here, in order, and say so
        spdlog::error("[{}] called parallel_for from one of its tasks; the tasks run on one "
                      "thread", pc->plugin->name());
        for (uint32_t i = 0; i < count; ++i) task(context, i, 0);
        return;
    }
    const InHostCode waiting;  // the tasks are the plugin calls timed, not this wait
    pc->pool->parallel_for(int(count), [&](int i, int worker) {
        t_in_post_task = true;
        call_plugin(pc->plugin, PluginEntry::post, task, context, uint32_t(i), uint32_t(worker));
        t_in_post_task = false;
    });
}

void* host_scratch(const facet_pass_frame* frame, uint32_t slot, size_t bytes) {
    const auto* pc = static_cast<const PostContext*>(frame->host_data);
    const char* name = pc->plugin->name().c_str();
    if (t_in_post_task) {
        spdlog::error("[{}] asked for scratch memory from one of its tasks (only its post "
                      "function may)", name);
        return nullptr;
    }
    if (slot >= FACET_PASS_SCRATCH_SLOTS) {
        spdlog::error("[{}] asked for scratch slot {} (there are {})", name, slot,
                      FACET_PASS_SCRATCH_SLOTS);
        return nullptr;
    }
    PostScratch& buffer = pc->scratch[slot];
    if (buffer.size() != bytes) {
        uint64_t total = bytes;
        for (uint32_t s = 0; s < FACET_PASS_SCRATCH_SLOTS; ++s)
            if (s != slot) total += pc->scratch[s].size();
        if (total > memory_budget()) {
            spdlog::error("[{}] asked for {} of scratch memory, over the memory budget of {}",
                          name, memory_text(total), memory_text(memory_budget()));
            return nullptr;
        }
        buffer.clear();
        buffer.shrink_to_fit();  // a new size: no copy of the old contents
        buffer.resize(bytes);
    }
    return buffer.data();
}

// The services a plugin finds by id and version (facet_host.extension).
// ---- "facet.environment": the scene's environment, prefiltered

const facet_environment* environment_lighting(const facet_draw* draw) {
    return static_cast<const DrawContext*>(draw->host_data)->environment;
}

const void* host_extension(const char* id, uint32_t version) {
    static const facet_textures_service textures = {
        sizeof(facet_textures_service), &textures_info, &textures_sample, &textures_sample_grad};
    static const facet_environment_service environment = {sizeof(facet_environment_service),
                                                          &environment_lighting};
    static const facet_pass_service pass = {sizeof(facet_pass_service), &host_parallel_for,
                                            &host_scratch};
    if (!id || version == 0) return nullptr;
    if (std::strcmp(id, FACET_TEXTURES_EXTENSION) == 0 && version <= FACET_TEXTURES_VERSION)
        return &textures;
    if (std::strcmp(id, FACET_PASS_EXTENSION) == 0 && version <= FACET_PASS_VERSION)
        return &pass;
    if (std::strcmp(id, FACET_ENVIRONMENT_EXTENSION) == 0 && version <= FACET_ENVIRONMENT_VERSION)
        return &environment;
    return nullptr;
}

}  // namespace

void prepare_context(DrawContext& dc, const ShaderPlugin& shader, Isa isa, const void* params,
                     const TextureBinding* textures, int texture_count, bool may_discard,
                     const PipelineState& state) {
    dc.shader = &shader;
    dc.fragment = shader.fragment_for(isa);
    dc.kernels = &kernels(isa);
    dc.vertex_floats = shader.varying_floats();
    dc.varying_floats = shader.read_floats(params);
    dc.interpolation = shader.float_interpolation();
    dc.perspective_only = true;
    for (uint32_t k = 0; k < dc.varying_floats; ++k)
        dc.perspective_only &= dc.interpolation[k] != FACET_INTERP_LINEAR;
    dc.textures = textures;
    dc.texture_count = textures ? std::min(texture_count, shader.texture_count()) : 0;
    // With no texture bound, the shader gets no texels and reads white.
    dc.sample_textures = false;
    if (shader.needs(FACET_NEED_TEXTURES))
        for (int s = 0; s < dc.texture_count; ++s) dc.sample_textures |= bool(textures[s].texture);
    dc.needs_ao = shader.needs(FACET_NEED_AO);
    dc.state = state;
    dc.may_discard = may_discard && shader.needs(FACET_NEED_DISCARD);
    // Packed fragments have their depth written before they are shaded.
    dc.packable = (shader.shader_desc().flags & FACET_SHADER_PACKABLE) &&
                  !shader.needs(FACET_NEED_DERIVATIVES) && !dc.may_discard &&
                  !state.alpha_to_coverage;
}

facet_draw make_abi_draw(const DrawCall& call, int width, int height, const DrawContext& dc) {
    facet_draw d{};
    alignas(16) static const unsigned char kNoParams[FACET_MAX_PARAMS_SIZE] = {};
    d.host = host_services();
    d.params = call.params ? call.params : kNoParams;  // never NULL
    d.host_data = &dc;
    copy_matrix(d.model, call.model);
    copy_matrix(d.view, call.view);
    copy_matrix(d.projection, call.projection);
    copy_matrix(d.view_projection, call.projection * call.view);
    copy_matrix(d.model_view_projection, call.projection * call.view * call.model);
    copy_matrix(d.normal_matrix, glm::mat4(normal_matrix(call.model)));
    d.camera_position[0] = call.camera_position.x;
    d.camera_position[1] = call.camera_position.y;
    d.camera_position[2] = call.camera_position.z;
    d.camera_position[3] = 1.0f;
    if (call.shader->needs(FACET_NEED_LIGHTS)) {
        d.light_count = call.light_count;
        d.lights = call.lights;
    }
    if (call.shader->needs(FACET_NEED_SHADOW_MAP) && d.lights) d.shadows = call.shadows;
    d.viewport_width = uint32_t(width);
    d.viewport_height = uint32_t(height);
    d.time = call.time;
    return d;
}

const facet_host* host_services() {
    static const facet_host host = {FACET_ABI_MAJOR, FACET_ABI_MINOR, sizeof(facet_host),
                                    &host_log, &host_extension};
    return &host;
}

}  // namespace facet
