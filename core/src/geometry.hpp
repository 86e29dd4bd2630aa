// What Renderer::draw keeps between draws (private to the core): the thread
// pool, the vertex stage's outputs, the setup chunks, the tile bins and
// per-thread statistics. Reused, so a steady frame allocates nothing.
#pragma once

#include "bin.hpp"
#include "setup.hpp"
#include "thread_pool.hpp"

#include <glm/glm.hpp>

#include <vector>

namespace facet {

struct Geometry {
    explicit Geometry(int threads) : pool(threads), worker_stats(size_t(pool.size())) {}

    ThreadPool pool;
    std::vector<glm::vec4> clip;   // per vertex
    std::vector<WindowVertex> window;  // per vertex: projected, with its outcodes (draw.cpp)
    std::vector<float> varyings;   // per vertex, varying_floats each
    std::vector<SetupChunk> chunks;
    Bins bins;
    std::vector<FrameStats> worker_stats;
};

}  // namespace facet
