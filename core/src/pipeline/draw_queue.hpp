// What Pipeline::queue keeps until flush() (private to the core): the
// queued draws with their vertex stage's outputs, the setup chunks, the tile
// bins and per-thread statistics. Reused, so a steady frame allocates
// nothing.
//
// Draws queue up until flush() (or until the queue is full): their triangles
// are binned together, so each tile is rasterized once for all of them while
// its pixels stay in cache, rather than once per draw.
#pragma once

#include "pipeline/bin.hpp"
#include "pipeline/draw_context.hpp"
#include "pipeline/setup.hpp"

#include "facet/pipeline.hpp"

#include <glm/glm.hpp>

#include <deque>
#include <memory>
#include <vector>

namespace facet {

// One queued draw: its constant state and its vertices' results, kept until
// its triangles are rasterized. Not movable: abi.host_data points at dc and
// dc.abi at abi.
struct QueuedDraw {
    QueuedDraw() = default;
    QueuedDraw(const QueuedDraw&) = delete;
    QueuedDraw& operator=(const QueuedDraw&) = delete;

    DrawContext dc;
    facet_draw abi{};
    std::vector<glm::vec4> clip;       // per vertex
    std::vector<WindowVertex> window;  // per vertex: projected, with its outcodes (vertex.cpp)
    std::vector<float> varyings;       // per vertex, varying_floats each
};

struct DrawQueue {
    explicit DrawQueue(int threads) : worker_stats(size_t(threads)) {}

    // A thread's counters, on cache lines of its own (see SetupChunk).
    struct alignas(64) WorkerStats {
        FrameStats stats;
    };

    std::vector<std::unique_ptr<QueuedDraw>> draws;  // the first draws_used are queued
    int draws_used = 0;
    // The first chunks_used hold setups not yet rasterized. A deque: growing
    // it never moves the queued chunks, whose clipped vertices setups point at.
    std::deque<SetupChunk> chunks;
    int chunks_used = 0;
    size_t triangles_queued = 0;     // in those chunks, before clipping and culling
    Framebuffer* target = nullptr;   // of the queued draws
    Bins bins;
    std::vector<WorkerStats> worker_stats;
};

}  // namespace facet
