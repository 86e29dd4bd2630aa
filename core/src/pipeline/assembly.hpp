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

class Assembler {
public:
    // The draw's vertex i is the mesh's first_vertex + i.
    Assembler(const QueuedDraw& d, const Viewport& viewport, const CullState& cull,
              uint32_t first_vertex)
        : dc_(d.dc), draw_(d), viewport_(viewport), cull_(cull), guard_(viewport.guard_ndc()),
          first_vertex_(first_vertex),
          biased_((d.dc.state.depth_bias_constant != 0.0f || d.dc.state.depth_bias_slope != 0.0f) &&
                  d.dc.state.topology == Topology::triangles && !d.dc.state.wireframe) {}

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
};

}  // namespace facet
