// Coverage: the block rasterizer against a small, obviously right oracle.
//
// The oracle tests one sample point against one triangle with exact integer
// arithmetic, and derives the top-left rule from its D3D wording ("a top
// edge is exactly horizontal and above the other edges; a left edge is not
// horizontal and on the left side of the triangle"), independently of
// setup.cpp's edge-normal form.
//
// Every triangle is rasterized by the kernels of every instruction-set path
// this CPU has, each with 32-bit lanes where the triangle allows them and
// with 64-bit lanes always, and all of them must agree (cover() below).
#include "pipeline/assembly.hpp"
#include "pipeline/bin.hpp"
#include "pipeline/clip.hpp"
#include "pipeline/kernels.hpp"
#include "pipeline/setup.hpp"
#include "pipeline/vertex.hpp"

#include <facet/framebuffer.hpp>
#include <facet/isa.hpp>

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <limits>

#include <random>
#include <set>
#include <cstring>
#include <tuple>
#include <utility>
#include <vector>

using namespace facet;

namespace {

struct P {
    int64_t x, y;  // sub-pixel units, y down
};

int64_t cross(P a, P b, P c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

int sign(int64_t v) { return (v > 0) - (v < 0); }

// Is edge a-b (third vertex c) a top or a left edge?
bool top_or_left(P a, P b, P c) {
    if (a.y == b.y) return c.y > a.y;  // horizontal with the interior below: top
    // Left: at the height of c, the edge lies to the left of c.
    const int64_t den = b.y - a.y;
    const int64_t num = a.x * den + (b.x - a.x) * (c.y - a.y);  // x_edge(c.y) * den
    return den > 0 ? num < c.x * den : num > c.x * den;
}

bool oracle_covers(const P v[3], P p) {
    if (cross(v[0], v[1], v[2]) == 0) return false;
    for (int k = 0; k < 3; ++k) {
        const P a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
        const int side = sign(cross(a, b, p));
        if (side == 0 ? !top_or_left(a, b, c) : side != sign(cross(a, b, c))) return false;
    }
    return true;
}

constexpr int kSize = 64;  // a power of two keeps window <-> NDC conversions exact

glm::dvec4 clip_of(P p) {
    const double ndc_x = double(p.x) / (256.0 * kSize) * 2.0 - 1.0;
    const double ndc_y = 1.0 - double(p.y) / (256.0 * kSize) * 2.0;
    return {ndc_x, ndc_y, 0.5, 1.0};
}

using PixelSet = std::set<std::pair<int, int>>;

// The blocks of t's coverage, the same from every path and lane width.
std::vector<Block> cover(const TriangleSetup& t, int samples) {
    std::vector<Block> first;
    bool have_first = false;
    for (Isa isa : supported_isas())
        for (EdgeWidth width : {EdgeWidth::automatic, EdgeWidth::wide}) {
            std::vector<Block> blocks;
            kernels(isa).cover(t, 0, 0, 1 << 20, 1 << 20, samples, width, blocks);
            if (!have_first) {
                first = std::move(blocks);
                have_first = true;
                continue;
            }
            INFO("path " << isa_name(isa) << (width == EdgeWidth::wide ? ", 64-bit lanes" : ""));
            REQUIRE(blocks.size() == first.size());
            for (size_t i = 0; i < blocks.size(); ++i) {
                REQUIRE(blocks[i].x == first[i].x);
                REQUIRE(blocks[i].y == first[i].y);
                REQUIRE(blocks[i].mask == first[i].mask);
                // Every lane's weights, bit for bit: the narrow one-sample
                // route (narrow_coverage.hpp) against BlockCoverage's.
                REQUIRE(std::memcmp(blocks[i].bary, first[i].bary, sizeof first[i].bary) == 0);
                for (int lane = 0; lane < FACET_BLOCK_LANES; ++lane)
                    if (samples > 1 && (blocks[i].mask >> lane & 1))
                        REQUIRE(blocks[i].samples[lane] == first[i].samples[lane]);
            }
        }
    return first;
}

PixelSet raster(const P v[3], bool* drawn = nullptr, int subpixel_bits = 8) {
    const float none = 0.0f;
    const SetupVertex sv[3] = {{clip_of(v[0]), &none}, {clip_of(v[1]), &none},
                               {clip_of(v[2]), &none}};
    CullState cull;
    cull.cull_back = false;
    TriangleSetup t;
    PixelSet out;
    const bool ok = setup_triangle(sv, Viewport{kSize, kSize, 1, subpixel_bits}, cull, t) ==
                    SetupResult::ok;
    if (drawn) *drawn = ok;
    if (!ok) return out;
    for (const Block& b : cover(t, 1))
        for (int i = 0; i < FACET_BLOCK_LANES; ++i)
            if (b.mask & (1u << i)) out.insert({b.x + i % 4, b.y + i / 4});
    return out;
}

PixelSet oracle(const P v[3]) {
    PixelSet out;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            if (oracle_covers(v, {x * 256 + 128, y * 256 + 128})) out.insert({x, y});
    return out;
}

P px(double x, double y) { return {int64_t(x * 256), int64_t(y * 256)}; }

// Covered (x, y, sample) triples at n samples per pixel.
using SampleSet = std::set<std::tuple<int, int, int>>;

// The standard sample positions, in 1/16 pixel from the centre (the D3D
// 10.1 / Vulkan tables), written out here independently of the core's.
std::vector<std::pair<int, int>> pattern(int n) {
    switch (n) {
        case 2: return {{4, 4}, {-4, -4}};
        case 4: return {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
        default: return {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
    }
}

SampleSet raster_samples(const P v[3], int n) {
    const float none = 0.0f;
    const SetupVertex sv[3] = {{clip_of(v[0]), &none}, {clip_of(v[1]), &none},
                               {clip_of(v[2]), &none}};
    TriangleSetup t;
    SampleSet out;
    if (setup_triangle(sv, Viewport{kSize, kSize, n}, CullState{false, false, true}, t) !=
        SetupResult::ok)
        return out;
    for (const Block& b : cover(t, n))
        for (int i = 0; i < FACET_BLOCK_LANES; ++i) {
            if (!(b.mask & (1u << i))) continue;
            for (int s = 0; s < n; ++s)
                if (b.samples[i] & (1u << s)) out.insert({b.x + i % 4, b.y + i / 4, s});
        }
    return out;
}

SampleSet oracle_samples(const P v[3], int n) {
    SampleSet out;
    const auto offsets = pattern(n);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            for (int s = 0; s < n; ++s) {
                const P p{x * 256 + 128 + offsets[size_t(s)].first * 16,
                          y * 256 + 128 + offsets[size_t(s)].second * 16};
                if (oracle_covers(v, p)) out.insert({x, y, s});
            }
    return out;
}

}  // namespace

TEST_CASE("oracle agrees with hand-worked fill-rule cases", "[raster][oracle]") {
    // Right triangle (0,0) (4,0) (0,4): centres with x + y < 4 are inside; the
    // hypotenuse through centres (x + y == 4) is a bottom-right edge.
    const P tri[3] = {px(0, 0), px(4, 0), px(0, 4)};
    CHECK(oracle(tri).size() == 6);
    // A 4x4 square with corners on pixel centres: the top and left sides
    // are in, the bottom and right sides are out.
    const P a[3] = {px(1.5, 1.5), px(5.5, 1.5), px(5.5, 5.5)};
    const P b[3] = {px(1.5, 1.5), px(5.5, 5.5), px(1.5, 5.5)};
    PixelSet both = oracle(a);
    for (auto p : oracle(b)) CHECK(both.insert(p).second);  // never twice
    CHECK(both.size() == 16);
    CHECK(both.count({1, 1}) == 1);
    CHECK(both.count({5, 5}) == 0);
}

TEST_CASE("fill rule on ties: vertices on pixel centres and pixel edges", "[raster][fill]") {
    // Every vertex on a half-pixel grid: most edges pass exactly through
    // pixel centres, which is where a wrong tie rule shows.
    std::mt19937 rng(1234);
    std::uniform_int_distribution<int> coord(0, 2 * 20);  // 0 .. 20 px in half pixels
    int compared = 0, with_ties = 0;
    for (int n = 0; n < 3000; ++n) {
        P v[3];
        for (P& p : v) p = {coord(rng) * 128, coord(rng) * 128};
        const PixelSet expected = oracle(v);
        const PixelSet got = raster(v);
        REQUIRE(got == expected);
        ++compared;
        for (auto [x, y] : expected)
            for (int k = 0; k < 3; ++k)
                if (cross(v[k], v[(k + 1) % 3], {x * 256 + 128, y * 256 + 128}) == 0) ++with_ties;
    }
    CHECK(compared == 3000);
    CHECK(with_ties > 1000);  // the sample really exercised ties
}

TEST_CASE("fill rule: shared edges cover each pixel exactly once", "[raster][fill]") {
    // Two triangles sharing an edge, in both windings, with vertices on
    // centres and edges: their coverage is disjoint and is the square's.
    for (double o : {1.0, 1.5}) {
        const P a = px(o, o), b = px(o + 8, o), c = px(o + 8, o + 8), d = px(o, o + 8);
        for (bool flip : {false, true}) {
            const P t1[3] = {a, flip ? c : b, flip ? b : c};
            const P t2[3] = {a, flip ? d : c, flip ? c : d};
            const PixelSet s1 = raster(t1), s2 = raster(t2);
            PixelSet all = s1;
            for (auto p : s2) REQUIRE(all.insert(p).second);
            CHECK(all.size() == 64);
        }
    }
}

TEST_CASE("32-bit and 64-bit lanes agree with the oracle at the width where they part",
          "[raster][msaa]") {
    // Triangles in a 16384-pixel viewport with an edge spanning just under
    // and just over 2^20 sub-pixels (4096 pixels): the widest that take
    // 32-bit lanes and the narrowest that do not; then 2^21, 1.5 * 2^21 and
    // 2^22, the last two past what 32-bit lanes hold (a limit of 1.5 * 2^21
    // fails here). Where an edge crosses a block the lanes' values are
    // largest, so windows along each edge are rasterized with both widths
    // on every path (cover() compares them) and held to the oracle, with
    // one sample and with 8, whose positions reach furthest from the
    // centres.
    constexpr int kBig = 16384;
    const auto clip = [](P p) {
        return glm::dvec4(double(p.x) / (256.0 * kBig) * 2.0 - 1.0,
                          1.0 - double(p.y) / (256.0 * kBig) * 2.0, 0.5, 1.0);
    };
    constexpr int64_t kSpans[] = {int64_t(1) << 20, int64_t(1) << 20, int64_t(1) << 21,
                                  int64_t(3) << 20, int64_t(1) << 22};
    std::mt19937 rng(77);
    std::uniform_int_distribution<int64_t> start(256 * 1000, 256 * 6000), tweak(-64, 64);
    std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
    int narrow = 0, wide = 0, covered_windows = 0;
    for (int n = 0; n < 30; ++n) {
        // Edge v0-v1 of |dx| + |dy| = span + d, d within a few sub-pixels
        // of 0; v2 beside its middle, so the other edges are about half as
        // long.
        const int64_t span = kSpans[n % 5] + tweak(rng) / 16;
        const double a = angle(rng);
        const double cx = std::cos(a), cy = std::sin(a);
        const double scale = double(span) / (std::abs(cx) + std::abs(cy));
        const P v0{start(rng), start(rng)};
        const P v1{v0.x + int64_t(std::llround(cx * scale)), v0.y + int64_t(std::llround(cy * scale))};
        const P v2{(v0.x + v1.x) / 2 - int64_t(std::llround(cy * 256 * 30)) + tweak(rng),
                   (v0.y + v1.y) / 2 + int64_t(std::llround(cx * 256 * 30)) + tweak(rng)};
        const P v[3] = {v0, v1, v2};
        const float none = 0.0f;
        const SetupVertex sv[3] = {{clip(v0), &none}, {clip(v1), &none}, {clip(v2), &none}};
        for (int samples : {1, 8}) {
            TriangleSetup t;
            if (setup_triangle(sv, Viewport{kBig, kBig, samples}, CullState{false, false, true},
                               t) != SetupResult::ok)
                continue;
            (t.narrow ? narrow : wide) += 1;
            const auto offsets =
                samples == 1 ? std::vector<std::pair<int, int>>{{0, 0}} : pattern(samples);
            for (int k = 0; k < 3; ++k)
                for (double f : {0.1, 0.5, 0.9}) {  // windows along edge k
                    const P a0 = v[k], a1 = v[(k + 1) % 3];
                    const int x = int((double(a0.x) + f * double(a1.x - a0.x)) / 256.0) & ~3;
                    const int y = int((double(a0.y) + f * double(a1.y - a0.y)) / 256.0) & ~3;
                    const int x0 = std::max(0, x - 16), y0 = std::max(0, y - 16);
                    SampleSet got;
                    for (Isa isa : supported_isas())
                        for (EdgeWidth width : {EdgeWidth::automatic, EdgeWidth::wide}) {
                            std::vector<Block> blocks;
                            kernels(isa).cover(t, x0, y0, x0 + 31, y0 + 31, samples, width, blocks);
                            SampleSet s;
                            for (const Block& b : blocks)
                                for (int i = 0; i < FACET_BLOCK_LANES; ++i)
                                    for (int j = 0; j < samples; ++j)
                                        if (samples == 1 ? (b.mask >> i & 1) : (b.samples[i] >> j & 1))
                                            s.insert({b.x + i % 4, b.y + i / 4, j});
                            if (isa == Isa::portable && width == EdgeWidth::automatic) got = s;
                            INFO("path " << isa_name(isa) << (width == EdgeWidth::wide ? ", 64-bit" : "")
                                         << ", " << samples << " samples, span " << span);
                            REQUIRE(s == got);
                        }
                    SampleSet want;
                    for (int py = y0; py < std::min(y0 + 32, kBig); ++py)
                        for (int px = x0; px < std::min(x0 + 32, kBig); ++px)
                            for (int j = 0; j < samples; ++j)
                                if (oracle_covers(v, {px * 256 + 128 + offsets[size_t(j)].first * 16,
                                                      py * 256 + 128 + offsets[size_t(j)].second * 16}))
                                    want.insert({px, py, j});
                    INFO(samples << " samples, span " << span);
                    REQUIRE(got == want);
                    covered_windows += !got.empty();  // the far end of a wedge may be too thin
                }
        }
    }
    CHECK(narrow > 4);  // both sides of the limit were tried
    CHECK(wide > 20);
    CHECK(covered_windows > 200);
}

TEST_CASE("random sub-pixel triangles match the oracle", "[raster]") {
    std::mt19937 rng(99);
    std::uniform_int_distribution<int64_t> coord(-4 * 256, (kSize + 4) * 256);
    for (int n = 0; n < 2000; ++n) {
        P v[3];
        for (P& p : v) p = {coord(rng), coord(rng)};
        REQUIRE(raster(v) == oracle(v));
    }
}

// Pixels whose centre lies within [lo, hi] sub-pixels, on one axis.
int centres_within(int64_t lo, int64_t hi) {
    int n = 0;
    for (int64_t c = 128; c <= hi; c += 256) n += c >= lo;
    return n;
}

TEST_CASE("a triangle within a 2x2 box is set up exactly when it covers a centre",
          "[raster][setup]") {
    std::mt19937 rng(314);
    std::uniform_int_distribution<int64_t> corner(0, (kSize - 4) * 256), offset(0, 2 * 256);
    int dropped = 0, kept = 0;
    for (int n = 0; n < 20000; ++n) {
        const int64_t ox = corner(rng), oy = corner(rng);
        P v[3];
        for (P& p : v) {
            p = {ox + offset(rng), oy + offset(rng)};
            if (n % 2) p = {p.x / 128 * 128, p.y / 128 * 128};  // ties: on centres and pixel edges
        }
        bool drawn = false;
        const PixelSet got = raster(v, &drawn);
        REQUIRE(got == oracle(v));
        const int64_t lo_x = std::min({v[0].x, v[1].x, v[2].x}), hi_x = std::max({v[0].x, v[1].x, v[2].x});
        const int64_t lo_y = std::min({v[0].y, v[1].y, v[2].y}), hi_y = std::max({v[0].y, v[1].y, v[2].y});
        const int columns = centres_within(lo_x, hi_x), rows = centres_within(lo_y, hi_y);
        if (cross(v[0], v[1], v[2]) == 0 || columns > 2 || rows > 2) continue;
        CAPTURE(v[0].x, v[0].y, v[1].x, v[1].y, v[2].x, v[2].y);
        REQUIRE(drawn == !got.empty());
        (drawn ? kept : dropped) += columns > 0 && rows > 0;
    }
    CHECK(dropped > 1000);  // boxes with centres, none covered
    CHECK(kept > 1000);
}

TEST_CASE("fewer sub-pixel bits: vertices round to the coarser grid, then the fill rule holds",
          "[raster][subpixel]") {
    // Rounding to the nearest multiple of 2^(8 - bits) sub-pixels, halves
    // away from zero, is what "n sub-pixel bits" means for a vertex.
    auto coarse = [](int64_t c, int bits) {
        const int64_t q = int64_t(1) << (8 - bits);
        return c >= 0 ? (c + q / 2) / q * q : -((-c + q / 2) / q * q);
    };
    std::mt19937 rng(2718);
    std::uniform_int_distribution<int64_t> coord(-4 * 256, (kSize + 4) * 256);
    int differs = 0;
    for (int bits = 1; bits <= 8; ++bits) {
        CAPTURE(bits);
        for (int n = 0; n < 400; ++n) {
            P v[3], snapped[3];
            for (int k = 0; k < 3; ++k) {
                v[k] = {coord(rng), coord(rng)};
                snapped[k] = {coarse(v[k].x, bits), coarse(v[k].y, bits)};
            }
            const PixelSet got = raster(v, nullptr, bits);
            REQUIRE(got == oracle(snapped));
            if (bits < 8 && got != oracle(v)) ++differs;
        }
    }
    CHECK(differs > 100);  // coarser snapping really moved coverage
}

TEST_CASE("degenerate triangles draw nothing", "[raster]") {
    bool drawn = true;
    const P line[3] = {px(1, 1), px(5, 5), px(9, 9)};
    CHECK(raster(line, &drawn).empty());
    CHECK_FALSE(drawn);
    // Thinner than a sample spacing and between centres: no pixel, no crash.
    const P sliver[3] = {px(1.6, 1), px(1.7, 30), px(1.6, 60)};
    CHECK(raster(sliver) == oracle(sliver));
}

TEST_CASE("barycentric weights reproduce pixel centres", "[raster]") {
    const P v[3] = {px(2.25, 1.5), px(40.75, 9), px(11, 50.125)};
    const float none = 0.0f;
    const SetupVertex sv[3] = {{clip_of(v[0]), &none}, {clip_of(v[1]), &none},
                               {clip_of(v[2]), &none}};
    TriangleSetup t;
    REQUIRE(setup_triangle(sv, Viewport{kSize, kSize}, CullState{false, false, true}, t) ==
            SetupResult::ok);
    // Weights are for setup's (possibly reordered) vertices, whose positions
    // the edge functions hold.
    for (Isa isa : supported_isas()) {
        INFO("path " << isa_name(isa));
        std::vector<Block> blocks;
        kernels(isa).cover(t, 0, 0, kSize, kSize, 1, EdgeWidth::automatic, blocks);
        for (const Block& b : blocks)
            for (int i = 0; i < FACET_BLOCK_LANES; ++i) {
                double x = 0, y = 0, sum = 0;
                for (int k = 0; k < 3; ++k) {
                    x += b.bary[k][i] * double(t.edge[k].x0) / 256.0;
                    y += b.bary[k][i] * double(t.edge[k].y0) / 256.0;
                    sum += b.bary[k][i];
                }
                CHECK(sum == Approx(1.0).margin(1e-5));
                CHECK(x == Approx(b.x + i % 4 + 0.5).margin(1e-3));
                CHECK(y == Approx(b.y + i / 4 + 0.5).margin(1e-3));
            }
    }
}

TEST_CASE("MSAA: every sample's coverage matches the oracle at the standard positions",
          "[raster][msaa]") {
    std::mt19937 rng(4242);
    // Vertices on a 1/16-pixel grid put samples exactly on edges (ties);
    // arbitrary sub-pixel vertices test everything else.
    std::uniform_int_distribution<int> grid(-16, (kSize + 1) * 16);
    std::uniform_int_distribution<int64_t> any(-4 * 256, (kSize + 4) * 256);
    for (int n : {2, 4, 8}) {
        CAPTURE(n);
        for (int k = 0; k < 400; ++k) {
            P v[3];
            for (P& p : v) p = k % 2 ? P{grid(rng) * 16, grid(rng) * 16} : P{any(rng), any(rng)};
            REQUIRE(raster_samples(v, n) == oracle_samples(v, n));
        }
        // Also small triangles that cover samples but no pixel centre.
        for (int k = 0; k < 300; ++k) {
            const int64_t x = any(rng) / 2 + 256 * 8, y = any(rng) / 2 + 256 * 8;
            std::uniform_int_distribution<int64_t> d(-200, 200);
            const P v[3] = {{x, y}, {x + d(rng), y + d(rng)}, {x + d(rng), y + d(rng)}};
            REQUIRE(raster_samples(v, n) == oracle_samples(v, n));
        }
    }
    // The positions themselves are the standard ones.
    for (int n : {2, 4, 8})
        for (int s = 0; s < n; ++s)
            CHECK(sample_offset(n, s) == glm::ivec2(pattern(n)[size_t(s)].first,
                                                    pattern(n)[size_t(s)].second));
}

namespace {

// The vertex stage's outcodes and window position of one vertex, from the
// scalar functions the clipper and setup use.
WindowVertex scalar_projection(const glm::vec4& clip, const Viewport& viewport) {
    WindowVertex w{};
    if (!(std::isfinite(clip.x) && std::isfinite(clip.y) && std::isfinite(clip.z) &&
          std::isfinite(clip.w))) {
        w.user = kInvalid;
        return w;
    }
    const glm::dvec4 c(clip);
    w.user = outcode(c, 1.0) | outcode(c, viewport.guard_ndc()) << 8;
    if (band_code(w.user) == 0 && !project_vertex(c, viewport, w)) w.user |= kNoWindow;
    return w;
}

// Field by field (a setup's padding is never written).
void require_same_setup(const TriangleSetup& a, const TriangleSetup& b) {
    for (int k = 0; k < 3; ++k) {
        CAPTURE(k);
        REQUIRE(a.edge[k].x0 == b.edge[k].x0);
        REQUIRE(a.edge[k].y0 == b.edge[k].y0);
        REQUIRE(a.edge[k].dx == b.edge[k].dx);
        REQUIRE(a.edge[k].dy == b.edge[k].dy);
        REQUIRE(a.edge[k].bias == b.edge[k].bias);
        REQUIRE(std::bit_cast<uint32_t>(a.bary_dx[k]) == std::bit_cast<uint32_t>(b.bary_dx[k]));
        REQUIRE(std::bit_cast<uint32_t>(a.bary_dy[k]) == std::bit_cast<uint32_t>(b.bary_dy[k]));
        REQUIRE(std::bit_cast<uint32_t>(a.z[k]) == std::bit_cast<uint32_t>(b.z[k]));
        REQUIRE(std::bit_cast<uint32_t>(a.inv_w[k]) == std::bit_cast<uint32_t>(b.inv_w[k]));
        REQUIRE(a.varyings[k] == b.varyings[k]);
    }
    REQUIRE(a.area2 == b.area2);
    REQUIRE(std::bit_cast<uint64_t>(a.inv_area2) == std::bit_cast<uint64_t>(b.inv_area2));
    REQUIRE(a.x0 == b.x0);
    REQUIRE(a.y0 == b.y0);
    REQUIRE(a.x1 == b.x1);
    REQUIRE(a.y1 == b.y1);
    REQUIRE(a.narrow == b.narrow);
    REQUIRE(a.clamp_weights == b.clamp_weights);
    REQUIRE(a.front_facing == b.front_facing);
}

// What Assembler::run gives triangles [0, count) of `idx`, from the scalar
// setup_triangle: their setups in order, a marker (area2 = -1 - triangle)
// in place of each one to be clipped, and the counts of the rest.
void scalar_assembly(const WideAssembly& a, const uint32_t* idx, size_t count, SetupChunk& out) {
    for (size_t t = 0; t < count; ++t) {
        const WindowVertex* w[3];
        const float* varyings[3];
        for (int k = 0; k < 3; ++k) {
            w[k] = &a.window[idx[3 * t + k] - a.first_vertex];
            varyings[k] = a.varyings + size_t(idx[3 * t + k] - a.first_vertex) * a.vertex_floats;
        }
        const uint32_t any = w[0]->user | w[1]->user | w[2]->user;
        ++out.stats.triangles_in;
        if (any & kInvalid) {
            ++out.stats.triangles_invalid;
        } else if (view_code(w[0]->user) & view_code(w[1]->user) & view_code(w[2]->user)) {
            ++out.stats.triangles_culled_frustum;
        } else if (band_code(any)) {
            out.setups.emplace_back().area2 = -1 - int64_t(t);
        } else if (any & kNoWindow) {
            ++out.stats.triangles_culled_degenerate;
        } else {
            TriangleSetup s;
            const SetupResult r = setup_triangle(w, varyings, a.viewport, a.cull, s);
            if (r == SetupResult::ok) out.setups.push_back(s);
            if (r == SetupResult::ok) ++out.stats.triangles_rasterized;
            if (r == SetupResult::culled_backface) ++out.stats.triangles_culled_backface;
            if (r == SetupResult::degenerate || r == SetupResult::no_pixels)
                ++out.stats.triangles_culled_degenerate;
        }
    }
}

}  // namespace

TEST_CASE("wide assembly sets up every triangle as the scalar setup does", "[raster][setup]") {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::uniform_int_distribution<int> pick(0, 99);
    constexpr uint32_t kFirst = 5, kVertices = 3000, kFloats = 3;
    // Vertices mostly in view, some near each other (small triangles, level
    // and upright edges, triangles about a pixel across), some outside the view or the guard band, invalid,
    // or at the origin.
    std::vector<glm::vec4> clip;
    for (uint32_t i = 0; i < kVertices; ++i) {
        const int p = pick(rng);
        glm::vec4 c{unit(rng), unit(rng), 0.5f + 0.4f * unit(rng), 1.0f + 0.5f * unit(rng)};
        if (p < 40 && i > 0) c = clip[i - 1] + 0.01f * glm::vec4(unit(rng), unit(rng), 0, 0);
        else if (p < 50) c.x *= 4.0f;
        else if (p < 52) c.x *= 1e7f;
        else if (p < 53) c.y = std::numeric_limits<float>::quiet_NaN();
        else if (p < 54) c = {0.0f, 0.0f, 0.0f, 0.0f};
        else if (p < 64 && i > 0) c = clip[i - 1] + glm::vec4(0.02f, 0, 0, 0);  // a level edge
        else if (p < 74 && i > 0) c = clip[i - 1] + glm::vec4(0, 0.02f, 0, 0);  // an upright one
        else if (p < 84 && i > 0) c = clip[i - 1] + 0.003f * glm::vec4(unit(rng), unit(rng), 0, 0);
        clip.push_back(c);
    }
    std::vector<float> varyings(kVertices * kFloats + 1);
    std::vector<uint32_t> idx;
    std::uniform_int_distribution<uint32_t> vertex(0, kVertices - 1), near(0, 4);
    for (int t = 0; t < 8003; ++t) {
        const uint32_t v0 = vertex(rng);
        for (uint32_t v : {v0, std::min(v0 + near(rng), kVertices - 1),
                           pick(rng) < 5 ? v0 : std::min(v0 + near(rng), kVertices - 1)})
            idx.push_back(v + kFirst);
    }
    const CullState culls[] = {{true, false, true}, {false, true, false}, {false, false, true}};
    for (const int samples : {1, 4})
        for (const CullState& cull : culls)
            for (const int first_row : {0, 40}) {
                const Viewport viewport{640, 480, samples, kSubpixelBits, first_row, 200};
                CAPTURE(samples, cull.cull_back, cull.cull_front, first_row);
                std::vector<WindowVertex> window;
                for (const glm::vec4& c : clip) window.push_back(scalar_projection(c, viewport));
                // The kernel's triangles to be clipped leave a marker, as
                // the scalar assembly above does.
                const auto marker = [](const void* context, const uint32_t* triangle,
                                       SetupChunk& chunk) {
                    const auto* first = static_cast<const uint32_t*>(context);
                    chunk.setups.emplace_back().area2 = -1 - (triangle - first) / 3;
                };
                const WideAssembly a{window.data(), varyings.data(), kFloats, kFirst, viewport,
                                     cull, marker, idx.data()};
                SetupChunk want;
                scalar_assembly(a, idx.data(), idx.size() / 3, want);
                for (Isa isa : supported_isas()) {
                    CAPTURE(isa_name(isa));
                    SetupChunk got;
                    const size_t done =
                        kernels(isa).assemble_triangles(a, idx.data(), idx.size() / 3, got);
                    if (isa == Isa::portable) {
                        REQUIRE(done == 0);  // the core's scalar loop takes them
                        continue;
                    }
                    REQUIRE(done == idx.size() / 3 / 8 * 8);
                    SetupChunk expected;
                    scalar_assembly(a, idx.data(), done, expected);
                    REQUIRE(got.setups.size() == expected.setups.size());
                    for (size_t i = 0; i < got.setups.size(); ++i) {
                        CAPTURE(i);
                        if (expected.setups[i].area2 < 0) {
                            REQUIRE(got.setups[i].area2 == expected.setups[i].area2);
                            continue;
                        }
                        require_same_setup(got.setups[i], expected.setups[i]);
                    }
                    const FrameStats& g = got.stats;
                    const FrameStats& e = expected.stats;
                    CHECK(g.triangles_in == e.triangles_in);
                    CHECK(g.triangles_invalid == e.triangles_invalid);
                    CHECK(g.triangles_culled_frustum == e.triangles_culled_frustum);
                    CHECK(g.triangles_culled_backface == e.triangles_culled_backface);
                    CHECK(g.triangles_culled_degenerate == e.triangles_culled_degenerate);
                    CHECK(g.triangles_rasterized == e.triangles_rasterized);
                    // Every fate occurs.
                    CHECK(e.triangles_invalid > 0);
                    CHECK(e.triangles_culled_frustum > 0);
                    CHECK(e.triangles_culled_degenerate > 0);
                    CHECK(e.triangles_rasterized > 100);
                    CHECK(expected.setups.size() > e.triangles_rasterized);  // some to be clipped
                    if (cull.cull_back || cull.cull_front) CHECK(e.triangles_culled_backface > 0);
                }
            }
}

TEST_CASE("vertex projection gives the scalar outcodes and window positions on every path",
          "[raster][vertex]") {
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-30, 30), pick(0, 15);
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<glm::vec4> clip;
    // Random positions over many magnitudes, inside and outside the view
    // and the guard band, on both sides of w = 0; and the special ones.
    for (int i = 0; i < 20000; ++i) {
        glm::vec4 c;
        for (int k = 0; k < 4; ++k) c[k] = std::ldexp(unit(rng), exponent(rng) / (k == 3 ? 3 : 1));
        if (i % 3 == 0) c.w = std::abs(c.w);
        switch (pick(rng)) {
            case 0: c.x = nan; break;
            case 1: c.w = -inf; break;
            case 2: c = {0.0f, 0.0f, 0.0f, 0.0f}; break;  // the origin: w = 0, no window
            case 3: c.w = 0.0f; break;
            default: break;
        }
        clip.push_back(c);
    }
    // Window positions (512 + k / 512, 256 - k / 512) on the finest grid's
    // rounding ties, and the coarser grids' at every k of theirs.
    for (int k = -600; k <= 600; ++k)
        clip.push_back({std::ldexp(float(k), -18), std::ldexp(float(k), -17), 0.5f, 1.0f});
    // And left of and above the window, where the ties are negative: x + 1
    // and 1 - y are exact here too.
    for (int k = 1; k <= 600; ++k)
        clip.push_back(
            {-1.0f - std::ldexp(float(k), -18), 1.0f + std::ldexp(float(k), -17), 0.5f, 1.0f});
    for (const int bits : {8, 4, 1})
        for (const int first_row : {0, 37}) {
            Viewport viewport{1024, 512, 1, bits, first_row, 100};
            CAPTURE(bits, first_row);
            for (Isa isa : supported_isas()) {
                CAPTURE(isa_name(isa));
                // A count that is no multiple of four: the kernel pads its
                // last group.
                std::vector<WindowVertex> out(clip.size() - 3);
                kernels(isa).project_vertices(clip.data(), out.size(), viewport, out.data());
                for (size_t i = 0; i < out.size(); ++i) {
                    const WindowVertex want = scalar_projection(clip[i], viewport);
                    CAPTURE(i, clip[i].x, clip[i].y, clip[i].z, clip[i].w);
                    REQUIRE(out[i].user == want.user);
                    if (want.user & (kInvalid | kNoWindow) || band_code(want.user)) continue;
                    REQUIRE(out[i].x == want.x);
                    REQUIRE(out[i].y == want.y);
                    REQUIRE(std::bit_cast<uint32_t>(out[i].z) == std::bit_cast<uint32_t>(want.z));
                    REQUIRE(std::bit_cast<uint64_t>(out[i].w) == std::bit_cast<uint64_t>(want.w));
                    REQUIRE(std::bit_cast<uint64_t>(out[i].inv_w) ==
                            std::bit_cast<uint64_t>(want.inv_w));
                }
            }
        }
}
