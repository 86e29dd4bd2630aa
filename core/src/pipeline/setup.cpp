#include "pipeline/setup.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace facet {

namespace {

// Rounds a window coordinate to the nearest multiple of 1 / 2^bits pixel
// (halves away from zero), in units of the kSubpixelBits grid. NaN goes to
// the limit rather than to an undefined integer. No call into libm (the
// core is built for the baseline, where fmin and trunc are calls): this
// runs for every vertex.
int64_t snap(double window, int bits) {
    const double limit = kGuardBandPixels * 2.0;  // never reached after clipping
    double c = window < limit ? window : limit;   // NaN: the limit
    c = c > -limit ? c : -limit;
    // Scaling by a power of two is exact; |v| < 2^30, so converting it to
    // an integer truncates it exactly, and so is v - t.
    const double v = c * double(int64_t(1) << bits);
    const int64_t t = int64_t(v);
    const double f = v - double(t);
    // Without a branch: which way a coordinate rounds is a coin toss.
    const int64_t r = t + int64_t(f >= 0.5) - int64_t(f <= -0.5);
    return r * (int64_t(1) << (kSubpixelBits - bits));
}

// The floor of a setup's scaled 1/w (see setup_triangle).
constexpr float kMinInverseW = 0x1p-64f;

// TriangleSetup::clamp_weights. A lane's weight is rounded by about
// 2^-22 (1 + 4 s), s being the most a weight steps from one pixel to the
// next (at most `step`: rounding of the lane-0 value, of the steps and of
// their sum); a vertex whose 1/w is r times another's scales that error by
// up to r in the perspective weights. Past 2^-17 there (r (1 + 4 s) > 32:
// far-apart 1/w, or a triangle a few pixels across) the covered lanes are
// clamped; below, a perspective weight is at most 2^-17 below 0.
bool needs_clamped_weights(const TriangleSetup& t, double step) {
    const float lo = std::min({t.inv_w[0], t.inv_w[1], t.inv_w[2]});
    const float hi = std::max({t.inv_w[0], t.inv_w[1], t.inv_w[2]});
    return !(double(hi) * (1.0 + 4.0 * step) <= 32.0 * double(lo));
}

// floor(a / 2^kSubpixelBits): an arithmetic shift, which rounds down.
int64_t floor_subpixels(int64_t a) { return a >> kSubpixelBits; }

// Top-left rule in a y-down window with the interior on the positive side:
// a left edge has the interior to its right (edge normal x > 0), a top edge
// is horizontal with the interior below it.
bool top_left(int64_t dx, int64_t dy) { return dy < 0 || (dy == 0 && dx > 0); }

EdgeFunction make_edge(int64_t x0, int64_t y0, int64_t x1, int64_t y1) {
    const int64_t dx = x1 - x0, dy = y1 - y0;
    return {int32_t(x0), int32_t(y0), int32_t(dx), int32_t(dy), top_left(dx, dy) ? 0 : -1};
}

// 2^ilogb(w) for w > 0: w with its mantissa cleared, when w is normal.
double power_of_two_below(double w) {
    const uint64_t bits = std::bit_cast<uint64_t>(w) & 0x7FF0000000000000u;
    return bits ? std::bit_cast<double>(bits) : std::ldexp(1.0, std::ilogb(w));
}

// Pixels px whose centre px * 256 + 128 lies within [lo, hi] sub-pixels.
void pixel_range(int64_t lo, int64_t hi, int& first, int& last) {
    const int64_t half = kSubpixelOne / 2;
    first = int(floor_subpixels(lo - half + kSubpixelOne - 1));
    last = int(floor_subpixels(hi - half));
}

}  // namespace

double Viewport::guard_ndc() const {
    // Window x = (ndc + 1) * width / 2 must stay within +-kGuardBandPixels.
    const double half = std::max(width, height) * 0.5;
    return (kGuardBandPixels - 2.0 * half) / half;
}

namespace {

// The window position of clip-space point `clip`, whose 1/w is `inv_w`.
glm::dvec2 window_at(const glm::dvec4& clip, double inv_w, const Viewport& viewport) {
    return {(clip.x * inv_w + 1.0) * 0.5 * viewport.width,
            (1.0 - clip.y * inv_w) * 0.5 * viewport.height};
}

}  // namespace

glm::dvec2 to_window(const glm::dvec4& clip, const Viewport& viewport) {
    return window_at(clip, 1.0 / clip.w, viewport);
}

bool project_vertex(const glm::dvec4& clip, const Viewport& viewport, WindowVertex& out) {
    if (!(clip.w > 0.0)) return false;
    const int bits = std::clamp(viewport.subpixel_bits, 1, kSubpixelBits);
    const double inv_w = 1.0 / clip.w;
    const glm::dvec2 p = window_at(clip, inv_w, viewport);
    out.x = int32_t(snap(p.x, bits));
    out.y = int32_t(snap(p.y, bits) - int64_t(viewport.first_row) * kSubpixelOne);
    out.z = float(clip.z / clip.w);
    out.w = clip.w;
    out.inv_w = inv_w;
    return true;
}

SetupResult setup_triangle(const SetupVertex v[3], const Viewport& viewport,
                           const CullState& cull, TriangleSetup& out, int orientation) {
    WindowVertex p[3];
    for (int i = 0; i < 3; ++i)
        if (!project_vertex(v[i].clip, viewport, p[i])) return SetupResult::degenerate;
    const WindowVertex* const pv[3] = {&p[0], &p[1], &p[2]};
    const float* const varyings[3] = {v[0].varyings, v[1].varyings, v[2].varyings};
    return setup_triangle(pv, varyings, viewport, cull, out, orientation);
}

SetupResult setup_triangle(const WindowVertex* const v[3], const float* const varyings[3],
                           const Viewport& viewport, const CullState& cull, TriangleSetup& out,
                           int orientation) {
    const int64_t area2 = window_area2(v);
    const SetupResult r = facing_result(area2, cull, orientation);
    return r == SetupResult::ok ? setup_kept_triangle(v, varyings, area2, viewport, cull, out) : r;
}

SetupResult setup_kept_triangle(const WindowVertex* const v[3], const float* const varyings[3],
                                int64_t area2, const Viewport& viewport, const CullState& cull,
                                TriangleSetup& out) {
    // Orient so the interior is on the positive side of every edge: the
    // corners in the order 0, 1, 2, or 0, 2, 1 when the area is negative.
    // (Chosen once, so that every corner below is a constant index.)
    const int second = area2 < 0 ? 2 : 1, third = 3 - second;
    const WindowVertex* const c[3] = {v[0], v[second], v[third]};
    for (int k = 0; k < 3; ++k)
        out.edge[k] = make_edge(c[k]->x, c[k]->y, c[(k + 1) % 3]->x, c[(k + 1) % 3]->y);
    out.area2 = area2 < 0 ? -area2 : area2;
    out.front_facing = front_facing(area2, cull);
    out.inv_area2 = 1.0 / double(out.area2);
    int64_t span = 0;  // the largest |dx| + |dy| of an edge
    for (int k = 0; k < 3; ++k) {
        const EdgeFunction& e = out.edge[k];
        span = std::max(span, std::abs(int64_t(e.dx)) + std::abs(int64_t(e.dy)));
        // Edge k gives the weight of vertex k + 2; it grows by -dy per
        // sub-pixel in x and by dx in y.
        out.bary_dx[(k + 2) % 3] = float(double(-e.dy * kSubpixelOne) * out.inv_area2);
        out.bary_dy[(k + 2) % 3] = float(double(e.dx * kSubpixelOne) * out.inv_area2);
    }
    out.narrow = span < kNarrowEdgeSpan;
    const float* const corner_varyings[3] = {varyings[0], varyings[second], varyings[third]};
    set_corners(c, corner_varyings, span, out);

    // Samples lie less than half a pixel from the centre.
    const int64_t reach = viewport.samples > 1 ? kSubpixelOne / 2 : 0;
    const int64_t X[3] = {v[0]->x, v[1]->x, v[2]->x}, Y[3] = {v[0]->y, v[1]->y, v[2]->y};
    pixel_range(std::min({X[0], X[1], X[2]}) - reach, std::max({X[0], X[1], X[2]}) + reach,
                out.x0, out.x1);
    pixel_range(std::min({Y[0], Y[1], Y[2]}) - reach, std::max({Y[0], Y[1], Y[2]}) + reach,
                out.y0, out.y1);
    out.x0 = std::max(out.x0, 0);
    out.y0 = std::max(out.y0, 0);
    out.x1 = std::min(out.x1, viewport.width - 1);
    out.y1 = std::min(out.y1, viewport.target_rows() - 1);
    if (out.x0 > out.x1 || out.y0 > out.y1) return SetupResult::no_pixels;
    if (viewport.samples == 1 && misses_small_box(out)) return SetupResult::no_pixels;
    return SetupResult::ok;
}

bool misses_small_box(const TriangleSetup& t) {
    if (t.x1 - t.x0 > 1 || t.y1 - t.y0 > 1) return false;
    const int64_t half = kSubpixelOne / 2;
    for (int y = t.y0; y <= t.y1; ++y)
        for (int x = t.x0; x <= t.x1; ++x) {
            bool inside = true;
            for (const EdgeFunction& e : t.edge)
                inside &= e.at(x * kSubpixelOne + half, y * kSubpixelOne + half) + e.bias >= 0;
            if (inside) return false;
        }
    return true;
}

void set_corners(const WindowVertex* const c[3], const float* const varyings[3], int64_t span,
                 TriangleSetup& out) {
    // 1/w times a power of two that brings the largest to (0.5, 1], and at
    // least 2^-64: perspective weights need only the ratios, and 1/w alone
    // overflows float for w < 2^-128 (and underflows past 2^128). With the
    // floor, lane_weights' sum of weight times 1/w is at least about 2^-66
    // (some weight is at least about 1/3), so its reciprocal is finite; a
    // vertex whose 1/w is below 2^-64 of the largest weighs nothing a float
    // shows.
    const double scale = power_of_two_below(std::min({c[0]->w, c[1]->w, c[2]->w}));
    for (int k = 0; k < 3; ++k) {
        out.z[k] = c[k]->z;
        out.inv_w[k] = std::max(float(c[k]->inv_w * scale), kMinInverseW);
        out.varyings[k] = varyings[k];
    }
    out.clamp_weights = needs_clamped_weights(out, double(span * kSubpixelOne) * out.inv_area2);
}

void add_depth_bias(TriangleSetup& t, double constant, double slope) {
    // The depth's plane: z = z0 + w1 (z1 - z0) + w2 (z2 - z0), the weights
    // edge[2] and edge[0] over area2 (edge k weighs vertex k + 2), each
    // growing by -dy per sub-pixel in x and by dx in y.
    const double dz1 = double(t.z[1]) - t.z[0], dz2 = double(t.z[2]) - t.z[0];
    const double per_pixel = double(kSubpixelOne) / double(t.area2);
    const double dzdx = (-double(t.edge[2].dy) * dz1 - double(t.edge[0].dy) * dz2) * per_pixel;
    const double dzdy = (double(t.edge[2].dx) * dz1 + double(t.edge[0].dx) * dz2) * per_pixel;
    const double m = std::max(std::abs(dzdx), std::abs(dzdy));
    const float largest = std::max({std::abs(t.z[0]), std::abs(t.z[1]), std::abs(t.z[2])});
    int e = 0;  // largest = f 2^e, f in [0.5, 1): its float exponent is e - 1
    std::frexp(largest > 0.0f ? largest : std::numeric_limits<float>::min(), &e);
    const double r = std::ldexp(1.0, e - 1 - 23);
    const double bias = constant * r + slope * m;
    if (!std::isfinite(bias)) return;
    // Held inside 0..1 (unless already at an end): a surface pushed back
    // onto the far depth would be taken for the sky's background.
    constexpr double kLow = std::numeric_limits<float>::min(), kHigh = 1.0 - 0x1p-24;
    for (float& z : t.z)
        z = float(std::clamp(double(z) + bias, std::min(double(z), kLow), std::max(double(z), kHigh)));
}

}  // namespace facet
