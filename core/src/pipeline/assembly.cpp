// Primitive assembly, clipping and triangle setup (assembly.hpp).
#include "pipeline/assembly.hpp"

#include "pipeline/clip.hpp"
#include "pipeline/vertex.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace facet {

namespace {

// Sign of the area of a convex clip-space polygon on screen (y down); 0
// when it is no wider than a step of the sub-pixel grid. Then every point
// of it lies within a step of its outline, and the fan of its snapped
// corners can fold over itself and cover samples twice.
int screen_orientation(const ClipVertex* poly, int n, const Viewport& viewport) {
    double area = 0.0, perimeter = 0.0;  // twice the area, in pixels
    for (int i = 0; i < n; ++i) {
        const glm::dvec2 a = to_window(poly[i].position, viewport);
        const glm::dvec2 b = to_window(poly[(i + 1) % n].position, viewport);
        area += a.x * b.y - b.x * a.y;
        perimeter += glm::length(b - a);
    }
    const double step = std::ldexp(1.0, -std::clamp(viewport.subpixel_bits, 1, kSubpixelBits));
    if (!(std::abs(area) > perimeter * step)) return 0;
    return area > 0.0 ? 1 : -1;
}

}  // namespace

void count_result(SetupResult r, FrameStats& stats) {
    switch (r) {
        case SetupResult::ok: ++stats.triangles_rasterized; break;
        case SetupResult::culled_backface: ++stats.triangles_culled_backface; break;
        case SetupResult::clipped_away: ++stats.triangles_culled_frustum; break;
        case SetupResult::degenerate:
        case SetupResult::no_pixels: ++stats.triangles_culled_degenerate; break;
    }
}

CullState cull_state(const PipelineState& s) {
    const bool culls = s.topology == Topology::triangles && !s.wireframe;
    return {culls && s.cull == CullMode::back, culls && s.cull == CullMode::front, s.front_ccw};
}

namespace {

bool has_bias(const PipelineState& s) {
    return (s.depth_bias_constant != 0.0f || s.depth_bias_slope != 0.0f) &&
           s.topology == Topology::triangles && !s.wireframe;
}

}  // namespace

Assembler::Assembler(const QueuedDraw& d, const Viewport& viewport, const CullState& cull,
                     uint32_t first_vertex, AssembleTriangles wide)
    : dc_(d.dc), draw_(d), viewport_(viewport), cull_(cull), guard_(viewport.guard_ndc()),
      first_vertex_(first_vertex), biased_(has_bias(d.dc.state)),
      wide_(biased_ ? nullptr : wide),
      wide_input_{d.window.data(), d.varyings.data(), d.dc.vertex_floats, first_vertex, viewport,
                  cull, &Assembler::clip_triangle, this} {}

void Assembler::clip_triangle(const uint32_t* idx, SetupChunk& chunk) const {
    SetupVertex v[3];
    uint32_t any = 0;
    for (int k = 0; k < 3; ++k) {
        const uint32_t i = idx[k] - first_vertex_;
        v[k] = {glm::dvec4(draw_.clip[i]), draw_.varyings.data() + size_t(i) * dc_.vertex_floats};
        any |= draw_.window[i].user;
    }
    const SetupResult r = clipped(v, band_code(any), chunk);
    if (r == SetupResult::ok) ++chunk.stats.triangles_clipped;
    count_result(r, chunk.stats);
}

void Assembler::run(const uint32_t* idx, size_t triangles, SetupChunk& chunk) const {
    if (wide_) {
        const size_t done = wide_(wide_input_, idx, triangles, chunk);
        idx += 3 * done;
        triangles -= done;
    }
    AssemblyCounts n;
    n.in = triangles;
    for (size_t t = 0; t < triangles; ++t, idx += 3) {
        const uint32_t i[3] = {idx[0] - first_vertex_, idx[1] - first_vertex_, idx[2] - first_vertex_};
        const WindowVertex* w[3] = {&draw_.window[i[0]], &draw_.window[i[1]], &draw_.window[i[2]]};
        const uint32_t any = w[0]->user | w[1]->user | w[2]->user;
        if (any & kInvalid) {
            ++n.invalid;
            continue;
        }
        if (view_code(w[0]->user) & view_code(w[1]->user) & view_code(w[2]->user)) {
            ++n.outside;
            continue;
        }
        if (band_code(any)) {
            clip_triangle(idx, chunk);
            continue;
        }
        if (any & kNoWindow) {  // a vertex at the origin, w = 0
            ++n.degenerate;
            continue;
        }
        const int64_t area2 = window_area2(w);
        if (const SetupResult r = facing_result(area2, cull_); r != SetupResult::ok) {
            ++(r == SetupResult::culled_backface ? n.back : n.degenerate);
            continue;
        }
        const float* varyings[3];
        for (int k = 0; k < 3; ++k)
            varyings[k] = draw_.varyings.data() + size_t(i[k]) * dc_.vertex_floats;
        TriangleSetup& s = chunk.setups.emplace_back();
        if (setup_kept_triangle(w, varyings, area2, viewport_, cull_, s) != SetupResult::ok) {
            chunk.setups.pop_back();  // no pixel centre
            ++n.degenerate;
            continue;
        }
        if (biased_) bias(s);
        ++n.set_up;
    }
    n.add_to(chunk.stats);
}

void Assembler::bias(TriangleSetup& t) const {
    add_depth_bias(t, dc_.state.depth_bias_constant, dc_.state.depth_bias_slope);
}

SetupResult Assembler::setup(const SetupVertex v[3], int orientation, SetupChunk& chunk) const {
    TriangleSetup& t = chunk.setups.emplace_back();
    const SetupResult r = setup_triangle(v, viewport_, cull_, t, orientation);
    if (r != SetupResult::ok) chunk.setups.pop_back();
    else if (biased_) bias(t);
    return r;
}


// Clips the triangle and sets up the fan of what is left, each piece held
// to the orientation of the whole polygon.
SetupResult Assembler::clipped(const SetupVertex v[3], uint32_t planes,
                                   SetupChunk& chunk) const {
    ClipVertex in[3];
    const int floats = int(dc_.varying_floats);
    for (int i = 0; i < 3; ++i) {
        in[i].position = v[i].clip;
        std::memcpy(in[i].varyings, v[i].varyings, sizeof(float) * floats);
    }
    return fan(in, 3, planes, chunk);
}

SetupResult Assembler::quad(const ClipVertex* v, int n, SetupChunk& chunk) const {
    const size_t first = chunk.setups.size();
    uint32_t planes = 0;  // those a corner lies outside: most quads need none
    for (int i = 0; i < n; ++i) planes |= outcode(v[i].position, guard_);
    const SetupResult r = fan(v, n, planes, chunk);
    for (size_t i = first; i < chunk.setups.size(); ++i) chunk.setups[i].front_facing = true;
    return r;
}

// Polygon `in` (n corners) clipped against `planes`, and the fan of what is
// left set up, each piece held to the orientation of the whole.
SetupResult Assembler::fan(const ClipVertex* in, int n_in, uint32_t planes,
                           SetupChunk& chunk) const {
    ClipVertex out[kMaxClipVertices];
    const int floats = int(dc_.varying_floats);
    const int n = clip_polygon(in, n_in, planes, guard_, floats, dc_.interpolation, out);
    if (n < 3) return SetupResult::clipped_away;
    // Flat varyings keep the first input vertex's value, not a blend.
    for (int k = 0; k < floats; ++k)
        if (dc_.interpolation[k] == FACET_INTERP_FLAT)
            for (int i = 0; i < n; ++i) out[i].varyings[k] = in[0].varyings[k];
    const size_t first = chunk.clipped_used;
    chunk.clipped_used += size_t(n);
    if (chunk.clipped.size() < chunk.clipped_used) chunk.clipped.resize(chunk.clipped_used);
    std::copy(out, out + n, chunk.clipped.begin() + std::ptrdiff_t(first));
    const int orientation = screen_orientation(out, n, viewport_);
    if (orientation == 0) return SetupResult::degenerate;
    SetupResult result = SetupResult::clipped_away;
    for (int i = 1; i + 1 < n; ++i) {
        const ClipVertex* a = &chunk.clipped[first];
        const ClipVertex* b = &chunk.clipped[first + size_t(i)];
        const ClipVertex* c = &chunk.clipped[first + size_t(i) + 1];
        const SetupVertex tri[3] = {{a->position, a->varyings},
                                    {b->position, b->varyings},
                                    {c->position, c->varyings}};
        const SetupResult r = setup(tri, orientation, chunk);
        if (r == SetupResult::ok || result == SetupResult::clipped_away) result = r;
    }
    return result;
}

}  // namespace facet
