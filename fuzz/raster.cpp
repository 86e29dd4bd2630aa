// Fuzz target: primitive assembly, clipping, setup, binning, rasterization
// and the fragment stage (core/src/pipeline/: vertex.cpp, project_kernels.cpp,
// assembly.cpp, assembly_kernels.cpp, clip.cpp, setup.cpp, bin.cpp,
// rasterize.cpp, fragment.cpp), and the wire (lines.cpp, edges.cpp),
// through Pipeline::draw, with random clip-space vertices.
//
// Input: three header bytes (viewport 1..72 pixels a side, so a 64-pixel
// tile edge can fall inside; MSAA 1, 2, 4 or 8; cull mode and front face;
// sub-pixel bits), then up to 12 triangles of three vertices of four
// components. A component is one byte: a special value (zeros, NaN, +-Inf,
// +-FLT_MAX, denormals, ...), a value on a 1/32 grid in [-2.75, 2.72], or
// else a float from the next four bytes.
//
// A shader writes its colour input as the clip position, so the vertices
// reach clipping exactly as decoded, and outputs red 1 under additive
// blending, so red counts coverage. Each triangle is drawn alone, then all
// of them in one draw, and once more with the stencil counting coverage.
// Alone, a triangle takes the scalar assembly; together, the first eight
// take the wide one (assemble_triangles) on the AVX2 and AVX-512 paths,
// and the rest the scalar one after them.
// Checks, for each triangle:
//  - statistics: one triangle in, ending in exactly one outcome (NaN or Inf:
//    invalid); fragments shaded = pixels covered; nothing covered unless it
//    was rasterized;
//  - no pixel or sample is covered twice (a clipped fan shares its edges);
//  - coverage against an oracle that does not clip (see below): a sample
//    point more than `tol` inside the visible part (0 <= z <= w) of the
//    triangle must be covered, unless its orientation is culled, and more
//    than `tol` outside must not be. `tol` is 1.5 steps of the sub-pixel
//    grid: snapping moves no point of the clipped polygon's outline, nor
//    of the fan inside it, by more than about 0.71 of a step;
//  - at covered pixels (1 sample), the perspective-correct barycentric
//    weights, interpolated as a varying, are finite, in [0, 1], and sum to
//    at most 1;
// and for the single draw of all: every sample's count and every statistic
// is the sum of the separate draws'; drawn with the stencil on, the same
// colours, and every sample's stencil value its count. Last, their wire
// (PipelineState::wireframe), counted the same way: one line in for each
// of the triangles' edges, each ending in one outcome; and where every
// vertex lies within the depth range and near the view (nothing cut), no
// sample covered farther than `tol` outside every edge's 1-pixel
// rectangle, nor more often than the rectangles that hold it.
#include "support.hpp"

#include <facet/framebuffer.hpp>
#include <facet/mesh.hpp>
#include <facet/pipeline.hpp>
#include <facet/plugin.hpp>
#include <facet/shader.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

namespace facet::fuzz {

namespace {

using Triangle = std::array<glm::vec4, 3>;

constexpr size_t kMaxTriangles = 12;
constexpr int kMaxSide = 72;

// Clip position = the vertex colour. The UV is one-hot per vertex ((0, 0),
// (1, 0), (0, 1)), so the varying is the weight of vertices 1 and 2.
struct ClipShader {
    static constexpr const char* name = "fuzz_clip";
    static constexpr const char* version = "fuzz";
    static constexpr uint32_t needs = FACET_NEED_COLORS | FACET_NEED_UVS;
    FACET_VARYINGS((sdk::Vec2, weights))
    FACET_PARAMS()
    static Varyings vertex(const sdk::VertexIn& in, const sdk::Draw&, const Params&,
                           sdk::Vec4& clip) {
        clip = in.color;
        return {in.uv};
    }
    static sdk::Vec4 fragment(const Varyings& v, sdk::Fragment&, const sdk::Draw&,
                              const Params&) {
        return {sdk::splat(1.0f), v.weights.x, v.weights.y, sdk::splat(1.0f)};
    }
};

// ---- input -----------------------------------------------------------------------

const float kSpecial[] = {0.0f,
                          -0.0f,
                          1.0f,
                          -1.0f,
                          0.5f,
                          std::numeric_limits<float>::quiet_NaN(),
                          std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity(),
                          std::numeric_limits<float>::max(),
                          -std::numeric_limits<float>::max(),
                          std::numeric_limits<float>::min(),
                          std::numeric_limits<float>::denorm_min(),
                          -std::numeric_limits<float>::denorm_min(),
                          1e-30f,
                          1e30f,
                          1048576.0f};  // 2^20: the guard band's size in pixels
constexpr int kSpecialCount = int(sizeof kSpecial / sizeof kSpecial[0]);

class Reader {
public:
    Reader(const uint8_t* data, size_t size) : p_(data), end_(data + size) {}
    bool empty() const { return p_ == end_; }
    uint8_t byte() { return p_ < end_ ? *p_++ : 0; }

    float component() {
        const int tag = byte();
        if (tag < kSpecialCount) return kSpecial[tag];
        if (tag < 192) return float(tag - 104) / 32.0f;
        uint32_t bits = 0;
        for (int i = 0; i < 4; ++i) bits |= uint32_t(byte()) << (8 * i);
        return std::bit_cast<float>(bits);
    }

private:
    const uint8_t* p_;
    const uint8_t* end_;
};

struct Config {
    int width, height, samples, subpixel_bits;
    CullMode cull;
    bool front_ccw;
};

Config read_config(Reader& in) {
    static constexpr CullMode kCull[] = {CullMode::none, CullMode::back, CullMode::front,
                                         CullMode::none};
    static constexpr int kBits[] = {8, 8, 8, 8, 6, 4, 2, 1};
    Config c;
    c.width = 1 + in.byte() % kMaxSide;
    c.height = 1 + in.byte() % kMaxSide;
    const int flags = in.byte();
    c.cull = kCull[flags & 3];
    c.front_ccw = (flags >> 2) & 1;
    c.samples = 1 << ((flags >> 3) & 3);
    c.subpixel_bits = kBits[flags >> 5];
    return c;
}

bool finite(const Triangle& t) {
    for (const glm::vec4& v : t)
        for (int i = 0; i < 4; ++i)
            if (!std::isfinite(v[i])) return false;
    return true;
}

std::string text(const Triangle& t) {
    std::string out;
    char buffer[160];
    for (const glm::vec4& v : t) {
        std::snprintf(buffer, sizeof buffer, "%s(%.9g, %.9g, %.9g, %.9g)", out.empty() ? "" : " ",
                      double(v.x), double(v.y), double(v.z), double(v.w));
        out += buffer;
    }
    return out;
}

// ---- the oracle ------------------------------------------------------------------
//
// No clipping: the sample point P = (X, Y) on screen is a ray, and the ray
// meets the triangle's plane where sum(l_i v_i) has x = px w and y = py w
// (px, py: P in NDC). With sum(l_i) = 1, Cramer's rule gives l_i = L_i / D,
// where L_i and D = sum(L_i) are affine functions of P (2x2 minors of the
// vertex data). P is visible when l_i >= 0, z >= 0 and w - z >= 0 there,
// that is when L_i, Z = sum(z_i L_i) and WZ = sum((w_i - z_i) L_i) all
// have the sign of D: half-planes on one side of the horizon D = 0. Their
// lines give P's distance from the visible region's edge.
//
// The core clips in double, so the clipped polygon's corners carry errors
// of a few units in the last place of the largest input component, S. At a
// point whose w is small against S that is many pixels: the visible part
// near P lies at w = W / D, W = sum(w_i L_i), and the tolerance grows with
// S / w there. The clipped polygon's outline also runs along the guard
// band (setup.hpp: 2^20 pixels out), whose corners carry the same errors;
// once they could reach the viewport, the oracle says nothing.

// c + cx X + cy Y at window position (X, Y), with the sums of the terms'
// magnitudes, which bound the rounding error of evaluating it.
struct Affine {
    double c = 0.0, cx = 0.0, cy = 0.0;
    double mc = 0.0, mx = 0.0, my = 0.0;

    Affine& add(double k, const Affine& f) {
        c += k * f.c, cx += k * f.cx, cy += k * f.cy;
        mc += std::abs(k) * f.mc, mx += std::abs(k) * f.mx, my += std::abs(k) * f.my;
        return *this;
    }
    double at(glm::dvec2 p) const { return c + cx * p.x + cy * p.y; }

    // Signed distance in pixels from P to the line f = 0 (positive where f
    // has the sign `side`); 0 when rounding could have the sign wrong.
    double distance(glm::dvec2 p, double side) const {
        const double value = at(p);
        if (std::abs(value) <= std::ldexp(mc + mx * std::abs(p.x) + my * std::abs(p.y), -40))
            return 0.0;
        const double gradient = std::hypot(cx, cy);
        const double d = gradient > 0.0 ? std::abs(value) / gradient
                                         : std::numeric_limits<double>::infinity();
        return value * side > 0.0 ? d : -d;
    }
};

// What the triangle must cover.
struct Reference {
    bool empty = false;   // non-finite: dropped
    Affine l[3], d, z, wz, w;
    int front = 0;        // +1 front-facing, -1 back-facing, 0 too close to call
    bool culled_front = false, culled_back = false;
    double snap = 0.0;    // pixels that vertex snapping may move an edge
    double scale = 0.0;   // S times half the larger viewport side (NDC to pixels)

    // +1: p must be covered, -1: must not be, 0: either.
    int expect(glm::dvec2 p) const {
        if (empty) return -1;
        const double horizon = d.distance(p, 1.0);
        if (horizon == 0.0) return 0;
        const double side = horizon > 0.0 ? 1.0 : -1.0;
        const double tol = snap + std::ldexp(scale / std::abs(w.at(p) / d.at(p)), -40);
        if (!(tol < std::ldexp(1.0, 18))) return 0;
        double inside = std::abs(horizon), outside = -1.0;  // margin in; distance out
        for (const Affine* f : {&l[0], &l[1], &l[2], &z, &wz}) {
            const double m = f->distance(p, side);
            inside = std::min(inside, m);
            outside = std::max(outside, -m);
        }
        if (inside > tol) {
            if (front == 0) return 0;
            const bool culled = front > 0 ? culled_front : culled_back;
            return culled ? -1 : 1;
        }
        // Out: beyond a violated half-plane, and the other side of the horizon.
        return std::min(outside, std::abs(horizon)) > tol ? -1 : 0;
    }
};

Reference reference(const Triangle& t, const Config& c) {
    Reference r;
    r.empty = !finite(t);
    if (r.empty) return r;
    r.snap = 1.5 * std::ldexp(1.0, -c.subpixel_bits);
    for (const glm::vec4& v : t)
        for (int i = 0; i < 4; ++i) r.scale = std::max(r.scale, std::abs(double(v[i])));
    r.scale *= 0.5 * std::max(c.width, c.height);
    // Minors of vertices j, k; P in NDC is (2X/W - 1, 1 - 2Y/H).
    Affine det;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec4 a(t[size_t((i + 1) % 3)]), b(t[size_t((i + 2) % 3)]);
        const double A = a.x * b.y - b.x * a.y, B = a.w * b.y - b.w * a.y,
                     C = a.x * b.w - b.x * a.w;
        const double mA = std::abs(a.x * b.y) + std::abs(b.x * a.y),
                     mB = std::abs(a.w * b.y) + std::abs(b.w * a.y),
                     mC = std::abs(a.x * b.w) + std::abs(b.x * a.w);
        r.l[i] = {A + B - C, -2.0 * B / c.width, 2.0 * C / c.height,
                  mA + mB + mC, 2.0 * mB / c.width, 2.0 * mC / c.height};
        const glm::dvec4 v(t[size_t(i)]);
        r.d.add(1.0, r.l[i]);
        r.z.add(v.z, r.l[i]);
        r.wz.add(v.w - v.z, r.l[i]);
        r.w.add(v.w, r.l[i]);
        det.add(v.w, Affine{A, 0.0, 0.0, mA, 0.0, 0.0});
    }
    // On screen the visible part has the orientation of det(x, y, w): > 0 is
    // counter-clockwise in NDC (y up).
    const double orientation = det.distance({0.0, 0.0}, 1.0);
    r.front = orientation == 0.0 ? 0 : (orientation > 0.0) == c.front_ccw ? 1 : -1;
    r.culled_front = c.cull == CullMode::front;
    r.culled_back = c.cull == CullMode::back;
    return r;
}

// ---- drawing and checking ------------------------------------------------------------

Mesh mesh_of(const std::vector<Triangle>& triangles) {
    static const glm::vec2 kOneHot[3] = {{0, 0}, {1, 0}, {0, 1}};
    Mesh m;
    m.source = "fuzz";
    for (const Triangle& t : triangles)
        for (int k = 0; k < 3; ++k) {
            m.indices.push_back(uint32_t(m.positions.size()));
            m.positions.push_back(glm::vec3(0.0f));
            m.colors.push_back(t[size_t(k)]);
            m.uvs.push_back(kOneHot[k]);
        }
    return m;
}

// With `stencil`, into a target with a stencil buffer, each covered sample
// also adds 1 to its stencil value; with `wire`, the mesh's wire is drawn.
FrameStats draw(Pipeline& pipeline, const Mesh& mesh, const Config& c, Framebuffer& fb,
                bool stencil = false, bool wire = false) {
    static const std::shared_ptr<ShaderPlugin> shader =
        ShaderPlugin::from_descriptor(sdk::describe<ClipShader>(), "fuzz");
    fb.clear(glm::vec4(0.0f), 0.0f, 0);
    DrawCall call;
    call.mesh = &mesh;
    call.shader = shader.get();
    call.state.cull = c.cull;
    call.state.front_ccw = c.front_ccw;
    call.state.blend = BlendMode::additive;
    call.state.depth_compare = DepthCompare::always;
    call.state.depth_write = false;
    call.state.subpixel_bits = c.subpixel_bits;
    call.state.stencil.enabled = stencil;
    call.state.stencil.front.pass = call.state.stencil.back.pass = StencilOp::increment;
    call.state.wireframe = wire;
    call.state.wire_color = glm::vec3(1.0f);  // red 1: counts as the shader's does
    FrameStats stats;
    pipeline.draw(call, fb, stats);
    return stats;
}

// The colour of every sample point: sample s of pixel (x, y) is at
// (y * width + x) * samples + s (with one sample, the pixels).
std::vector<glm::vec4> read_samples(Framebuffer& fb) {
    std::vector<glm::vec4> out;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x)
            for (int s = 0; s < fb.samples(); ++s) out.push_back(fb.sample(x, y, s));
    return out;
}

uint64_t outcomes(const FrameStats& s) {
    return s.triangles_culled_frustum + s.triangles_culled_backface +
           s.triangles_culled_degenerate + s.triangles_invalid + s.triangles_rasterized;
}

[[noreturn]] void fail_at(const Triangle& t, int x, int y, int s, const std::string& what) {
    fail("triangle " + text(t) + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
         ") sample " + std::to_string(s) + ": " + what);
}

void check_weights(const Triangle& t, int x, int y, const glm::vec4& c) {
    const float eps = 1e-4f;
    if (!(c.g >= -eps && c.b >= -eps && c.g + c.b <= 1.0f + eps))
        fail_at(t, x, y, 0,
                "barycentric weights (" + std::to_string(c.g) + ", " + std::to_string(c.b) +
                    ") are not finite weights in [0, 1]");
}

struct Covered {
    uint64_t pixels = 0;   // with a covered sample
    uint64_t samples = 0;
};

// Coverage of one triangle drawn alone, against the reference.
Covered check_coverage(const Triangle& t, const Config& c, const Reference& ref,
                       const std::vector<glm::vec4>& fb) {
    Covered covered;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const size_t pixel = size_t(y) * size_t(c.width) + size_t(x);
            bool any = false;
            for (int s = 0; s < c.samples; ++s) {
                const float count = fb[pixel * size_t(c.samples) + size_t(s)].r;
                if (count != 0.0f && count != 1.0f)
                    fail_at(t, x, y, s, "covered " + std::to_string(count) + " times");
                any |= count == 1.0f;
                covered.samples += count == 1.0f;
                const glm::dvec2 o = glm::dvec2(sample_offset(c.samples, s)) / 16.0;
                const int expected = ref.expect(glm::dvec2(x + 0.5, y + 0.5) + o);
                if (expected == 1 && count == 0.0f)
                    fail_at(t, x, y, s, "inside the triangle, facing the viewer, not covered");
                if (expected == -1 && count != 0.0f)
                    fail_at(t, x, y, s, "covered, but outside the triangle or culled");
            }
            if (any && c.samples == 1) check_weights(t, x, y, fb[pixel]);
            covered.pixels += any;
        }
    return covered;
}

void check_alone(const Triangle& t, const Config& c, const std::vector<glm::vec4>& fb,
                 const FrameStats& st) {
    const std::string tri = "triangle " + text(t) + ": ";
    check(st.triangles_in == 1 && outcomes(st) == 1,
          tri + "the outcomes do not add up to one triangle");
    check(finite(t) || st.triangles_invalid == 1, tri + "non-finite, but not counted invalid");
    check(st.fragments_depth_rejected == 0, tri + "fragments failed depth test 'always'");
    const Covered covered = check_coverage(t, c, reference(t, c), fb);
    // With MSAA a pixel whose samples two pieces of a clipped fan share is
    // shaded once for each, but never more often than it has samples.
    const bool shaded = c.samples == 1 ? st.fragments_shaded == covered.pixels
                                       : st.fragments_shaded >= covered.pixels &&
                                             st.fragments_shaded <= covered.samples;
    check(shaded, tri + std::to_string(covered.pixels) + " pixels (" +
                      std::to_string(covered.samples) + " samples) covered, " +
                      std::to_string(st.fragments_shaded) + " fragments shaded");
    check(covered.pixels == 0 || st.triangles_rasterized == 1,
          tri + "covers pixels, not rasterized");
}

void check_sums(const FrameStats& all, const FrameStats& sum) {
    const bool same =
        all.triangles_in == sum.triangles_in &&
        all.triangles_culled_frustum == sum.triangles_culled_frustum &&
        all.triangles_culled_backface == sum.triangles_culled_backface &&
        all.triangles_culled_degenerate == sum.triangles_culled_degenerate &&
        all.triangles_invalid == sum.triangles_invalid &&
        all.triangles_clipped == sum.triangles_clipped &&
        all.triangles_rasterized == sum.triangles_rasterized &&
        all.blocks_shaded == sum.blocks_shaded && all.fragments_shaded == sum.fragments_shaded;
    check(same, "drawn together, the triangles' statistics differ from the sum of their own");
}

// How far p lies inside the 1-pixel rectangle around segment a-b (no caps).
double inside_line(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 d = b - a;
    const double length = glm::length(d);
    if (!(length > 0.0)) return -1.0;  // covers nothing
    const glm::dvec2 along = d / length, across(-along.y, along.x);
    const double s = glm::dot(p - a, along), t = glm::dot(p - a, across);
    return std::min({s, length - s, 0.5 - std::abs(t)});
}

void check_wire(Pipeline& pipeline, const std::vector<Triangle>& triangles, const Config& c) {
    Framebuffer fb(c.width, c.height, ColorFormat::rgba32f, c.samples);
    const FrameStats st = draw(pipeline, mesh_of(triangles), c, fb, false, true);
    check(st.triangles_in == 3 * triangles.size(), "the wire has a line in for other than each edge");
    check(outcomes(st) == st.triangles_in, "a wire line did not end in exactly one outcome");
    // The window position of every corner of the finite triangles (an
    // invalid one has no wire), where none is cut.
    std::vector<glm::dvec2> at;
    for (const Triangle& t : triangles) {
        if (!finite(t)) continue;
        for (const glm::vec4& v : t) {
            const glm::dvec4 p(v);
            if (!(p.w > 0.0 && p.z >= 0.0 && p.z <= p.w)) return;
            const glm::dvec2 w((p.x / p.w + 1.0) * 0.5 * c.width, (1.0 - p.y / p.w) * 0.5 * c.height);
            if (!(std::abs(w.x) < 4096.0 && std::abs(w.y) < 4096.0)) return;
            at.push_back(w);
        }
    }
    const double tol = 1.5 * std::ldexp(1.0, -c.subpixel_bits);  // as for triangles
    const std::vector<glm::vec4> counts = read_samples(fb);
    size_t i = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
            for (int s = 0; s < c.samples; ++s, ++i) {
                const glm::dvec2 p = glm::dvec2(x + 0.5, y + 0.5) +
                                     glm::dvec2(sample_offset(c.samples, s)) / 16.0;
                int maybe = 0;
                for (size_t k = 0; k < at.size(); ++k) {
                    const size_t next = k % 3 == 2 ? k - 2 : k + 1;
                    maybe += inside_line(p, at[k], at[next]) > -tol;
                }
                check(counts[i].r <= float(maybe),
                      "the wire covers a sample outside its edges' rectangles, or too often");
            }
}

}  // namespace

void raster(const uint8_t* data, size_t size) {
    Reader in(data, size);
    const Config c = read_config(in);
    std::vector<Triangle> triangles;
    while (!in.empty() && triangles.size() < kMaxTriangles) {
        Triangle t;
        for (glm::vec4& v : t)
            for (int i = 0; i < 4; ++i) v[i] = in.component();
        triangles.push_back(t);
    }
    if (triangles.empty()) return;

    Pipeline pipeline(1);
    Framebuffer fb(c.width, c.height, ColorFormat::rgba32f, c.samples);
    std::vector<float> counts(size_t(c.width) * size_t(c.height) * size_t(c.samples), 0.0f);
    FrameStats sum;
    for (const Triangle& t : triangles) {
        const FrameStats st = draw(pipeline, mesh_of({t}), c, fb);
        const std::vector<glm::vec4> alone = read_samples(fb);
        check_alone(t, c, alone, st);
        for (size_t i = 0; i < counts.size(); ++i) counts[i] += alone[i].r;
        sum += st;
    }
    const FrameStats all = draw(pipeline, mesh_of(triangles), c, fb);
    check_sums(all, sum);
    const std::vector<glm::vec4> together = read_samples(fb);
    for (size_t i = 0; i < counts.size(); ++i)
        check(together[i].r == counts[i],
              "drawn together, the triangles cover a sample a different number of times");
    // Through the stencil route (no packing; tested sample by sample): the
    // same colours, and each sample's stencil counts its coverage.
    Framebuffer counted(c.width, c.height, ColorFormat::rgba32f, c.samples, true);
    const FrameStats st = draw(pipeline, mesh_of(triangles), c, counted, true);
    check(st.fragments_shaded == all.fragments_shaded,
          "with the stencil on, a different number of fragments was shaded");
    const std::vector<glm::vec4> stenciled = read_samples(counted);
    for (size_t k = 0; k < stenciled.size(); ++k)  // bit for bit: the weights may be NaN
        if (std::memcmp(&stenciled[k], &together[k], sizeof(glm::vec4)) != 0)
            fail("with the stencil on, sample " + std::to_string(k) + "'s colour differs: red " +
                 std::to_string(stenciled[k].r) + " against " + std::to_string(together[k].r));
    size_t i = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
            for (int s = 0; s < c.samples; ++s, ++i)
                check(float(counted.sample_stencil_at(x, y, s)) == counts[i],
                      "the stencil counts a sample's coverage wrongly");
    check_wire(pipeline, triangles, c);
}

}  // namespace facet::fuzz
