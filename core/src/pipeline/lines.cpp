// Lines and points as the rectangles and squares they cover (assembly.hpp,
// facet/render_state.hpp's Topology): built in window space around their
// projected end points, taken back to clip space with each end point's w,
// so that depth and varyings interpolate along a line as along an edge of
// a triangle, and set up as two triangles.
#include "pipeline/assembly.hpp"

#include "pipeline/edges.hpp"
#include "pipeline/vertex.hpp"

#include <glm/glm.hpp>

#include <cmath>
#include <cstring>

namespace facet {

namespace {

// Clip space of window point p (pixels, y down) at the w and z of `at`:
// the inverse of to_window.
glm::dvec4 from_window(glm::dvec2 p, const glm::dvec4& at, const Viewport& v) {
    return {(p.x / v.width * 2.0 - 1.0) * at.w, (1.0 - p.y / v.height * 2.0) * at.w, at.z, at.w};
}

// The part of segment a-b with 0 <= z <= w and w > 0, its varyings
// interpolated with it (in clip space), or false when nothing is.
bool clip_depth(ClipVertex& a, ClipVertex& b, int floats) {
    // Keeps where d >= 0, d varying linearly from da at a to db at b.
    const auto cut = [&](double da, double db) {
        if (da < 0.0 && db < 0.0) return false;
        if (da >= 0.0 && db >= 0.0) return true;
        const double t = da / (da - db);  // where d = 0, from a to b
        ClipVertex at;
        at.position = a.position + (b.position - a.position) * t;
        for (int k = 0; k < floats; ++k)
            at.varyings[k] = float(a.varyings[k] + (b.varyings[k] - a.varyings[k]) * t);
        (da < 0.0 ? a : b) = at;  // the end outside moves there
        return true;
    };
    return cut(a.position.z, b.position.z) &&
           cut(a.position.w - a.position.z, b.position.w - b.position.z) &&
           a.position.w > 0.0 && b.position.w > 0.0;
}

bool finite(const glm::dvec4& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
}

}  // namespace

void Assembler::line(uint32_t a, uint32_t b, SetupChunk& chunk) const {
    const int floats = int(dc_.varying_floats);
    ClipVertex end[2];
    const uint32_t at[2] = {a - first_vertex_, b - first_vertex_};
    for (int k = 0; k < 2; ++k) {
        end[k].position = glm::dvec4(draw_.clip[at[k]]);
        std::memcpy(end[k].varyings, draw_.varyings.data() + size_t(at[k]) * dc_.vertex_floats,
                    sizeof(float) * size_t(floats));
    }
    if (!finite(end[0].position) || !finite(end[1].position)) {
        ++chunk.stats.triangles_invalid;
        return;
    }
    if (!clip_depth(end[0], end[1], floats)) {
        ++chunk.stats.triangles_culled_frustum;
        return;
    }
    const glm::dvec2 p = to_window(end[0].position, viewport_);
    const glm::dvec2 q = to_window(end[1].position, viewport_);
    const double length = glm::length(q - p);
    if (!(length > 0.0)) {  // no direction: a line of no length covers nothing
        ++chunk.stats.triangles_culled_degenerate;
        return;
    }
    const double half = 0.5 * double(dc_.state.line_width);
    const glm::dvec2 across = glm::dvec2(p.y - q.y, q.x - p.x) * (half / length);
    ClipVertex corner[4] = {end[0], end[0], end[1], end[1]};
    corner[0].position = from_window(p + across, end[0].position, viewport_);
    corner[1].position = from_window(p - across, end[0].position, viewport_);
    corner[2].position = from_window(q - across, end[1].position, viewport_);
    corner[3].position = from_window(q + across, end[1].position, viewport_);
    count_result(quad(corner, 4, chunk), chunk.stats);
}

void Assembler::run_lines(const uint32_t* idx, size_t count, SetupChunk& chunk) const {
    for (size_t l = 0; l < count; ++l, idx += 2) {
        ++chunk.stats.triangles_in;
        line(idx[0], idx[1], chunk);
    }
}

// The sign of the determinant of a triangle's clip-space x, y and w gives
// its facing wherever its corners lie around w = 0 (Olano and Greer, 1997):
// it is the sign of its area in NDC (y up) times that of w0 w1 w2, and a
// triangle with a corner behind the eye is seen, where it is, turned as
// the determinant says.
bool Assembler::kept_by_culling(const uint32_t* triangle) const {
    glm::dvec3 r[3];
    for (int k = 0; k < 3; ++k) {
        const glm::dvec4 c(draw_.clip[triangle[k] - first_vertex_]);
        if (!finite(c)) return false;  // an invalid triangle draws nothing
        r[k] = glm::dvec3(c.x, c.y, c.w);
    }
    const double det = glm::dot(r[0], glm::cross(r[1], r[2]));
    if (!(det > 0.0 || det < 0.0)) return false;  // edge-on: nothing drawn
    const bool front = (det > 0.0) == cull_.front_ccw;
    return !((front && dc_.state.cull == CullMode::front) ||
             (!front && dc_.state.cull == CullMode::back));
}

bool Assembler::kept_by_culling(const MeshEdge& e, const uint32_t* indices) const {
    return kept_by_culling(indices + e.triangle[0]) ||
           (e.triangle[1] != kNoTriangle && kept_by_culling(indices + e.triangle[1]));
}

void Assembler::run_wire(const uint32_t* edges, size_t count, const uint32_t* list,
                         const uint32_t* indices, SetupChunk& chunk) const {
    const auto edge = [](const uint32_t* at) {
        MeshEdge e;
        std::memcpy(&e, at, sizeof e);
        return e;
    };
    for (size_t l = 0; l < count; ++l, edges += 4) {
        ++chunk.stats.triangles_in;
        const MeshEdge e = edge(edges);
        bool shown = kept_by_culling(e, indices);
        // An edge listed again (more than two triangles) is drawn by the
        // first of its listings with a triangle kept.
        for (const uint32_t* before = edges; shown && before != list;) {
            before -= 4;
            const MeshEdge b = edge(before);
            if (b.a != e.a || b.b != e.b) break;
            shown = !kept_by_culling(b, indices);
        }
        if (!shown) {
            ++chunk.stats.triangles_culled_backface;
            continue;
        }
        line(e.a, e.b, chunk);
    }
}

void Assembler::run_points(const uint32_t* idx, size_t count, SetupChunk& chunk) const {
    const int floats = int(dc_.varying_floats);
    const double half = 0.5 * double(dc_.state.point_size);
    for (size_t n = 0; n < count; ++n, ++idx) {
        ++chunk.stats.triangles_in;
        const uint32_t i = *idx - first_vertex_;
        ClipVertex centre;
        centre.position = glm::dvec4(draw_.clip[i]);
        std::memcpy(centre.varyings, draw_.varyings.data() + size_t(i) * dc_.vertex_floats,
                    sizeof(float) * size_t(floats));
        const glm::dvec4& p = centre.position;
        if (!finite(p)) {
            ++chunk.stats.triangles_invalid;
            continue;
        }
        if (!(p.w > 0.0 && p.z >= 0.0 && p.z <= p.w)) {  // a point is kept or not whole
            ++chunk.stats.triangles_culled_frustum;
            continue;
        }
        const glm::dvec2 c = to_window(p, viewport_);
        ClipVertex corner[4] = {centre, centre, centre, centre};
        const glm::dvec2 offsets[4] = {{-half, -half}, {-half, half}, {half, half}, {half, -half}};
        for (int k = 0; k < 4; ++k) corner[k].position = from_window(c + offsets[k], p, viewport_);
        count_result(quad(corner, 4, chunk), chunk.stats);
    }
}

}  // namespace facet
