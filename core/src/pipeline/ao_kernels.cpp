// The AO pass's row kernels (ao.hpp): occlusion, blur and upsample, kWidth
// texels of a row at a time; one of the per-ISA kernel sources.
#include "pipeline/ao_frame.hpp"
#include "base/simd.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

namespace facet::FACET_KERNEL_NS {

using simd::Float;
using simd::Int;
using simd::kWidth;

namespace {

Float select(const Int& m, const Float& a, const Float& b) { return m ? a : b; }
Int select(const Int& m, const Int& a, const Int& b) { return m ? a : b; }

// Lanes x0 .. x0 + kWidth - 1 of a row of `width` floats; lanes past the
// end read `otherwise`.
Float load_row(const float* row, int x0, int width, float otherwise) {
    if (x0 + kWidth <= width) return simd::load<Float>(row + x0);
    Float v = Float{} + otherwise;
    for (int i = 0; x0 + i < width; ++i) v[i] = row[x0 + i];
    return v;
}

void store_row(float* row, int x0, int width, const Float& v) {
    if (x0 + kWidth <= width) return simd::store(row + x0, v);
    for (int i = 0; x0 + i < width; ++i) row[x0 + i] = v[i];
}

// Truncated to integers; every lane must be in int range.
Int to_int(const Float& v) { return __builtin_convertvector(v, Int); }

// The target pixel column of AO texel columns i, and the pixel row of AO
// row j: texel i stands for pixel i * scale, the last within the target.
Int pixel_column(const AoFrame& f, const Int& i) {
    const Int px = i * f.scale;
    return px < f.target_width - 1 ? px : Int{} + (f.target_width - 1);
}
int pixel_row(const AoFrame& f, int j) { return std::min(j * f.scale, f.target_height - 1); }

// The view x of texels in pixel columns px whose view z is z, and the view
// y of texels in pixel row py (AoFrame::x0).
Float view_x(const AoFrame& f, const Int& px, const Float& z) {
    const Float a = f.x0 + f.x1 * simd::to_float(px);
    return f.perspective ? a * z : a;
}
Float view_y(const AoFrame& f, int py, const Float& z) {
    const float a = f.y0 + f.y1 * float(py);
    return f.perspective ? a * z : Float{} + a;
}

// 1 / (1 + 2500 r^2): the blur's and the upsample's weight for a relative
// depth difference r: 1/2 at 2%, about 1/10 at 6%.
Float depth_weight(const Float& relative) { return 1.0f / (1.0f + 2500.0f * relative * relative); }

// Lanes 0, 0, 1, 1, 2, 2, ... of v, and lanes 1, 1, 2, 2, 3, 3, ...: the
// texels of pixels 2 i and 2 i + 1 at half size, and of their right
// neighbours.
Float spread_pairs(const Float& v) {
#if FACET_SIMD_WIDTH == 16
    return __builtin_shufflevector(v, v, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7);
#elif FACET_SIMD_WIDTH == 8
    return __builtin_shufflevector(v, v, 0, 0, 1, 1, 2, 2, 3, 3);
#else
    return __builtin_shufflevector(v, v, 0, 0, 1, 1);
#endif
}
Float spread_next(const Float& v) {
#if FACET_SIMD_WIDTH == 16
    return __builtin_shufflevector(v, v, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8);
#elif FACET_SIMD_WIDTH == 8
    return __builtin_shufflevector(v, v, 1, 1, 2, 2, 3, 3, 4, 4);
#else
    return __builtin_shufflevector(v, v, 1, 1, 2, 2);
#endif
}

// Lanes 0, 2, 4, ... of a followed by b.
Float even_lanes(const Float& a, const Float& b) {
#if FACET_SIMD_WIDTH == 16
    return __builtin_shufflevector(a, b, 0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
#elif FACET_SIMD_WIDTH == 8
    return __builtin_shufflevector(a, b, 0, 2, 4, 6, 8, 10, 12, 14);
#else
    return __builtin_shufflevector(a, b, 0, 2, 4, 6);
#endif
}

// Lanes 0, 1, 2, 3, 0, 1, 2, 3, ...: four floats from p, repeated.
Float repeat4(const float* p) {
    using Float4 = float __attribute__((vector_size(16)));
    Float4 v;
    std::memcpy(&v, p, sizeof v);
#if FACET_SIMD_WIDTH == 16
    return __builtin_shufflevector(v, v, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3);
#elif FACET_SIMD_WIDTH == 8
    return __builtin_shufflevector(v, v, 0, 1, 2, 3, 0, 1, 2, 3);
#else
    return v;
#endif
}

// kSteps steps of up to 2^27 from a start within a 16384-texel grid (16.16
// fixed point) stay in int range.
static_assert(AoFrame::kSteps * 134217728.0 + 16384.0 * 65536.0 < 2147483648.0);

}  // namespace

// View z and keys of AO rows [first, first + count): each texel's target
// pixel (i * scale, j * scale) unprojected from the pre-pass depth through
// the inverse projection's rows; 0 where nothing was drawn.
void ao_position_rows(const AoFrame& f, int first, int count) {
    Int lane;
    for (int i = 0; i < kWidth; ++i) lane[i] = i;
    const float to_ndc_x = 2.0f / float(f.target_width), to_ndc_y = 2.0f / float(f.target_height);
    for (int j = first; j < first + count; ++j) {
        const int py = pixel_row(f, j);
        const float* depth = f.target_depth + size_t(py) * size_t(f.target_stride);
        const float ndc_y = 1.0f - (float(py) + 0.5f) * to_ndc_y;
        const size_t row = size_t(j) * size_t(f.width);
        for (int i0 = 0; i0 < f.width; i0 += kWidth) {
            const Int px = pixel_column(f, lane + i0);
            // At half size, the even pixels of two loads where every one is
            // within the row (no column clamped); else a gather.
            const Float d = f.scale == 2 && 2 * (i0 + kWidth) <= f.target_width
                                ? even_lanes(simd::load<Float>(depth + 2 * i0),
                                             simd::load<Float>(depth + 2 * i0 + kWidth))
                                : simd::gather(depth, px);
            const Int surface = d != f.background;
            const Float ndc_x = (simd::to_float(px) + 0.5f) * to_ndc_x - 1.0f;
            const auto dot = [&](const glm::vec4& r) {
                return (r.x * ndc_x + (r.y * ndc_y + r.w)) + r.z * d;
            };
            const Float z = select(surface, dot(f.z_row) / dot(f.w_row), Float{});
            store_row(f.z + row, i0, f.width, z);
            const Float inv_depth = -1.0f / select(surface, z, Float{} - 1.0f);
            store_row(f.key + size_t(j) * size_t(f.key_stride), i0, f.width,
                      f.perspective ? select(surface, inv_depth, Float{}) : z);
        }
    }
}

namespace {

// The normals of texels i0 .. i0 + kWidth - 1 of AO row j, not yet of unit
// length (unit_normals): the cross product of the position's steps to a
// neighbour along each axis, taking the neighbour nearer in depth (the one
// after it on a tie), turned towards the camera. A texel with a neighbour
// on one axis only faces the camera as nearly as a normal to that step can;
// one with none faces the camera; one where nothing was drawn gets +Z.
void normal_directions(const AoFrame& f, int i0, int j, Float& nx_out, Float& ny_out,
                       Float& nz_out) {
    Int lane;
    for (int i = 0; i < kWidth; ++i) lane[i] = i;
    struct Step {
        Int found;
        Float x, y, z;
    };
    // The step from p (lanes of texel k on, in pixel columns px and row py)
    // to the neighbours `apart` texels before and after, where `after` and
    // `before` say they exist: along a row (apart 1), in columns a and b
    // and row py; else in p's columns and rows a and b. z is padded by a row
    // and a vector on either side, so the loads stay in its storage; what
    // they read past the grid is masked.
    const auto step = [&](size_t k, ptrdiff_t apart, Int after, Int before, const Int& a_column,
                          const Int& b_column, int a_row, int b_row, const Float& px,
                          const Float& py, const Float& pz) {
        const Float az = simd::load<Float>(f.z + k + apart),
                    ax = view_x(f, a_column, az), ay = view_y(f, a_row, az);
        const Float bz = simd::load<Float>(f.z + k - apart),
                    bx = view_x(f, b_column, bz), by = view_y(f, b_row, bz);
        after &= az != 0.0f;
        before &= bz != 0.0f;
        const Float da = simd::abs(az - pz), db = simd::abs(bz - pz);
        const Int take_before = before & (~after | (db < da));
        return Step{after | before, select(take_before, px - bx, ax - px),
                    select(take_before, py - by, ay - py), select(take_before, pz - bz, az - pz)};
    };
    const Int i = lane + i0;
    const Int in_row = i < f.width;
    const size_t k = size_t(j) * size_t(f.width) + size_t(i0);
    const Int column = pixel_column(f, i);
    const int py_row = pixel_row(f, j);
    const Float pz = simd::load<Float>(f.z + k);
    const Float px = view_x(f, column, pz), py = view_y(f, py_row, pz);
    const Int all = Int{} - 1;
    const Step u = step(k, 1, in_row & (i + 1 < f.width), in_row & (i > 0),
                        pixel_column(f, i + 1), pixel_column(f, i - 1), py_row, py_row,
                        px, py, pz);
    const Step v = step(k, ptrdiff_t(f.width), in_row & (j + 1 < f.height ? all : Int{}),
                        in_row & (j > 0 ? all : Int{}), column, column,
                        pixel_row(f, j + 1), pixel_row(f, j - 1), px, py, pz);
    const Float cx = u.y * v.z - u.z * v.y, cy = u.z * v.x - u.x * v.z,
                cz = u.x * v.y - u.y * v.x;
    const Int crossed = u.found & v.found & ((cx * cx + cy * cy + cz * cz) > 0.0f);
    // Towards the eye: along -p in perspective, +Z in orthographic.
    const Float ex = f.perspective ? -px : Float{}, ey = f.perspective ? -py : Float{};
    const Float ez = f.perspective ? -pz : Float{} + 1.0f;
    const Int away = (cx * ex + cy * ey + cz * ez) < 0.0f;
    Float nx = select(away, -cx, cx), ny = select(away, -cy, cy), nz = select(away, -cz, cz);
    const Int surface = in_row & (pz != 0.0f);
    if (simd::bits(surface & ~crossed)) {  // rarely (at edges): not every texel's steps cross
        // With a step t on one axis only (or two that cross at nothing):
        // the eye's direction less its part along t.
        const Float tx = select(u.found, u.x, v.x), ty = select(u.found, u.y, v.y),
                    tz = select(u.found, u.z, v.z);
        const Float tt = select(u.found | v.found, tx * tx + ty * ty + tz * tz, Float{});
        const Float along =
            (ex * tx + ey * ty + ez * tz) / select(tt > 0.0f, tt, Float{} + 1.0f);
        const Float a = select(tt > 0.0f, along, Float{});
        nx = select(crossed, nx, ex - a * tx);
        ny = select(crossed, ny, ey - a * ty);
        nz = select(crossed, nz, ez - a * tz);
    }
    const Int none = (nx * nx + ny * ny + nz * nz) == 0.0f;  // t along the eye's ray
    nx = select(none, ex, nx), ny = select(none, ey, ny), nz = select(none, ez, nz);
    nx_out = select(surface, nx, Float{});
    ny_out = select(surface, ny, Float{});
    nz_out = select(surface, nz, Float{} + 1.0f);
}

// normal_directions' normals of unit length (none is 0).
void unit_normals(Float& nx, Float& ny, Float& nz) {
    const Float inv = 1.0f / simd::sqrt(nx * nx + ny * ny + nz * nz);
    nx *= inv, ny *= inv, nz *= inv;
}

// The unit normals of texels i0 .. i0 + kWidth - 1 of AO row j.
void texel_normals(const AoFrame& f, int i0, int j, Float& nx, Float& ny, Float& nz) {
    normal_directions(f, i0, j, nx, ny, nz);
    unit_normals(nx, ny, nz);
}

}  // namespace

// Normals of AO rows [first, first + count) (texel_normals): what the
// occlusion works out for itself as it starts each texel's marches, written
// out.
void ao_normal_rows(const AoFrame& f, int first, int count) {
    for (int j = first; j < first + count; ++j) {
        const size_t row = size_t(j) * size_t(f.width);
        for (int i0 = 0; i0 < f.width; i0 += kWidth) {
            Float nx, ny, nz;
            texel_normals(f, i0, j, nx, ny, nz);
            store_row(f.nx + row, i0, f.width, nx);
            store_row(f.ny + row, i0, f.width, ny);
            store_row(f.nz + row, i0, f.width, nz);
        }
    }
}

namespace {

// One texel vector's march inputs (Marcher): where it starts, its tangent
// plane as a key over the grid, and its clip-space start and frame, from
// which each direction's segment is projected.
struct MarchStart {
    Int x, surface;
    int y;
    Int sx0, sy0;  // 16.16 fixed point from texel (x, y)'s corner
    Float k0;                               // the start's key
    Float plane_key, plane_dx, plane_dy;    // the tangent plane's key at x, per texel
    Float cpx, cpy, cpw, nx0, ny0;          // clip start (cpw: z if orthographic), its ndc
    Float px, py, pz;                       // the view position
    Float nx, ny, nz;                       // the normal
    Float tcx, tcy, tcw, bcx, bcy, bcw, ncx, ncy, ncw;  // the frame in clip space, reach long
};

// One direction's march across a texel vector, on the grid in fixed point.
struct MarchStep {
    Int dsx, dsy, ahead;
    Float dk;      // the key's change per step
    bool bordered; // every lane's march stays within the key's border
};

// The marches of ao_occlusion_rows for one projection: a vector's work in
// stages, its start (begin, orient, frame), then each direction's step
// (aim), then the march. Texel i stands for target pixel i * scale, whose
// centre is at i * scale + 1/2: target x X falls to texel
// floor((X + (scale - 1) / 2) / scale).
template <bool Perspective>
class Marcher {
public:
    static constexpr float kFixed = 65536.0f;  // screen positions in 16.16 fixed point
    static constexpr float kStep = 1.0f / float(AoFrame::kSteps);

    Marcher(const AoFrame& frame, int x_end)
        : f(frame),
          x_end(x_end),
          P(frame.projection),
          sx_scale(0.5f * float(frame.target_width) / float(frame.scale)),
          sy_scale(0.5f * float(frame.target_height) / float(frame.scale)),
          offset(0.5f * float(frame.scale - 1) / float(frame.scale)),
          // How far ndc moves per texel, over P00 and P11: 2 scale / W
          // across, -2 scale / H down (the tangent planes' slopes).
          per_x(2.0f * float(frame.scale) / (P[0][0] * float(frame.target_width))),
          per_y(-2.0f * float(frame.scale) / (P[1][1] * float(frame.target_height))),
          // An occluder stands at least tol in front of the march and of
          // the tangent plane (float error and curvature), and less than
          // reach.
          tol(0.005f * frame.radius),
          reach(frame.radius),
          // Where the key's stride fits in 16 bits, as a march's rows from
          // its start do, their product is simd::mul_short's.
          short_rows(frame.key_stride <= 32767) {
        for (int i = 0; i < kWidth; ++i) lane[i] = i;
    }

    // Texels x0 .. x0 + kWidth - 1 of row y: where their marches start.
    void begin(MarchStart& t, int x0, int y) const {
        const size_t row = size_t(y) * size_t(f.width);
        t.x = lane + x0;
        t.y = y;
        const Float pz = select(t.x < x_end, load_row(f.z + row, x0, f.width, 0.0f), Float{});
        t.surface = pz != 0.0f;  // background texels stay visible
        if (!simd::bits(t.surface)) return;
        const Float px = view_x(f, pixel_column(f, t.x), pz), py = view_y(f, pixel_row(f, y), pz);
        t.px = px, t.py = py, t.pz = pz;
        normal_directions(f, x0, y, t.nx, t.ny, t.nz);  // of unit length in orient()
        start_on_grid(t, y);
    }

    // Start t's unit normal and its tangent plane, as a key over the grid
    // (the key is affine in screen position on a plane): only what stands
    // above it can block a direction of the hemisphere, and a lookup up to
    // half a texel from the march then never takes the surface itself, seen
    // at a grazing angle, for an occluder. Along the pixel rays
    // u = ((ndc + P20) / P00, (ndc + P21) / P11, -1) of a perspective
    // projection the plane n . p = d has key (n . u) / d; an orthographic
    // one's has z = (d - nx x - ny y) / nz; per_x and per_y turn their slopes
    // into steps of a texel. A plane seen edge on blocks nothing: its key is
    // one below every march's (0 for keys 1 / w, which are positive; the
    // lowest float for z).
    void orient(MarchStart& t) const {
        unit_normals(t.nx, t.ny, t.nz);
        const Float nx = t.nx, ny = t.ny, nz = t.nz, px = t.px, py = t.py, pz = t.pz;
        constexpr float kLowest = std::numeric_limits<float>::lowest();
        if constexpr (Perspective) {
            const Float d = nx * px + ny * py + nz * pz;  // < 0: n faces the eye
            const Int tilted = t.surface & (d < 1e-6f * pz);
            const Float inv_d = 1.0f / select(tilted, d, Float{} - 1.0f);
            t.plane_key = select(tilted, t.k0, Float{});  // the texel's own key: w = -z
            t.plane_dx = select(tilted, nx * inv_d * per_x, Float{});
            t.plane_dy = select(tilted, ny * inv_d * per_y, Float{});
        } else {
            const Int tilted = t.surface & (nz > 1e-6f);
            const Float inv_nz = 1.0f / select(tilted, nz, Float{} + 1.0f);
            t.plane_key = select(tilted, pz, Float{} + kLowest);
            t.plane_dx = select(tilted, -nx * inv_nz * per_x, Float{});
            t.plane_dy = select(tilted, -ny * inv_nz * per_y, Float{});
        }
    }

    // The frame of start t in clip space, reach long: a direction's end is
    // the start plus a mix of these, with the direction's weights. The
    // tangent t is perpendicular to n (n x X, or n x Y near X), and b = n x t.
    void frame(MarchStart& t) const {
        const Float nx = t.nx, ny = t.ny, nz = t.nz;
        const Int near_x = (nx < -0.9f) | (nx > 0.9f);
        Float tx = select(near_x, -nz, Float{}), ty = select(near_x, Float{}, nz),
              tz = select(near_x, nx, -ny);
        const Float inv_t = 1.0f / simd::sqrt(tx * tx + ty * ty + tz * tz);
        tx *= inv_t, ty *= inv_t, tz *= inv_t;
        const Float bx = ny * tz - nz * ty, by = nz * tx - nx * tz, bz = nx * ty - ny * tx;
        t.tcx = clip(tx, ty, tz, 0), t.tcy = clip(tx, ty, tz, 1), t.tcw = clip(tx, ty, tz, 3);
        t.bcx = clip(bx, by, bz, 0), t.bcy = clip(bx, by, bz, 1), t.bcw = clip(bx, by, bz, 3);
        t.ncx = clip(nx, ny, nz, 0), t.ncy = clip(nx, ny, nz, 1), t.ncw = clip(nx, ny, nz, 3);
    }

    // Texel (x, y) turns its directions by (x & 3) * 4 + (y & 3), and a
    // vector starts at a multiple of 4: lane i takes turn i & 3 of its
    // row's four. Direction k of each lane of row y.
    void direction(int k, int y, Float& hx, Float& hy, Float& hz) const {
        const float* turns = f.directions + size_t(((y & 3) * f.samples + k) * 3) * 4;
        hx = repeat4(turns), hy = repeat4(turns + 4), hz = repeat4(turns + 8);
    }

    // Direction h's step from start t: the direction's end, `reach` away,
    // projected once; on the screen the march is a straight segment,
    // stepped evenly, along which the key is linear too.
    void aim(MarchStep& m, const MarchStart& t, const Float& hx, const Float& hy,
             const Float& hz) const {
        const Float cex = t.cpx + (t.tcx * hx + t.bcx * hy + t.ncx * hz);
        const Float cey = t.cpy + (t.tcy * hx + t.bcy * hy + t.ncy * hz);
        const Float cew = t.cpw + (t.tcw * hx + t.bcw * hy + t.ncw * hz);
        m.ahead = t.surface;
        Float k1 = cew, nx1 = cex, ny1 = cey;
        if constexpr (Perspective) {
            m.ahead &= cew > 0.0f;  // a march behind the camera sees nothing
            k1 = 1.0f / select(m.ahead, cew, Float{} + 1.0f);
            nx1 = cex * k1, ny1 = cey * k1;
        }
        m.dsx = fixed_step((nx1 - t.nx0) * (sx_scale * kStep * kFixed), m.ahead);
        m.dsy = fixed_step((t.ny0 - ny1) * (sy_scale * kStep * kFixed), m.ahead);
        m.dk = (k1 - t.k0) * kStep;
        // A march is straight and starts on the grid: it stays within the
        // border if its end does.
        const Int ex = t.x + ((t.sx0 + AoFrame::kSteps * m.dsx) >> 16);
        const Int ey = ((t.sy0 + AoFrame::kSteps * m.dsy) >> 16) + t.y;
        constexpr int border = AoFrame::kBorder;
        m.bordered = !simd::bits(t.surface & ((ex < -border) | (ex >= f.width + border) |
                                              (ey < -border) | (ey >= f.height + border)));
    }

    // Whether the march is blocked: a step reads a surface nearer than the
    // march by tol .. reach (in view units, compared on keys without a
    // division) and above the tangent plane by tol. For keys 1 / w the two
    // tests by tol read there - m > tol there m, for m the march's key and
    // for m the plane's, which is the one test for the larger m; the reach
    // test, there - here < reach there here, is there (1 - reach here) < here.
    template <bool Bordered>
    Int march(const MarchStart& t, const MarchStep& m, int y) const {
        Int sx = t.sx0, sy = t.sy0;
        Int blocked = Int{};
        const Int start = y * f.key_stride + t.x;  // the start texel's key
        for (int s = 1; s <= AoFrame::kSteps; ++s) {
            sx += m.dsx, sy += m.dsy;
            // Texels from the start: at most kSteps 2^11 (fixed_step), so a
            // row's offset is simd::mul_short's where the stride fits.
            Int dx = sx >> 16, dy = sy >> 16;
            // Off the grid, the border (key 0, which blocks nothing): read as
            // it is by a bordered march, else clamped to its first texel.
            if constexpr (!Bordered) {
                const Int ix = t.x + dx, iy = dy + y;
                dx = (ix < -1 ? Int{} - 1 : ix > f.width ? Int{} + f.width : ix) - t.x;
                dy = (iy < -1 ? Int{} - 1 : iy > f.height ? Int{} + f.height : iy) - y;
            }
            const Int row = short_rows ? simd::mul_short(dy, f.key_stride) : dy * f.key_stride;
            const Float there = simd::gather(f.key, start + row + dx);
            const Float here = t.k0 + float(s) * m.dk;  // the march's key
            const Float plane = t.plane_key + t.plane_dx * simd::to_float(dx) +
                                t.plane_dy * simd::to_float(dy);
            const Float higher = simd::max(plane, here);
            if constexpr (Perspective) {
                blocked |= (there - tol * higher * there > higher) &
                           (there * (1.0f - reach * here) < here);
            } else {
                blocked |= (there != 0.0f) & (there - higher > tol) & (there - here < reach);
            }
        }
        return blocked & m.ahead;
    }

    const AoFrame& f;
    const int x_end;

private:
    // The march starts at the surface point: its clip position (clip
    // positions are linear along a ray), through the terms of P that are
    // not 0 (AoFrame::set_pixel_rays: x from x and z, y from y and z, and in
    // perspective w from z alone; orthographic x and y from x and y, moved),
    // and where it falls on the grid.
    void start_on_grid(MarchStart& t, int y) const {
        const Float px = t.px, py = t.py, pz = t.pz;
        if constexpr (Perspective) {
            t.cpx = P[0][0] * px + P[2][0] * pz;
            t.cpy = P[1][1] * py + P[2][1] * pz;
            t.cpw = P[2][3] * pz;
        } else {
            t.cpx = P[0][0] * px + P[3][0];
            t.cpy = P[1][1] * py + P[3][1];
            t.cpw = pz;
        }
        t.k0 = Perspective ? 1.0f / t.cpw : pz;
        // Where it falls on the grid, as x_ndc = cx * k (k = 1 / w, or 1).
        t.nx0 = Perspective ? t.cpx * t.k0 : t.cpx;
        t.ny0 = Perspective ? t.cpy * t.k0 : t.cpy;
        // From the texel's own corner (about half a texel from it: the
        // position less the index is exact there, so the start is the one
        // counted from the grid's corner, less the index times 2^16, which
        // on a grid 32768 texels wide would not fit 32 bits). Lanes with no
        // surface start at their own texel, which every path can read.
        t.sx0 = select(t.surface,
                       to_int((((t.nx0 + 1.0f) * sx_scale + offset) - simd::to_float(t.x)) * kFixed),
                       Int{});
        t.sy0 = select(t.surface,
                       to_int((((1.0f - t.ny0) * sy_scale + offset) - float(y)) * kFixed), Int{});
    }

    // Vector (vx, vy, vz) of the frame in clip space, reach long: its row c
    // (0 x, 1 y, 3 w) through P's terms that are not 0, as for the start.
    // An orthographic march's key is z, so its third row is the vector's z.
    Float clip(const Float& vx, const Float& vy, const Float& vz, int c) const {
        if constexpr (Perspective) {
            if (c == 0) return reach * (P[0][0] * vx + P[2][0] * vz);
            if (c == 1) return reach * (P[1][1] * vy + P[2][1] * vz);
            return reach * (P[2][3] * vz);
        } else {
            return c == 0 ? reach * (P[0][0] * vx) : c == 1 ? reach * (P[1][1] * vy) : reach * vz;
        }
    }

    // A step in fixed point, within +-2^27 so that kSteps of them from a
    // start (within a texel of its texel's corner) stay in int range (a
    // longer one leaves the grid at its first step either way); none for
    // NaN or where the march does not go ahead.
    static Int fixed_step(const Float& v, const Int& ahead) {
        const Float c = simd::min(simd::max(v, Float{} - 134217728.0f), Float{} + 134217728.0f);
        return to_int(select(ahead & (v == v), c, Float{}));
    }

    const glm::mat4& P;
    const float sx_scale, sy_scale, offset, per_x, per_y, tol, reach;
    const bool short_rows;
    Int lane;
};

// The groups side by side at (x0, y0) whose marches run together. A group
// is 16 texels of each of 4 rows, whatever the path, as kAcross vectors of
// kWidth neighbours per row, so that every path takes the same groups as
// open. So that each stage has at least 8 vectors to overlap, there are
// kGroups of them: one group of 8 vectors (AVX2) or 16 (SSE2), two of 4
// (AVX-512; the AO pass on one thread, fastest of 40: 9.8-10.0 -> 9.0-9.3
// ms; two groups of 8 on AVX2 were no faster).
//
// All but the marches are chains of dependent operations (square roots,
// divisions); each stage done for every vector in hand and a batch of
// directions before the next, they overlap, and no march waits on them
// (the AO pass on one thread, fastest of 40: 10.7-10.8 -> 9.6-10.1 ms, AVX2).
template <bool Perspective>
class GroupMarches {
public:
    static constexpr int kGroupWidth = AoFrame::kGroupWidth, kGroupRows = AoFrame::kGroupRows;
    static constexpr int kAcross = kGroupWidth / kWidth, kGroupVectors = kAcross * kGroupRows;
    static constexpr int kGroups = std::max(8 / kGroupVectors, 1);
    static constexpr int kVectors = kGroups * kGroupVectors, kBatch = 8;

    GroupMarches(const Marcher<Perspective>& marcher, int x0, int y0, int y_end)
        : m_(marcher), f_(marcher.f), x0_(x0), y0_(y0), y_end_(y_end) {}

    // The visibility of the groups' texels, into AoFrame::raw.
    void run() {
        start_all();
        // The most grazing direction first (the last: the directions'
        // elevations fall with their index); where it is open for every
        // texel of the group, the group is taken as open. A grazing
        // direction is the first a nearby occluder blocks; only an overhang
        // within reach could block a steeper one alone. The group's 16
        // texels of a row and 4 rows turn the direction set all 16 ways:
        // between them they look for an occluder all round.
        for (int i0 = 0; i0 < f_.samples && any_active();) {
            const int batch = std::min(i0 == 0 ? 1 : kBatch, f_.samples - i0);
            aim_batch(i0, batch);
            march_batch(batch);
            i0 += batch;
            if (i0 == 1 && i0 < f_.samples) settle_open_groups();
        }
        store();
    }

private:
    // Vector v: of group v / kGroupVectors (from x0 + that kGroupWidth),
    // row y0 + (v % kGroupVectors) / kAcross, texels from the group's first
    // plus (v % kAcross) kWidth.
    static int group_of(int v) { return v / kGroupVectors; }
    int row_of(int v) const { return y0_ + v % kGroupVectors / kAcross; }
    int column_of(int v) const { return x0_ + group_of(v) * kGroupWidth + (v % kAcross) * kWidth; }
    bool marching(int v) const { return active_[group_of(v)] && simd::bits(start_[v].surface); }
    bool any_active() const {
        bool any = false;
        for (bool a : active_) any |= a;
        return any;
    }
    // Sample i's direction: the last first, then the rest in order.
    int direction(int i) const { return i < 1 ? f_.samples - 1 : i - 1; }

    // Each stage of the starts for every vector before the next.
    void start_all() {
        for (bool& a : active_) a = false;
        for (int v = 0; v < kVectors; ++v) {
            start_[v].surface = Int{};
            open_[v] = Float{};
            if (row_of(v) < y_end_ && column_of(v) < m_.x_end)
                m_.begin(start_[v], column_of(v), row_of(v));
            active_[group_of(v)] |= simd::bits(start_[v].surface) != 0;
        }
        for (int v = 0; v < kVectors; ++v)
            if (simd::bits(start_[v].surface)) m_.orient(start_[v]);
        for (int v = 0; v < kVectors; ++v)
            if (simd::bits(start_[v].surface)) m_.frame(start_[v]);
    }

    // The steps of directions i0 .. i0 + batch - 1, row by row (a row's
    // lanes share their directions).
    void aim_batch(int i0, int batch) {
        for (int k = 0; k < batch; ++k)
            for (int r = 0; r < kGroupRows; ++r) {
                Float hx{}, hy{}, hz{};
                m_.direction(direction(i0 + k), y0_ + r, hx, hy, hz);
                for (int g = 0; g < kGroups; ++g)
                    for (int v = g * kGroupVectors + r * kAcross;
                         v < g * kGroupVectors + (r + 1) * kAcross; ++v)
                        if (marching(v)) m_.aim(steps_[v][k], start_[v], hx, hy, hz);
            }
    }

    void march_batch(int batch) {
        for (int v = 0; v < kVectors; ++v) {
            if (!marching(v)) continue;
            for (int k = 0; k < batch; ++k) {
                const MarchStep& s = steps_[v][k];
                const Int blocked = s.bordered ? m_.template march<true>(start_[v], s, row_of(v))
                                               : m_.template march<false>(start_[v], s, row_of(v));
                open_[v] += select(blocked, Float{}, Float{} + 1.0f);
            }
        }
    }

    // After the first direction: a group open for all of its texels is
    // taken as open in every direction, and marches no more.
    void settle_open_groups() {
        for (int g = 0; g < kGroups; ++g) {
            if (!active_[g]) continue;
            uint32_t closed = 0;
            for (int v = g * kGroupVectors; v < (g + 1) * kGroupVectors; ++v)
                closed |= simd::bits(start_[v].surface & (open_[v] != 1.0f));
            if (!closed) {
                for (int v = g * kGroupVectors; v < (g + 1) * kGroupVectors; ++v)
                    open_[v] = Float{} + float(f_.samples);
                active_[g] = false;
            }
        }
    }

    void store() const {
        for (int v = 0; v < kVectors; ++v) {
            const int first_texel = column_of(v);
            if (first_texel >= m_.x_end || row_of(v) >= y_end_) continue;
            const Float visible = select(start_[v].surface, open_[v] * (1.0f / float(f_.samples)),
                                         Float{} + 1.0f);
            store_row(f_.raw + size_t(row_of(v)) * size_t(f_.width), first_texel, m_.x_end,
                      visible);
        }
    }

    const Marcher<Perspective>& m_;
    const AoFrame& f_;
    const int x0_, y0_, y_end_;
    MarchStart start_[kVectors];
    MarchStep steps_[kVectors][kBatch];
    bool active_[kGroups];  // a group with a surface, not yet settled
    Float open_[kVectors];  // directions found open, per texel
};

template <bool Perspective>
void occlusion_rows(const AoFrame& f, int first, int count, int x_first, int x_count) {
    const Marcher<Perspective> marcher(f, std::min(x_first + x_count, f.width));
    using Groups = GroupMarches<Perspective>;
    const int y_end = first + count;
    for (int y0 = first; y0 < y_end; y0 += Groups::kGroupRows)
        for (int x0 = x_first; x0 < marcher.x_end; x0 += Groups::kGroups * Groups::kGroupWidth) {
            Groups groups(marcher, x0, y0, y_end);
            groups.run();
        }
}

}  // namespace

// Ambient visibility of AO rows [first, first + count), before the blur:
// the share of the texel's `samples` directions whose march is not blocked,
// over columns [x_first, x_first + x_count) (x_first a multiple of
// AoFrame::kGroupWidth, first of AoFrame::kGroupRows).
// Texels turn their direction set by (x & 3) * 4 + (y & 3). A vector's lanes
// are neighbours in a row, so that its start reads whole vectors. A
// direction's march reaches `radius` along it in AoFrame::kSteps even steps
// of its segment on the screen, in fixed point, and compares keys (1 / w,
// or z) rather than depths: no division per step.
// A step is blocked only by a surface above the texel's tangent plane
// (whose key is affine over the grid), so that a lookup half a texel off
// never takes the surface itself for an occluder. Each group of 16 texels
// of 4 rows marches its most grazing direction first, and is taken as
// open, without the rest, where it is open for all of its texels.
void ao_occlusion_rows(const AoFrame& f, int first, int count, int x_first, int x_count) {
    if (f.perspective) occlusion_rows<true>(f, first, count, x_first, x_count);
    else occlusion_rows<false>(f, first, count, x_first, x_count);
}

// AO rows [first, first + count) of `raw` averaged over the 4x4 window
// aligned with the rotation pattern (x - 1 .. x + 2, y - 1 .. y + 2),
// weighted by depth similarity, into `blurred`.
void ao_blur_rows(const AoFrame& f, int first, int count) {
    for (int y = first; y < first + count; ++y) {
        const size_t row = size_t(y) * size_t(f.width);
        for (int x0 = 0; x0 < f.width; x0 += kWidth) {
            const Float z = load_row(f.z + row, x0, f.width, 0.0f);
            const Int surface = z != 0.0f;
            if (!simd::bits(surface)) {
                store_row(f.blurred + row, x0, f.width, Float{} + 1.0f);
                continue;
            }
            const int j_first = std::max(y - 1, 0), j_last = std::min(y + 2, f.height - 1);
            const bool inside = x0 >= 1 && x0 + kWidth + 2 <= f.width;
            if (inside) {
                // Open wherever the window is open: the weighted mean of ones
                // is exactly one (every term of the sum is its weight's).
                Int open = Int{} - 1;
                for (int j = j_first; j <= j_last; ++j)
                    for (int dx = -1; dx <= 2; ++dx)
                        open &= simd::load<Float>(f.raw + size_t(j) * size_t(f.width) +
                                                  size_t(x0 + dx)) == 1.0f;
                if (simd::bits(open) == simd::kPartMask) {
                    store_row(f.blurred + row, x0, f.width, Float{} + 1.0f);
                    continue;
                }
            }
            const Float inv_z = 1.0f / select(surface, z, Float{} + 1.0f);
            Float sum = Float{}, weight = Float{};
            for (int j = j_first; j <= j_last; ++j) {
                const size_t at = size_t(j) * size_t(f.width);
                for (int dx = -1; dx <= 2; ++dx) {
                    Int in = Int{} - 1;  // lanes whose neighbour x0 + i + dx is in the row
                    Float zn{}, raw{};
                    if (inside) {
                        zn = simd::load<Float>(f.z + at + size_t(x0 + dx));
                        raw = simd::load<Float>(f.raw + at + size_t(x0 + dx));
                    } else {
                        for (int i = 0; i < kWidth; ++i) {
                            const int x = std::clamp(x0 + i + dx, 0, f.width - 1);
                            in[i] = x0 + i + dx == x ? -1 : 0;
                            zn[i] = f.z[at + size_t(x)];
                            raw[i] = f.raw[at + size_t(x)];
                        }
                    }
                    const Float w = select(in, depth_weight((zn - z) * inv_z), Float{});
                    sum += w * raw;
                    weight += w;
                }
            }
            store_row(f.blurred + row, x0, f.width,
                      select(surface, sum / weight, Float{} + 1.0f));
        }
    }
}

namespace {

// The rows' loads would miss the cache (a tile's rows are too short for the
// hardware's prefetcher to follow): row y asks for the depth of the row
// kAhead on and, every other row, for the row of texels that row will
// reach first (at half size, the only size this runs at). j0 is the first
// row of texels that row y reads, and rows from `last` on are not drawn.
void prefetch_rows_ahead(const AoFrame& f, int y, int j0, int last, int x_first, int x_count) {
    constexpr int kAhead = 4;
    const float* depth = f.target_depth + size_t(y) * size_t(f.target_stride);
    if (y + kAhead < last)
        for (int x = x_first; x < x_first + x_count; x += 16)
            __builtin_prefetch(depth + kAhead * size_t(f.target_stride) + size_t(x));
    if (y % 2 == 0 && j0 + kAhead / 2 + 1 < f.height)
        for (int i = x_first / 2; i < (x_first + x_count) / 2; i += 16) {
            const size_t at = size_t(j0 + kAhead / 2 + 1) * size_t(f.width) + size_t(i);
            __builtin_prefetch(f.z + at);
            __builtin_prefetch(f.blurred + at);
        }
}

// Corner k of the texels around a vector of pixels (bit 0 the right
// column, bit 1 the lower row; `texels(k, z, a)` gives their view z and
// blurred visibility) weighs c_k / d_k: its bilinear weight c_k (0 where
// nothing was drawn) over d_k = 1 / depth_weight. The weighted mean
// sum(c_k a_k / d_k) / sum(c_k / d_k) is taken with both sums times the
// product of the d_k, which needs no division: d_k is capped at 1e8 (a
// weight below 1e-8 changes nothing that shows), so that the product stays
// finite. A row of texels with no weight (fy 0: the pixel's row is the
// texels') adds nothing. `enough` where the mean weight is above 1e-4.
template <class Texels>
Float depth_weighted_mean(const Texels& texels, const Float& fx, float fy, const Float& z,
                          const Float& inv_z, Int& enough) {
    Float c[4], dk[4], a[4];
    for (int corner = 0; corner < 4; ++corner) {
        if (corner >= 2 && fy == 0.0f) {
            c[corner] = Float{}, dk[corner] = Float{} + 1.0f, a[corner] = Float{};
            continue;
        }
        Float zt;
        texels(corner, zt, a[corner]);
        const Float wx = corner & 1 ? fx : 1.0f - fx;
        const float wy = corner & 2 ? fy : 1.0f - fy;
        const Float r = (zt - z) * inv_z;
        const Int drawn = zt != 0.0f;
        c[corner] = select(drawn, wx * wy, Float{});
        dk[corner] = select(drawn, select(r * r < 4e4f, 1.0f + 2500.0f * r * r, Float{} + 1e8f),
                            Float{} + 1.0f);
    }
    const Float d01 = dk[0] * dk[1], d23 = dk[2] * dk[3];
    const Float others[4] = {dk[1] * d23, dk[0] * d23, dk[3] * d01, dk[2] * d01};
    Float sum = Float{}, weight = Float{};
    for (int corner = 0; corner < 4; ++corner) {
        const Float w = c[corner] * others[corner];
        sum += w * a[corner];
        weight += w;
    }
    enough = weight > 1e-4f * (d01 * d23);
    return sum / select(enough, weight, Float{} + 1.0f);
}

// The visibility of the corner nearest in depth (across an edge, where no
// corner is alike).
template <class Texels>
Float nearest_in_depth(const Texels& texels, const Float& z, const Float& inv_z) {
    Float nearest = Float{} + 1.0f, closest = Float{} + INFINITY;
    for (int corner = 0; corner < 4; ++corner) {
        Float zt, at;
        texels(corner, zt, at);
        const Float difference = (zt - z) * inv_z;
        const Float distance = select(zt != 0.0f, difference * difference, Float{} + INFINITY);
        const Int nearer = distance < closest;
        closest = select(nearer, distance, closest);
        nearest = select(nearer, at, nearest);
    }
    return nearest;
}

}  // namespace

// The visibility of target pixels [x_first, x_first + x_count) of rows
// [first, first + count) (x_first and x_count multiples of kWidth, first
// of 4), into `blocks`: 4x4 blocks of 16 floats (row by row), `across`
// blocks a row, the block of (x_first, first) first,
// from the blurred AO texels around each pixel: the bilinear weights of the
// four nearest, each times its depth similarity to the pixel's own view z,
// so that an edge's near side never takes the far side's occlusion; where
// no texel is alike, the one nearest in depth. Pixels past the target's
// edge get 1.
void ao_upsample_rows(const AoFrame& f, int first, int count, int x_first, int x_count,
                      float* blocks, int across) {
    const float inv_scale = 1.0f / float(f.scale);
    Int lane;
    for (int i = 0; i < kWidth; ++i) lane[i] = i;
    for (int y = first; y < first + count; ++y) {
        // Texel j stands for target pixel j * scale: rows j0 and j1 straddle y.
        const int j0 = std::min(y / f.scale, f.height - 1), j1 = std::min(j0 + 1, f.height - 1);
        const float fy = float(y - j0 * f.scale) * inv_scale;
        // Where a vector of pixels from x0 goes: 4 floats to each block.
        float* row = blocks + size_t((y - first) / 4) * size_t(across) * 16 +
                     size_t((y - first) % 4) * 4;
        const auto store = [&](int x0, const Float& v) {
            float* at = row + size_t(x0 - x_first) * 4;  // block (x0 - x_first) / 4
            const float* from = reinterpret_cast<const float*>(&v);
            for (int c = 0; c < kWidth / 4; ++c)
                std::memcpy(at + 16 * c, from + 4 * c, 4 * sizeof(float));
        };
        const float* depth = f.target_depth + size_t(y) * size_t(f.target_stride);
        const float ndc_y = 1.0f - (float(y) + 0.5f) * (2.0f / float(f.target_height));
        prefetch_rows_ahead(f, y, j0, first + count, x_first, x_count);
        const int x_end = std::min(x_first + x_count, f.target_width);
        for (int x0 = x_first; x0 < x_end; x0 += kWidth) {
            // At half size a vector of pixels spans half as many texels,
            // in order: two loads and a spread of each, where they lie within
            // the row; else gathers.
            const int base = x0 / 2;
            const bool spread = f.scale == 2 && base + kWidth <= f.width;
            // Open where the texels around (kWidth / 2 + 1 of each row) are
            // open: the weighted mean of ones, and the nearest of them, is
            // exactly one. No depth is read for it.
            constexpr uint32_t kReached = (2u << (kWidth / 2)) - 1u;
            const auto ones = [&](int j) {
                return simd::load<Float>(f.blurred + j * f.width + base) == 1.0f;
            };
            if (spread && (simd::bits(ones(j0) & ones(j1)) & kReached) == kReached) {
                store(x0, Float{} + 1.0f);
                continue;
            }
            // The pixel's view z, from its depth (rows are padded: whole loads).
            const Float d = simd::load<Float>(depth + x0);
            const Float ndc_x =
                (simd::to_float(lane + x0) + 0.5f) * (2.0f / float(f.target_width)) - 1.0f;
            const Int surface = (d != f.background) & (lane + x0 < f.target_width);
            if (!simd::bits(surface)) {
                store(x0, Float{} + 1.0f);
                continue;
            }
            const Float zv = (f.z_row.x * ndc_x + (f.z_row.y * ndc_y + f.z_row.w)) + f.z_row.z * d;
            const Float wv = (f.w_row.x * ndc_x + (f.w_row.y * ndc_y + f.w_row.w)) + f.w_row.z * d;
            // z = zv / wv and 1 / z = wv / zv, with one division (once the
            // loads come from the cache, divisions bound this loop).
            const Float inv_zw = 1.0f / select(surface, zv * wv, Float{} + 1.0f);
            const Float z = select(surface, zv * zv * inv_zw, Float{});
            const Float inv_z = select(surface, wv * wv * inv_zw, Float{} + 1.0f);
            const Int x = lane + x0;
            const Int i0 = f.scale == 2 ? x >> 1 : x;
            const Float fx = simd::to_float(x - i0 * f.scale) * inv_scale;
            const Int columns[2] = {i0 < f.width - 1 ? i0 : Int{} + (f.width - 1),
                                    i0 + 1 < f.width - 1 ? i0 + 1 : Int{} + (f.width - 1)};
            // Corner k's view z and blurred visibility (bit 0 the right
            // column, bit 1 the lower row).
            const auto texels = [&](int corner, Float& zt, Float& at) {
                const int texel_row = (corner & 2 ? j1 : j0) * f.width;
                if (spread) {
                    const Float zs = simd::load<Float>(f.z + texel_row + base);
                    const Float as = simd::load<Float>(f.blurred + texel_row + base);
                    zt = corner & 1 ? spread_next(zs) : spread_pairs(zs);
                    at = corner & 1 ? spread_next(as) : spread_pairs(as);
                } else {
                    const Int k = columns[corner & 1] + texel_row;
                    zt = simd::gather(f.z, k), at = simd::gather(f.blurred, k);
                }
            };
            Int enough;
            Float v = depth_weighted_mean(texels, fx, fy, z, inv_z, enough);
            if (simd::bits(surface & ~enough))  // rarely (across an edge)
                v = select(enough, v, nearest_in_depth(texels, z, inv_z));
            store(x0, select(surface, v, Float{} + 1.0f));
        }
    }
}

}  // namespace facet::FACET_KERNEL_NS
