// The vertex stage.
//
// Takes: a queued draw's mesh and shader, and the target's viewport.
// Gives: each vertex's clip position and varyings (the plugin's vertex
// function, kVertexBatch vertices per call, batches in parallel, with only
// the inputs the shader asks for), and its window position and outcodes,
// once per vertex however many triangles share it (QueuedDraw::window).
#pragma once

#include "pipeline/draw_queue.hpp"
#include "pipeline/setup.hpp"
#include "base/thread_pool.hpp"

#include <cstdint>

namespace facet {

struct Kernels;

// What the vertex stage records of each vertex in WindowVertex::user: its
// outcodes against the viewport (for rejection, view_code) and the guard
// band (for clipping, band_code), and whether it is unusable.
constexpr uint32_t kInvalid = 1u << 16;   // a non-finite clip position
constexpr uint32_t kNoWindow = 1u << 17;  // w <= 0: not projected
inline uint32_t view_code(uint32_t user) { return user & 0xFFu; }
inline uint32_t band_code(uint32_t user) { return user >> 8 & 0xFFu; }

// Shades vertices [first_vertex, first_vertex + vertex_count) of `mesh`
// (a part's) into d.clip, d.varyings and d.window, from their index 0.
void shade_vertices(const Mesh& mesh, uint32_t first_vertex, uint32_t vertex_count,
                    const ShaderPlugin& shader, const Viewport& viewport, const Kernels& kernels,
                    ThreadPool& pool, QueuedDraw& d);

}  // namespace facet
