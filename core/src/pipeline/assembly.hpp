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

// The back-face culling of a pipeline state (none for lines and points).
CullState cull_state(const PipelineState& s);

// Counts a primitive's fate in `stats`.
void count_result(SetupResult r, FrameStats& stats);

class Assembler {
public:
    // The draw's vertex i is the mesh's first_vertex + i.
    Assembler(const QueuedDraw& d, const Viewport& viewport, const CullState& cull,
              uint32_t first_vertex)
        : dc_(d.dc), draw_(d), viewport_(viewport), cull_(cull), guard_(viewport.guard_ndc()),
          first_vertex_(first_vertex) {}

    // Assembles, clips and sets up `triangles` triangles from `idx` (the
    // mesh's indices) into `chunk`, counting them in chunk.stats.
    void run(const uint32_t* idx, size_t triangles, SetupChunk& chunk) const;
    // The same for `count` lines (a pair of indices each) or points (one
    // each), each a rectangle or square of two triangles (lines.cpp),
    // counted as triangles in.
    void run_lines(const uint32_t* idx, size_t count, SetupChunk& chunk) const;
    void run_points(const uint32_t* idx, size_t count, SetupChunk& chunk) const;

private:
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
};

}  // namespace facet
