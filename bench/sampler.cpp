// facet-bench-sampler: the texture sampler alone, on every path, in
// nanoseconds a sampled lane.
//
//     facet-bench-sampler [--runs N] [--isa sse2 avx2 avx512]
//
// Each workload is the UVs of every 4x4 block of a 1920x1080 frame, all 16
// lanes sampled: a floor seen at a grazing angle (every level of a
// trilinear chain, minified), the same floor near (magnified), and a
// surface facing the eye at about one texel a pixel. Each is sampled from
// a 1024x1024 colour texture (sRGB: 16-bit linear texels), a 1024x1024
// data texture (8-bit) and a 600x400 colour texture (no power of two), with
// each filter (anisotropic at 16x). A row gives the median and the fastest of --runs passes over
// the frame on one thread, and the scalar reference sampler's median
// (facet/texture.hpp) for scale. The sampler's share of a real frame is
// for perf on facet-bench (docs/performance.md).
#include "pipeline/kernels.hpp"  // core/src: the per-path kernels' table

#include <facet/isa.hpp>
#include <facet/texture.hpp>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

using namespace facet;

namespace {

constexpr int W = 1920, H = 1080, N = 16;

// A frame's worth of 4x4 blocks of UVs: u[16], v[16] each.
struct Workload {
    const char* name;
    std::vector<float> uv;  // per block: 16 u, then 16 v
};

// UVs of a plane y = 0 seen from height `eye` over `reach` units ahead,
// `repeats` texture repeats a unit: the ray through each pixel, exactly.
Workload floor_view(const char* name, float eye, float repeats) {
    Workload w{name, {}};
    for (int by = 0; by < H; by += 4)
        for (int bx = 0; bx < W; bx += 4) {
            float u[N], v[N];
            for (int i = 0; i < N; ++i) {
                const float sx = (float(bx + i % 4) + 0.5f) / H - 0.5f * W / H;
                const float sy = 0.5f - (float(by + i / 4) + 0.5f) / H;
                const float down = std::max(0.02f - sy, 1e-3f);  // horizon a little above centre
                const float distance = eye / down;
                u[i] = sx * distance * repeats;
                v[i] = distance * repeats;
            }
            w.uv.insert(w.uv.end(), u, u + N);
            w.uv.insert(w.uv.end(), v, v + N);
        }
    return w;
}

Workload facing(const char* name, float texels_per_pixel) {
    Workload w{name, {}};
    for (int by = 0; by < H; by += 4)
        for (int bx = 0; bx < W; bx += 4) {
            for (int i = 0; i < N; ++i)
                w.uv.push_back((bx + i % 4 + 0.5f) * texels_per_pixel / 1024);
            for (int i = 0; i < N; ++i)
                w.uv.push_back((by + i / 4 + 0.5f) * texels_per_pixel / 1024);
        }
    return w;
}

std::shared_ptr<Texture> make_texture(int width, int height, bool srgb) {
    auto t = std::make_shared<Texture>();
    t->width = width;
    t->height = height;
    t->srgb = srgb;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            t->texels.push_back({uint8_t(x * 7 ^ y * 3), uint8_t(x + y), uint8_t(x * y >> 4), 255});
    generate_mipmaps(*t);
    t->sampled();
    return t;
}

// Milliseconds of one pass of `sample` over every block of `w`.
template <class F>
double pass(const Workload& w, F&& sample) {
    alignas(64) float rgba[4 * N];
    float sink = 0.0f;
    const auto start = std::chrono::steady_clock::now();
    for (size_t b = 0; b < w.uv.size(); b += 2 * N) {
        sample(&w.uv[b], &w.uv[b + N], rgba);
        sink += rgba[5];
    }
    const auto end = std::chrono::steady_clock::now();
    if (sink == -1.0f) std::puts("");  // keeps the work
    return std::chrono::duration<double, std::milli>(end - start).count();
}

struct Timing {
    double median, fastest;
};

template <class F>
Timing time_runs(const Workload& w, int runs, F&& sample) {
    std::vector<double> ms;
    for (int r = 0; r < runs; ++r) ms.push_back(pass(w, sample));
    std::sort(ms.begin(), ms.end());
    return {ms[ms.size() / 2], ms.front()};
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"facet's texture sampler alone, on every path: nanoseconds a sampled lane."};
    int runs = 9;
    std::vector<std::string> isa_names;
    app.add_option("--runs", runs, "passes over each workload (median and fastest)")
        ->check(CLI::Range(1, 1000));
    app.add_option("--isa", isa_names,
                   "paths: sse2, avx2, avx512 (default: every one this CPU has)");
    CLI11_PARSE(app, argc, argv);
    std::vector<Isa> isas;
    for (const std::string& name : isa_names)
        isas.push_back(parse_isa(name).value_or(Isa::portable));
    if (isas.empty()) isas = supported_isas();

    const Workload workloads[] = {floor_view("floor, grazing", 1.0f, 0.5f),
                                  floor_view("floor, near", 4.0f, 0.05f),
                                  facing("facing, 1 texel/px", 1.0f)};
    const struct {
        const char* name;
        std::shared_ptr<Texture> texture;
    } textures[] = {{"1024^2 colour", make_texture(1024, 1024, true)},
                    {"1024^2 data", make_texture(1024, 1024, false)},
                    {"600x400 colour", make_texture(600, 400, true)}};
    const double lanes = double(W) * H;
    std::printf(
        "facet-bench-sampler: ns a lane over a %dx%d frame, 1 thread, %d runs "
        "(median / fastest); reference: the scalar sampler's median\n",
        W, H, runs);
    for (const Workload& w : workloads) {  // what reading the UVs alone costs
        const Timing x = time_runs(
            w, runs, [](const float* u, const float* v, float* rgba) { rgba[5] = u[0] + v[15]; });
        std::printf("%-20s reading the UVs alone: %.2f ns a lane (fastest)\n", w.name,
                    x.fastest * 1e6 / lanes);
    }
    std::printf("%-20s %-15s %-9s %-7s %9s %9s %9s\n", "workload", "texture", "filter", "path",
                "median", "fastest", "reference");
    for (const Workload& w : workloads)
        for (const auto& t : textures)
            for (const Filter filter : {Filter::nearest, Filter::bilinear, Filter::trilinear,
                                        Filter::anisotropic}) {
                const TextureBinding b{t.texture, filter, Wrap::repeat};  // anisotropic: 16x
                const Timing ref = time_runs(w, std::max(1, runs / 3),
                                             [&](const float* u, const float* v, float* rgba) {
                                                 sample_block(b, u, v, 0xFFFFu, rgba);
                                             });
                const char* const names[] = {"nearest", "bilinear", "trilinear", "aniso16x"};
                const char* filter_name = names[int(filter)];
                for (const Isa isa : isas) {
                    const Kernels& k = kernels(isa);
                    const Timing x =
                        time_runs(w, runs, [&](const float* u, const float* v, float* rgba) {
                            k.sample_block(b, u, v, 0xFFFFu, rgba);
                        });
                    std::printf("%-20s %-15s %-9s %-7s %9.2f %9.2f %9.2f\n", w.name, t.name,
                                filter_name, std::string(isa_name(isa)).c_str(),
                                x.median * 1e6 / lanes, x.fastest * 1e6 / lanes,
                                ref.median * 1e6 / lanes);
                }
            }
    return 0;
}
