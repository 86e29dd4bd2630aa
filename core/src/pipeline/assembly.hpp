// Primitive assembly, clipping and triangle setup.
//
// Takes: a queued draw's triangles (index triples) and its shaded vertices
// (vertex.hpp).
// Gives: a TriangleSetup per triangle (or clipped piece) that covers a
// pixel, in a SetupChunk, and the count of every triangle by its fate:
// invalid, outside the view, back-facing, degenerate, clipped or set up.
// A triangle inside the guard band is set up from its projected vertices;
// one that crosses it is clipped in homogeneous space first (clip.hpp), and
// its pieces keep the orientation of the whole.
#pragma once

#include "pipeline/clip.hpp"
#include "pipeline/draw_queue.hpp"
#include "pipeline/setup.hpp"

#include <cstddef>
#include <cstdint>

namespace facet {

// The back-face culling of a pipeline state's triangles (none for lines,
// points and the wire, whose lines face the eye).
CullState cull_state(const PipelineState& s);

// Counts a primitive's fate in `stats`.
void count_result(SetupResult r, FrameStats& stats);

// The fates of a run of triangles, counted in registers and added to a
// chunk's statistics once: a counter in memory would be read and written
// back at every triangle. (A triangle to be clipped is counted in `in`
// here, and its fate by Assembler::clip_triangle.)
struct AssemblyCounts {
    uint64_t in = 0, invalid = 0, outside = 0, back = 0, degenerate = 0, set_up = 0;
    void add_to(FrameStats& stats) const {
        stats.triangles_in += in;
        stats.triangles_invalid += invalid;
        stats.triangles_culled_frustum += outside;
        stats.triangles_culled_backface += back;
        stats.triangles_culled_degenerate += degenerate;
        stats.triangles_rasterized += set_up;
    }
};

// What the wide assembly kernel (Kernels::assemble_triangles) reads of a
// draw, and the way back into the core for the triangles it leaves there.
struct WideAssembly {
    const WindowVertex* window;  // the draw's vertices, projected
    const float* varyings;       // theirs, vertex_floats each
    uint32_t vertex_floats;
    uint32_t first_vertex;       // what each index has on the draw's vertex
    Viewport viewport;
    CullState cull;
    // A triangle with a corner outside the guard band: clipped, set up
    // and counted by the core, in its place in the order.
    void (*clip)(const void* assembler, const uint32_t* triangle, SetupChunk& chunk);
    const void* assembler;
};

// The kernel: sets up the first triangles of `idx` (a multiple of eight of
// them, none on a path without the lanes for it) into `chunk` as
// Assembler::run would, counts them, and returns how many it took.
using AssembleTriangles = size_t (*)(const WideAssembly& a, const uint32_t* idx, size_t count,
                                     SetupChunk& chunk);

class Assembler {
public:
    // The draw's vertex i is the mesh's first_vertex + i. `wide`, if not
    // null, takes the triangles it can (none of a state with a depth bias).
    Assembler(const QueuedDraw& d, const Viewport& viewport, const CullState& cull,
              uint32_t first_vertex, AssembleTriangles wide = nullptr);

    // Assembles, clips and sets up `triangles` triangles from `idx` (the
    // mesh's indices) into `chunk`, counting them in chunk.stats.
    void run(const uint32_t* idx, size_t triangles, SetupChunk& chunk) const;
    // The same for `count` lines (a pair of indices each) or points (one
    // each), each a rectangle or square of two triangles (lines.cpp),
    // counted as triangles in.
    void run_lines(const uint32_t* idx, size_t count, SetupChunk& chunk) const;
    void run_points(const uint32_t* idx, size_t count, SetupChunk& chunk) const;
    // The same for `count` edges of the wire (a MeshEdge each, edges.hpp)
    // of the triangles of `indices` (the part's): an edge is a line where
    // one of its triangles is kept by the state's culling.
    // `edges` lies in the draw's list, which starts at `list`: an edge of
    // more than two triangles, listed more than once, is drawn once.
    void run_wire(const uint32_t* edges, size_t count, const uint32_t* list,
                  const uint32_t* indices, SetupChunk& chunk) const;

private:
    // The triangle of three indices that must be clipped, set up and counted.
    void clip_triangle(const uint32_t* idx, SetupChunk& chunk) const;
    static void clip_triangle(const void* self, const uint32_t* idx, SetupChunk& chunk) {
        static_cast<const Assembler*>(self)->clip_triangle(idx, chunk);
    }
    // The line from mesh vertex a to b, cut to the depth range, as its
    // rectangle (lines.cpp), its fate counted.
    void line(uint32_t a, uint32_t b, SetupChunk& chunk) const;
    // Whether the triangle of `triangle`'s three indices is kept by the
    // state's culling, as seen from its clip-space corners.
    bool kept_by_culling(const uint32_t* triangle) const;
    bool kept_by_culling(const MeshEdge& e, const uint32_t* indices) const;  // either triangle
    void bias(TriangleSetup& t) const;  // the state's depth bias, added
    // The convex polygon `v` (n corners: a line's rectangle, a point's
    // square) clipped and set up, front-facing whichever way it turns.
    SetupResult quad(const ClipVertex* v, int n, SetupChunk& chunk) const;
    SetupResult fan(const ClipVertex* in, int n, uint32_t planes, SetupChunk& chunk) const;
    SetupResult setup(const SetupVertex v[3], int orientation, SetupChunk& chunk) const;
    SetupResult clipped(const SetupVertex v[3], uint32_t planes, SetupChunk& chunk) const;

    const DrawContext& dc_;
    const QueuedDraw& draw_;  // its vertices
    const Viewport viewport_;
    const CullState cull_;
    const double guard_;  // guard-band half-width, NDC
    const uint32_t first_vertex_;
    const bool biased_;  // the state has a depth bias (add_depth_bias) for its triangles
    const AssembleTriangles wide_;
    const WideAssembly wide_input_;
};

}  // namespace facet
