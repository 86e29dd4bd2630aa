#include "clip.hpp"

#include <utility>

namespace facet {

namespace {

constexpr int kPlaneCount = 6;

// Signed distance of p to plane `i`: >= 0 inside.
template <class Vec, class T>
T distance(const Vec& p, int i, T guard) {
    switch (i) {
        case 0: return p.w - p.z;
        case 1: return p.z;
        case 2: return p.x + guard * p.w;
        case 3: return guard * p.w - p.x;
        case 4: return p.y + guard * p.w;
        default: return guard * p.w - p.y;
    }
}

uint32_t outcode(const glm::vec4& p, double guard) {
    const glm::dvec4 d(p);
    uint32_t code = 0;
    for (int i = 0; i < kPlaneCount; ++i)
        if (distance(d, i, guard) < 0.0) code |= 1u << i;
    return code;
}

// The point where edge (a, b) crosses the plane, interpolated from the inside
// vertex a (da >= 0 > db). Always starting from the inside vertex makes the
// result independent of the direction the edge is walked in.
void intersect(const ClipVertex& a, double da, const ClipVertex& b, double db, int floats,
               ClipVertex& out) {
    const double t = da / (da - db);
    out.position = a.position + t * (b.position - a.position);
    for (int k = 0; k < floats; ++k)
        out.varyings[k] = float(a.varyings[k] + t * (b.varyings[k] - a.varyings[k]));
}

// One Sutherland-Hodgman step against plane `plane`.
int clip_against(const ClipVertex* in, int n, int plane, double guard, int floats,
                 ClipVertex* out) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const ClipVertex& a = in[i];
        const ClipVertex& b = in[(i + 1) % n];
        const double da = distance(a.position, plane, guard);
        const double db = distance(b.position, plane, guard);
        if (da >= 0.0) out[m++] = a;
        if ((da >= 0.0) != (db >= 0.0)) {
            if (da >= 0.0) intersect(a, da, b, db, floats, out[m++]);
            else intersect(b, db, a, da, floats, out[m++]);
        }
    }
    return m;
}

}  // namespace

ClipClass classify(const glm::vec4& a, const glm::vec4& b, const glm::vec4& c, double guard) {
    const uint32_t view = outcode(a, 1.0) & outcode(b, 1.0) & outcode(c, 1.0);
    const uint32_t band = outcode(a, guard) | outcode(b, guard) | outcode(c, guard);
    return {view, band};
}

int clip_polygon(const ClipVertex* in, int n, uint32_t planes, double guard, int floats,
                 ClipVertex* out) {
    ClipVertex buffer[2][kMaxClipVertices];
    const ClipVertex* src = in;
    int count = n;
    int flip = 0;
    for (int plane = 0; plane < kPlaneCount && count > 0; ++plane) {
        if (!(planes & (1u << plane))) continue;
        count = clip_against(src, count, plane, guard, floats, buffer[flip]);
        src = buffer[flip];
        flip ^= 1;
    }
    for (int i = 0; i < count; ++i) out[i] = src[i];
    return count;
}

}  // namespace facet
