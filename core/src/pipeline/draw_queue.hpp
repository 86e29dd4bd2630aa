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
#include "pipeline/edges.hpp"
#include "pipeline/setup.hpp"

#include "facet/pipeline.hpp"

#include <glm/glm.hpp>

#include <deque>
#include <memory>
#include <vector>

namespace facet {

// What of a DrawCall its vertex stage, setup and binning depend on (all a
// vertex shader can read of its facet_draw, and the culling and snapping),
// the data pointed at by address: two calls alike in these, whose data
// did not change in between, make the same triangles, whatever their depth
// test, writes, blending or AO (Pipeline::redraw).
struct Geometry {
    const Mesh* mesh = nullptr;
    uint32_t first_index = 0, index_count = 0, first_vertex = 0, vertex_count = 0;
    const ShaderPlugin* shader = nullptr;
    const void* params = nullptr;
    const TextureBinding* textures = nullptr;
    int texture_count = 0;
    glm::mat4 model{1.0f}, view{1.0f}, projection{1.0f};
    glm::vec3 camera_position{0.0f};
    const facet_light* lights = nullptr;
    uint32_t light_count = 0;
    const facet_shadow* shadows = nullptr;
    float time = 0.0f;
    int image_height = 0, first_row = 0;
    CullMode cull = CullMode::back;
    bool front_ccw = true;
    int subpixel_bits = 8;
    Topology topology = Topology::triangles;
    bool wireframe = false;
    float line_width = 1.0f, point_size = 1.0f;
    float depth_bias_constant = 0.0f, depth_bias_slope = 0.0f;

    Geometry() = default;
    explicit Geometry(const DrawCall& call);
    bool operator==(const Geometry&) const = default;
};

// One queued draw: its constant state and its vertices' results, kept until
// its triangles are rasterized. Not movable: abi.host_data points at dc and
// dc.abi at abi.
struct QueuedDraw {
    QueuedDraw() = default;
    QueuedDraw(const QueuedDraw&) = delete;
    QueuedDraw& operator=(const QueuedDraw&) = delete;

    Geometry geometry;  // of the call that made it
    DrawContext dc;
    facet_draw abi{};
    std::vector<glm::vec4> clip;       // per vertex
    std::vector<WindowVertex> window;  // per vertex: projected, with its outcodes (vertex.cpp)
    std::vector<float> varyings;       // per vertex, varying_floats each
    // Lines: the part's edges, a pair of vertex indices each; its wire: its
    // edges (a MeshEdge each, edges.hpp); points: its vertices. Empty for
    // triangles, which read the mesh's indices.
    std::vector<uint32_t> primitives;
};

// A clear waiting for the draws into its target (Pipeline::clear). A tile
// is cleared as its first triangles are drawn (draw_tile), while its pixels
// are about to be in the cache anyway, and the tiles no draw touched when
// the clear is completed (Pipeline::flush), with streaming stores: no pass
// over the whole target reads it in only to overwrite it.
struct PendingClear {
    bool waiting = false;  // else done, and kept for its storage (a steady frame allocates nothing)
    Framebuffer* target = nullptr;
    glm::vec4 color{0.0f};
    float depth = 0.0f;
    uint8_t stencil = 0;
    int columns = 0, rows = 0;     // the target's tiles (kTileSize pixels), as Bins lays them out
    std::vector<uint8_t> cleared;  // per tile: done; each written by the thread drawing the tile

    // Whether the target still has the size it was cleared at (a target
    // resized since is left alone: Framebuffer::resize leaves its contents
    // undefined until it is cleared again).
    bool fits() const {
        return columns == tiles_across(target->width()) && rows == tiles_across(target->height());
    }
    // Tile `tile`'s storage rectangle [x0, x1) x [y0, y1): its pixels, and
    // the storage's padding where it is the last column or row of tiles.
    void storage_rect(int tile, int& x0, int& y0, int& x1, int& y1) const {
        x0 = tile % columns * kTileSize;
        y0 = tile / columns * kTileSize;
        x1 = tile % columns == columns - 1 ? target->stride() : x0 + kTileSize;
        y1 = tile / columns == rows - 1 ? target->rows() : y0 + kTileSize;
    }
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
    // Some of the queued draws' triangles were rasterized as they were
    // queued (the queue was full): the queue holds only the rest of them.
    bool split = false;
    // flush(stats, true) drew the queue and kept it, binned, for redraw(),
    // into a target of this size and sample count.
    bool kept = false;
    int kept_width = 0, kept_height = 0, kept_samples = 0;
    Bins bins;
    std::vector<WorkerStats> worker_stats;
    std::vector<PendingClear> clears;  // at most one waiting per target
    PendingClear* clear_now = nullptr;  // that of `target`, while its tiles are drawn
    EdgeCache edges;  // of the parts drawn as lines or wire
};

}  // namespace facet
