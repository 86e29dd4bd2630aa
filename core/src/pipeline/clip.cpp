#include "pipeline/clip.hpp"

#include <utility>

namespace facet {

namespace {

constexpr int kPlaneCount = 6;

// Signed distance of p to plane `i` (bit i of ClipPlane): >= 0 inside.
double distance(const glm::dvec4& p, int i, double guard) {
    switch (1u << i) {
        case kPlaneNear: return p.w - p.z;
        case kPlaneFar: return p.z;
        case kPlaneLeft: return p.x + guard * p.w;
        case kPlaneRight: return guard * p.w - p.x;
        case kPlaneBottom: return p.y + guard * p.w;
        default: return guard * p.w - p.y;
    }
}

// The point where edge (a, b) crosses the plane, interpolated from the inside
// vertex a (da >= 0 > db). Always starting from the inside vertex makes the
// result independent of the direction the edge is walked in.
void intersect(const ClipVertex& a, double da, const ClipVertex& b, double db, int floats,
               const uint8_t* interpolation, ClipVertex& out) {
    const double t = da / (da - db);
    // From the nearer end: with a far larger than b, t rounds to 1 and
    // a + t (b - a) lands on b itself, outside the plane.
    out.position = t <= 0.5 ? a.position + t * (b.position - a.position)
                            : b.position + (db / (db - da)) * (a.position - b.position);
    // The same point's fraction of the way along the edge on screen.
    const double s = out.position.w > 0.0 ? t * b.position.w / out.position.w : t;
    for (int k = 0; k < floats; ++k) {
        const double f = interpolation[k] == FACET_INTERP_LINEAR ? s : t;
        out.varyings[k] = float(a.varyings[k] + f * (b.varyings[k] - a.varyings[k]));
    }
}

// One Sutherland-Hodgman step against plane `plane`.
int clip_against(const ClipVertex* in, int n, int plane, double guard, int floats,
                 const uint8_t* interpolation, ClipVertex* out) {
    int m = 0;
    for (int i = 0; i < n && m + 2 <= kMaxClipVertices; ++i) {
        const ClipVertex& a = in[i];
        const ClipVertex& b = in[(i + 1) % n];
        const double da = distance(a.position, plane, guard);
        const double db = distance(b.position, plane, guard);
        if (da >= 0.0) out[m++] = a;
        if ((da >= 0.0) != (db >= 0.0)) {
            if (da >= 0.0) intersect(a, da, b, db, floats, interpolation, out[m++]);
            else intersect(b, db, a, da, floats, interpolation, out[m++]);
        }
    }
    return m;
}

}  // namespace

uint32_t outcode(const glm::dvec4& p, double guard) {
    // distance() for every plane at once, without its switch: this runs for
    // every vertex of every triangle.
    const double gw = guard * p.w;
    return (p.w - p.z < 0.0 ? kPlaneNear : 0u) | (p.z < 0.0 ? kPlaneFar : 0u) |
           (p.x + gw < 0.0 ? kPlaneLeft : 0u) | (gw - p.x < 0.0 ? kPlaneRight : 0u) |
           (p.y + gw < 0.0 ? kPlaneBottom : 0u) | (gw - p.y < 0.0 ? kPlaneTop : 0u);
}

bool outside_frustum(const Bounds& b, const glm::mat4& mvp) {
    uint32_t all = ~0u;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 corner(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y,
                               i & 4 ? b.max.z : b.min.z);
        all &= outcode(glm::dvec4(mvp * glm::vec4(corner, 1.0f)), 1.0);
    }
    return all != 0;
}

int clip_polygon(const ClipVertex* in, int n, uint32_t planes, double guard, int floats,
                 const uint8_t* interpolation, ClipVertex* out) {
    ClipVertex buffer[2][kMaxClipVertices];
    const ClipVertex* src = in;
    int count = n;
    int flip = 0;
    for (int plane = 0; plane < kPlaneCount && count > 0; ++plane) {
        if (!(planes & (1u << plane))) continue;
        count = clip_against(src, count, plane, guard, floats, interpolation, buffer[flip]);
        src = buffer[flip];
        flip ^= 1;
    }
    for (int i = 0; i < count; ++i) out[i] = src[i];
    return count;
}

}  // namespace facet
