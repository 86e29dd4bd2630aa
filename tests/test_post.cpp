// Screen passes (post-processing, ABI 1.4): each built-in pass against a
// double-precision reference of its own mathematics (the comment at the top
// of its source), on one thread and on several; the chain in a scene, in
// order, between the float frame and the 8-bit target; its errors, named
// by file and line; a pass written in C, hot-reloaded.
#include "support.hpp"

#include "frame/post.hpp"

#include <facet/error.hpp>
#include <facet/hot_reload.hpp>
#include <facet/plugin.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <thread>

using namespace facet;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

// An image in double precision, edges clamped when read.
struct Picture {
    int width = 0, height = 0;
    std::vector<glm::dvec4> pixels;

    Picture(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h), glm::dvec4(0.0)) {}
    glm::dvec4& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
    glm::dvec4 at(int x, int y) const {
        return pixels[size_t(std::clamp(y, 0, height - 1)) * size_t(width) +
                      size_t(std::clamp(x, 0, width - 1))];
    }
};

// Smooth HDR gradients up to `peak`, noise, and hard-edged shapes: what a
// filter must get right in flat areas, at edges and at the image's border.
Picture hdr_picture(int w, int h, double peak, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> noise(0.0, 0.2);
    Picture p(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double u = double(x) / w, v = double(y) / h;
            glm::dvec4 c(u, v, 0.5 * (u + v), 0.25 + 0.5 * u);
            if ((x - w / 3) * (x - w / 3) + (y - h / 2) * (y - h / 2) < h * h / 16)
                c = glm::dvec4(peak, 0.6 * peak, 0.2 * peak, 1.0);  // a bright disc
            if (x > 2 * w / 3 && y < h / 3) c = glm::dvec4(0.05, 0.1, 0.9, 1.0);
            p.at(x, y) = c + glm::dvec4(noise(rng), noise(rng), noise(rng), 0.0);
        }
    return p;
}

// Flat shapes in display range with no anti-aliasing: the jagged edges
// FXAA is for. (Flat, so that no decision of the float code and the double
// reference falls on a tie that rounding could break either way.)
Picture jagged_picture(int w, int h) {
    Picture p(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec4 c(0.1, 0.12, 0.15, 1.0);
            const double dx = x + 0.5 - 0.3 * w, dy = y + 0.5 - 0.5 * h;
            if (dx * dx + dy * dy < 0.09 * h * h) c = glm::dvec4(0.9, 0.8, 0.3, 1.0);  // disc
            // a rectangle turned by about 20 degrees
            const double rx = 0.94 * (x + 0.5 - 0.72 * w) + 0.34 * (y + 0.5 - 0.5 * h);
            const double ry = -0.34 * (x + 0.5 - 0.72 * w) + 0.94 * (y + 0.5 - 0.5 * h);
            if (std::abs(rx) < 0.14 * w && std::abs(ry) < 0.25 * h) c = glm::dvec4(0.2, 0.7, 0.4, 1.0);
            if (y > x / 3 + 0.8 * h) c = glm::dvec4(1.0, 1.0, 1.0, 1.0);  // a shallow slope
            p.at(x, y) = c;
        }
    return p;
}

MaterialParam number(const std::string& name, double v, bool integer = false) {
    MaterialParam p;
    p.name = name;
    p.numbers = {v};
    p.is_integer = integer;
    return p;
}
MaterialParam word(const std::string& name, const std::string& w) {
    MaterialParam p;
    p.name = name;
    p.kind = MaterialParam::Kind::word;
    p.word = w;
    return p;
}

// The built-in pass `name` with `params`, run on `input` through the
// core's post chain with `threads` threads.
Picture run_pass(const std::string& name, const std::vector<MaterialParam>& params,
                 const Picture& input, int threads) {
    PluginRegistry registry;
    TextureCache textures;
    PostPass pass;
    pass.name = name;
    pass.file = "test";
    pass.params = params;
    pass.plugin = registry.get(name);
    pass.block = bind_params(params, *pass.plugin, pass.file, textures).block;
    Framebuffer frame(input.width, input.height, ColorFormat::rgba32f);
    frame.clear(glm::vec4(0.0f), 0.0f);
    for (int y = 0; y < input.height; ++y)
        for (int x = 0; x < input.width; ++x) frame.set_pixel(x, y, glm::vec4(input.at(x, y)));
    Framebuffer target(input.width, input.height, ColorFormat::rgba32f);
    Pipeline pipeline(threads);
    PostChain chain;
    FrameStats stats;
    chain.run({pass}, frame, target, RenderSettings{}, 0.0f, pipeline, stats);
    REQUIRE(stats.post_passes == 1);
    Picture out(input.width, input.height);
    for (int y = 0; y < input.height; ++y)
        for (int x = 0; x < input.width; ++x) out.at(x, y) = glm::dvec4(target.pixel(x, y));
    return out;
}

// The largest difference of a channel, relative to the reference's size
// where that is above 1 (NaN where one side only is NaN; none where both
// are, or both are the same infinity).
double max_error(const Picture& got, const Picture& want) {
    double worst = 0.0;
    for (size_t i = 0; i < want.pixels.size(); ++i)
        for (int c = 0; c < 4; ++c) {
            const double a = got.pixels[i][c], b = want.pixels[i][c];
            if (a == b || (std::isnan(a) && std::isnan(b))) continue;
            const double e = std::abs(a - b) / std::max(1.0, std::abs(b));
            worst = std::isnan(e) || std::isinf(e) ? std::numeric_limits<double>::infinity()
                                                   : std::max(worst, e);
        }
    return worst;
}

// `p` with a NaN pixel and an infinite one: each pass keeps the harm local.
Picture with_bad_pixels(Picture p) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    p.at(5, 5) = glm::dvec4(nan, 0.5, 0.5, 1.0);
    p.at(p.width - 9, p.height - 7) = glm::dvec4(inf, inf, 0.25, 1.0);
    return p;
}

// Checks the pass on 1 and 2 threads against `want`, and that `want` is not
// the input (a pass that did nothing would fail).
void check_pass(const std::string& name, const std::vector<MaterialParam>& params,
                const Picture& input, const Picture& want, double tolerance) {
    CAPTURE(name);
    REQUIRE(max_error(input, want) > 100 * tolerance);
    const Picture one = run_pass(name, params, input, 1);
    CHECK(max_error(one, want) <= tolerance);
    const Picture two = run_pass(name, params, input, 2);
    CHECK(std::memcmp(two.pixels.data(), one.pixels.data(),
                      one.pixels.size() * sizeof one.pixels[0]) == 0);  // threads change nothing
}

// ---- the references, in double ------------------------------------------------

Picture box_reference(const Picture& in, int r) {
    Picture out(in.width, in.height);
    const double n = double(2 * r + 1) * double(2 * r + 1);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
            glm::dvec4 sum(0.0);
            for (int j = -r; j <= r; ++j)
                for (int i = -r; i <= r; ++i) {
                    glm::dvec4 v = in.at(x + i, y + j);
                    for (int c = 0; c < 4; ++c) v[c] = std::isfinite(v[c]) ? v[c] : 0.0;
                    sum += v;  // a value that is not finite counts as 0
                }
            out.at(x, y) = sum / n;
        }
    return out;
}

std::vector<double> gaussian(double sigma) {
    const int r = std::max(1, int(std::ceil(3.0 * sigma)));
    std::vector<double> w;
    double sum = 0.0;
    for (int k = -r; k <= r; ++k) sum += w.emplace_back(std::exp(-k * k / (2.0 * sigma * sigma)));
    for (double& v : w) v /= sum;
    return w;
}

Picture gaussian_reference(const Picture& in, double sigma) {
    const std::vector<double> w = gaussian(sigma);
    const int r = int(w.size() / 2);
    Picture out(in.width, in.height);
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
            glm::dvec4 sum(0.0);
            for (int j = -r; j <= r; ++j)
                for (int i = -r; i <= r; ++i)
                    sum += w[size_t(j + r)] * w[size_t(i + r)] * in.at(x + i, y + j);
            out.at(x, y) = sum;
        }
    return out;
}

Picture tonemap_reference(const Picture& in, double exposure, const std::string& curve) {
    Picture out = in;
    for (glm::dvec4& c : out.pixels)
        for (int k = 0; k < 3; ++k) {
            const double s = c[k] * std::exp2(exposure);
            const double x = s > 0.0 ? s : 0.0;  // NaN: 0
            if (std::isinf(x))
                c[k] = 1.0;
            else if (curve == "aces")
                c[k] = std::min(1.0, x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14));
            else if (curve == "reinhard")
                c[k] = x / (1.0 + x);
            else
                c[k] = std::min(x, 1.0);
        }
    return out;
}

Picture half_of(const Picture& in, const std::function<glm::dvec4(glm::dvec4)>& f) {
    Picture out((in.width + 1) / 2, (in.height + 1) / 2);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const int x0 = std::min(2 * x, in.width - 1), x1 = std::min(2 * x + 1, in.width - 1);
            const int y0 = std::min(2 * y, in.height - 1), y1 = std::min(2 * y + 1, in.height - 1);
            out.at(x, y) =
                0.25 * (f(in.at(x0, y0)) + f(in.at(x1, y0)) + f(in.at(x0, y1)) + f(in.at(x1, y1)));
        }
    return out;
}

// `to` += scale * `from` (half its size), read bilinearly at pixel centres.
void add_upsampled(const Picture& from, Picture& to, double scale) {
    const auto tap = [](int i, int n, int& i0, int& i1, double& t) {
        const double p = std::clamp((i + 0.5) * 0.5 - 0.5, 0.0, double(n - 1));
        i0 = int(p);
        i1 = std::min(i0 + 1, n - 1);
        t = p - i0;
    };
    for (int y = 0; y < to.height; ++y)
        for (int x = 0; x < to.width; ++x) {
            int x0, x1, y0, y1;
            double tx, ty;
            tap(x, from.width, x0, x1, tx);
            tap(y, from.height, y0, y1, ty);
            const glm::dvec4 top = glm::mix(from.at(x0, y0), from.at(x1, y0), tx);
            const glm::dvec4 bottom = glm::mix(from.at(x0, y1), from.at(x1, y1), tx);
            to.at(x, y) += scale * glm::mix(top, bottom, ty);
        }
}

Picture bloom_reference(const Picture& in, double threshold, double intensity, int levels) {
    const auto bright = [&](glm::dvec4 c) {
        const double l = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
        if (!(l > threshold) || !std::isfinite(l)) return glm::dvec4(0.0);
        return glm::dvec4(glm::dvec3(c) * ((l - threshold) / l), 0.0);
    };
    const auto same = [](glm::dvec4 c) { return c; };
    std::vector<Picture> level;
    level.push_back(half_of(in, bright));
    while (int(level.size()) < levels && (level.back().width > 1 || level.back().height > 1))
        level.push_back(half_of(level.back(), same));
    for (Picture& l : level) l = gaussian_reference(l, 1.5);
    for (size_t i = level.size() - 1; i > 0; --i) add_upsampled(level[i], level[i - 1], 1.0);
    Picture out = in;
    add_upsampled(level[0], out, intensity);
    return out;
}

struct FxaaSettings {
    double edge_threshold = 0.125, edge_threshold_min = 0.0312, subpixel = 0.75;
    int search_steps = 12;
};

// shaders/post/fxaa.cpp, steps 1 to 7, in double.
Picture fxaa_reference(const Picture& in, const FxaaSettings& p) {
    const auto L = [&](int x, int y) {
        const glm::dvec4 c = in.at(x, y);
        return std::sqrt(std::clamp(0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b, 0.0, 1.0));
    };
    Picture out = in;
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
            const double m = L(x, y), n = L(x, y - 1), s = L(x, y + 1), w = L(x - 1, y),
                         e = L(x + 1, y);
            const double hi = std::max({m, n, s, w, e}), lo = std::min({m, n, s, w, e});
            const double range = hi - lo;
            if (range < std::max(p.edge_threshold_min, p.edge_threshold * hi)) continue;
            const double rows = 2 * std::abs(n - 2 * m + s) +
                                std::abs(L(x - 1, y - 1) - 2 * w + L(x - 1, y + 1)) +
                                std::abs(L(x + 1, y - 1) - 2 * e + L(x + 1, y + 1));
            const double columns = 2 * std::abs(w - 2 * m + e) +
                                   std::abs(L(x - 1, y - 1) - 2 * n + L(x + 1, y - 1)) +
                                   std::abs(L(x - 1, y + 1) - 2 * s + L(x + 1, y + 1));
            const glm::ivec2 normal = rows >= columns ? glm::ivec2(0, 1) : glm::ivec2(1, 0);
            const double back = L(x - normal.x, y - normal.y), ahead = L(x + normal.x, y + normal.y);
            const glm::ivec2 across = std::abs(back - m) >= std::abs(ahead - m) ? -normal : normal;
            const glm::ivec2 along(normal.y, normal.x);
            const double side = L(x + across.x, y + across.y);
            const double gradient = std::abs(side - m), average = 0.5 * (side + m);
            double deltas[2] = {0.0, 0.0}, distances[2] = {0.0, 0.0};
            for (int way = 0; way < 2; ++way) {
                const int sign = way == 0 ? -1 : 1;
                distances[way] = p.search_steps + 1;
                for (int i = 1; i <= p.search_steps; ++i) {
                    const int px = x + sign * i * along.x, py = y + sign * i * along.y;
                    deltas[way] = 0.5 * (L(px, py) + L(px + across.x, py + across.y)) - average;
                    if (std::abs(deltas[way]) >= 0.25 * gradient) {
                        distances[way] = i;
                        break;
                    }
                }
            }
            const double nearer = std::min(distances[0], distances[1]);
            const double delta = distances[0] < distances[1] ? deltas[0] : deltas[1];
            const double edge = (delta < 0.0) != (m < average)
                                    ? 0.5 - nearer / (distances[0] + distances[1])
                                    : 0.0;
            const double mean = (2 * (n + s + w + e) + L(x - 1, y - 1) + L(x + 1, y - 1) +
                                 L(x - 1, y + 1) + L(x + 1, y + 1)) / 12.0;
            const double t = std::clamp(std::abs(mean - m) / range, 0.0, 1.0);
            const double smooth = (3.0 - 2.0 * t) * t * t;
            const double offset = std::max(edge, p.subpixel * smooth * smooth);
            if (offset <= 0.0) continue;
            const glm::dvec4 c = in.at(x, y);
            out.at(x, y) = c + offset * (in.at(x + across.x, y + across.y) - c);
        }
    return out;
}

}  // namespace

TEST_CASE("box and Gaussian blurs match their double-precision sums", "[post]") {
    const Picture input = hdr_picture(61, 37, 8.0, 1);
    const Picture bad = with_bad_pixels(input);
    for (const int r : {1, 3, 20}) {
        CAPTURE(r);
        check_pass("box_blur", {number("radius", r, true)}, bad, box_reference(bad, r), 2e-6);
    }
    for (const double sigma : {0.6, 2.0, 7.5}) {
        CAPTURE(sigma);
        check_pass("gaussian_blur", {number("sigma", sigma)}, input,
                   gaussian_reference(input, sigma), 2e-6);
    }
}

TEST_CASE("tone mapping follows its curves: ACES fitted, Reinhard, clamp", "[post]") {
    Picture input = with_bad_pixels(hdr_picture(33, 17, 40.0, 2));
    input.at(0, 0) = glm::dvec4(-1.0, 0.0, 1e6, 0.5);  // below 0, 0, far above 1
    for (const std::string curve : {"aces", "reinhard", "clamp"})
        for (const double exposure : {0.0, -1.5, 2.0}) {
            CAPTURE(curve, exposure);
            check_pass("tonemap", {word("operator", curve), number("exposure", exposure)}, input,
                       tonemap_reference(input, exposure, curve), 1e-6);
        }
}

TEST_CASE("bloom: bright pass, pyramid, blur and upsampling as documented", "[post]") {
    const Picture input = with_bad_pixels(hdr_picture(75, 43, 12.0, 3));
    for (const int levels : {1, 3, 8}) {
        CAPTURE(levels);
        check_pass("bloom",
                   {number("threshold", 1.2), number("intensity", 0.3),
                    number("levels", levels, true)},
                   input, bloom_reference(input, 1.2, 0.3, levels), 2e-6);
    }
}

TEST_CASE("FXAA blends across the edges it finds, as its steps say", "[post]") {
    const Picture input = jagged_picture(96, 64);
    check_pass("fxaa", {}, input, fxaa_reference(input, FxaaSettings{}), 1e-5);
    FxaaSettings wide;
    wide.edge_threshold = 0.05;
    wide.subpixel = 1.0;
    wide.search_steps = 3;
    check_pass("fxaa",
               {number("edge_threshold", 0.05), number("subpixel", 1.0),
                number("search_steps", 3, true)},
               input, fxaa_reference(input, wide), 1e-5);
}

TEST_CASE("a scene's post chain runs in order between the float frame and its target",
          "[post]") {
    test::TempDir dir("post");
    dir.write("quad.obj", test::kQuadObj);
    const auto scene_with = [&](const std::string& post, const std::string& render) {
        dir.write("scene.yaml",
                  "render: {size: [8, 8]" + render + "}\n"
                  "objects:\n  - {mesh: quad.obj, material: {shader: unlit, params: "
                  "{base_color: [2, 0.5, 0.25, 1]}}}\n" + post);
        PluginRegistry registry;
        Scene scene = load_scene(dir.path / "scene.yaml", registry);
        Renderer renderer(2);
        Framebuffer fb;
        const FrameStats stats = renderer.render(scene, fb);
        return std::make_pair(fb.pixel(4, 4), stats);
    };
    // clamp, then Reinhard: 2 -> 1 -> 0.5; the other way: 2 -> 2/3 -> 2/3.
    const auto [a, a_stats] = scene_with(
        "post:\n  - {pass: tonemap, operator: clamp}\n  - {pass: tonemap, operator: reinhard}\n",
        ", color_format: rgba32f");
    CHECK(a.r == Approx(0.5).epsilon(1e-6));
    CHECK(a.g == Approx(0.5 / 1.5).epsilon(1e-6));
    CHECK(a_stats.post_passes == 2);
    const auto [b, b_stats] = scene_with(
        "post:\n  - {pass: tonemap, operator: reinhard}\n  - {pass: tonemap, operator: clamp}\n",
        ", color_format: rgba32f");
    CHECK(b.r == Approx(2.0 / 3.0).epsilon(1e-6));
    // Into an 8-bit target, with MSAA: the chain still sees the float frame.
    const auto [c, c_stats] = scene_with("post:\n  - {pass: tonemap, operator: reinhard}\n",
                                         ", msaa: 4");
    CHECK(c.r == srgb8_to_linear(linear_to_srgb8(2.0f / 3.0f)));
    CHECK(c.b == srgb8_to_linear(linear_to_srgb8(0.25f / 1.25f)));
    // render: {post: false}: no chain, and the frame goes straight to the target.
    const auto [d, d_stats] = scene_with("post:\n  - {pass: tonemap, operator: reinhard}\n",
                                         ", color_format: rgba32f, post: false");
    CHECK(d.r == 2.0f);
    CHECK(d_stats.post_passes == 0);
}

TEST_CASE("post chain errors name the file and line", "[post][config]") {
    test::TempDir dir("post-errors");
    dir.write("quad.obj", test::kQuadObj);
    const auto error_of = [&](const std::string& post, const std::string& material = "unlit") {
        dir.write("scene.yaml", "objects:\n  - {mesh: quad.obj, material: {shader: " + material +
                                    "}}\npost:\n" + post);
        PluginRegistry registry;
        try {
            load_scene(dir.path / "scene.yaml", registry);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    using Catch::Matchers::Contains;
    CHECK_THAT(error_of("  - {pass: no_such_pass}\n"),
               Contains("scene.yaml:4") && Contains("no_such_pass"));
    CHECK_THAT(error_of("  - {pass: phong}\n"),
               Contains("scene.yaml:4") && Contains("is a shader, not a screen pass"));
    CHECK_THAT(error_of("  - {pass: tonemap}\n", "bloom"),
               Contains("scene.yaml:2") && Contains("is a screen pass, not a shader"));
    CHECK_THAT(error_of("  - {threshold: 1}\n"), Contains("scene.yaml:4") && Contains("pass"));
    CHECK_THAT(error_of("  - {pass: tonemap, operator: filmic}\n"),
               Contains("scene.yaml:4") && Contains("'filmic'") &&
                   Contains("aces, reinhard, clamp"));
    CHECK_THAT(error_of("  - {pass: tonemap, operator: 2}\n"),
               Contains("scene.yaml:4") && Contains("one of its names"));
    CHECK_THAT(error_of("  - {pass: bloom, treshold: 1}\n"),
               Contains("scene.yaml:4") && Contains("'treshold'") && Contains("threshold (float)"));
    CHECK_THAT(error_of("  - {pass: bloom, levels: 9}\n"),
               Contains("scene.yaml:4") && Contains("outside 1 .. 8"));
    CHECK_THAT(error_of("  - {pass: gaussian_blur, sigma: [1, 2]}\n"),
               Contains("scene.yaml:4") && Contains("needs a number"));
    CHECK_THAT(error_of("  {pass: bloom}\n"), Contains("scene.yaml:4") && Contains("sequence"));
}

TEST_CASE("a screen pass's descriptor is checked like a shader's", "[post][plugin]") {
    static const facet_param_desc choice =
        sdk::choice("operator", 0, 0, "which one");
    const auto refusal = [](const facet_plugin_desc& d) {
        try {
            ShaderPlugin::from_descriptor(&d, "test");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    facet_pass_desc pass = {sizeof(facet_pass_desc), [](const facet_pass_frame*) {}};
    facet_plugin_desc d{};
    d.abi_major = FACET_ABI_MAJOR;
    d.abi_minor = FACET_ABI_MINOR;
    d.struct_size = sizeof d;
    d.name = "probe";
    d.pass = &pass;
    CHECK(refusal(d) == "accepted");
    CHECK(ShaderPlugin::from_descriptor(&d, "test")->is_post());
    using Catch::Matchers::Contains;
    facet_pass_desc no_run = {sizeof(facet_pass_desc), nullptr};
    facet_plugin_desc without = d;
    without.pass = &no_run;
    CHECK_THAT(refusal(without), Contains("the screen pass has no function"));
    facet_pass_desc short_pass = {4, pass.run};
    facet_plugin_desc small = d;
    small.pass = &short_pass;
    CHECK_THAT(refusal(small), Contains("the screen pass record is 4 bytes"));
    // A choice needs its names, none empty or twice, and a default among them.
    facet_plugin_desc chooses = d;
    chooses.schema = {1, 4, &choice, nullptr};
    CHECK_THAT(refusal(chooses), Contains("give it no names"));
    for (const char* names : {"a||b", "a|b|a"}) {
        const char* table[] = {names};
        chooses.schema.choices = table;
        CHECK_THAT(refusal(chooses), Contains("operator"));
    }
    const char* good[] = {"a|b"};
    chooses.schema.choices = good;
    CHECK(refusal(chooses) == "accepted");
    facet_param_desc far = choice;
    far.default_value[0] = 2;
    chooses.schema.params = &far;
    CHECK_THAT(refusal(chooses), Contains("not the index of one of 'a|b'"));
    // A texture parameter is a shader's only.
    facet_param_desc texture = sdk::texture("image", 0, -1, false);
    facet_plugin_desc textured = d;
    textured.schema = {1, 4, &texture, nullptr};
    CHECK_THAT(refusal(textured), Contains("a screen pass takes no textures"));
}

TEST_CASE("a screen pass written in C is hot-reloaded; a crashing version is refused",
          "[post][reload]") {
    test::TempDir dir("post-reload");
    fs::create_directories(dir.path / "plugins");
    REQUIRE(test::compile_post_plugin(dir.path / "plugins" / "halve.so", "halve", "-DSCALE=0.5f"));
    dir.write("quad.obj", test::kQuadObj);
    const auto scene_text = [](int gain) {
        return "render: {size: [16, 16], color_format: rgba32f}\nplugin_paths: [plugins]\n"
               "objects:\n  - {mesh: quad.obj, material: {shader: unlit, params: {base_color: "
               "[1, 1, 1, 1]}}}\npost:\n  - {pass: halve, gain: " + std::to_string(gain) + "}\n";
    };
    dir.write("scene.yaml", scene_text(1));
    PluginRegistry registry;
    Scene scene = load_scene(dir.path / "scene.yaml", registry);
    HotReload::Options options;
    options.settle = 30ms;
    HotReload reload(registry, scene, options);
    Renderer renderer(2);
    const auto red = [&] {
        Framebuffer fb;
        renderer.render(scene, fb);
        return fb.pixel(8, 8).r;
    };
    const auto next_event = [&] {
        for (int i = 0; i < 4000; ++i) {
            reload.update();
            std::vector<ReloadEvent> events = reload.take_events();
            if (!events.empty()) return events.front();
            std::this_thread::sleep_for(5ms);
        }
        FAIL("no reload event within 20 s");
        return ReloadEvent{};
    };
    CHECK(red() == 0.5f);
    REQUIRE(test::compile_post_plugin(dir.path / "plugins" / "halve.so", "halve", "-DSCALE=0.25f"));
    ReloadEvent e = next_event();
    CHECK(e.kind == ReloadEvent::Kind::plugin_reloaded);
    CHECK_THAT(e.message, Catch::Matchers::Contains("screen pass 'halve' (1 pass(es)"));
    CHECK(red() == 0.25f);
    REQUIRE(test::compile_post_plugin(dir.path / "plugins" / "halve.so", "halve",
                                      "-DFAULT_IN_POST"));
    e = next_event();
    CHECK(e.kind == ReloadEvent::Kind::plugin_refused);
    CHECK_THAT(e.message, Catch::Matchers::Contains("in its post function"));
    CHECK(red() == 0.25f);  // the last good version keeps running
    dir.write("scene.yaml", scene_text(2));
    e = next_event();
    CHECK(e.kind == ReloadEvent::Kind::config_reloaded);
    CHECK(red() == 0.5f);
}
