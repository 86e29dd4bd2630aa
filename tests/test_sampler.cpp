// The per-path texture sampler (core/src/pipeline/sampler.hpp) against the
// scalar reference sampler (facet/texture.hpp): every filter, wrap and
// format, sizes with and without powers of two, coordinates far outside the
// texture and NaN, random masks; within one 8-bit code of the reference on
// every path, and the same floats on every path.
#include "pipeline/kernels.hpp"

#include <facet/framebuffer.hpp>
#include <facet/isa.hpp>
#include <facet/texture.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <vector>

using namespace facet;

namespace {

constexpr int N = 16;

std::shared_ptr<Texture> noise_texture(int width, int height, bool srgb, uint32_t seed) {
    auto t = std::make_shared<Texture>();
    t->width = width;
    t->height = height;
    t->srgb = srgb;
    std::mt19937 random(seed);
    for (int i = 0; i < width * height; ++i)
        t->texels.push_back(
            {uint8_t(random()), uint8_t(random()), uint8_t(random()), uint8_t(random())});
    generate_mipmaps(*t);
    return t;
}

// A channel as the 8-bit code it would be stored as: sRGB for colour,
// linear for data and alpha.
int code(float v, bool srgb) {
    if (srgb) return linear_to_srgb8(v);
    return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

// One block of coordinates: a patch of a plane under a random affine map,
// scaled from magnified to far minified, now and then moved far away or
// made NaN.
struct UvBlock {
    float u[N], v[N];
    uint32_t mask;
};

UvBlock random_block(std::mt19937& random) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const float scale = std::exp2(unit(random) * 6.0f) / 64.0f;  // 1/4096 .. 1 a pixel
    const float du[2] = {unit(random) * scale, unit(random) * scale};
    const float dv[2] = {unit(random) * scale, unit(random) * scale};
    float u0 = unit(random) * 3.0f, v0 = unit(random) * 3.0f;
    const int far = int(random() % 16);
    if (far == 0) u0 += 1e6f;
    if (far == 1) v0 -= 3e7f;
    UvBlock b;
    for (int i = 0; i < N; ++i) {
        const float x = float(i % 4), y = float(i / 4);
        b.u[i] = u0 + x * du[0] + y * du[1];
        b.v[i] = v0 + x * dv[0] + y * dv[1];
    }
    if (far == 2) b.u[random() % N] = std::numeric_limits<float>::quiet_NaN();
    if (far == 3) b.v[random() % N] = std::numeric_limits<float>::infinity();
    b.mask = random() % 4 == 0 ? 0xFFFFu : uint32_t(random() & 0xFFFF);
    return b;
}

}  // namespace

TEST_CASE("the per-path sampler matches the reference to one 8-bit code", "[texture][isa]") {
    const std::shared_ptr<Texture> textures[] = {
        noise_texture(64, 32, true, 1),  noise_texture(37, 23, true, 2),
        noise_texture(16, 16, false, 3), noise_texture(50, 7, false, 4),
        noise_texture(1, 1, true, 5),    noise_texture(1, 9, false, 6)};
    std::mt19937 random(7);
    int most = 1;  // anisotropic's cap, 2 to 16 in turn
    for (const auto& texture : textures)
        for (const Filter filter :
             {Filter::nearest, Filter::bilinear, Filter::trilinear, Filter::anisotropic})
            for (const Wrap wrap : {Wrap::repeat, Wrap::clamp, Wrap::mirror}) {
                most = most % kMaxAnisotropy + 1;
                INFO(texture->width << "x" << texture->height << (texture->srgb ? " sRGB" : "")
                                    << ", filter " << int(filter) << ", wrap " << int(wrap)
                                    << ", anisotropy " << most);
                const TextureBinding b{texture, filter, wrap, {}, 0, std::max(most, 2)};
                int worst = 0, paths_differ = 0, outside_mask = 0;
                for (int k = 0; k < 200; ++k) {
                    const UvBlock block = random_block(random);
                    float expected[4 * N];
                    sample_block(b, block.u, block.v, block.mask, expected);
                    std::vector<float> first;
                    for (const Isa isa : supported_isas()) {
                        float got[4 * N];
                        kernels(isa).sample_block(b, block.u, block.v, block.mask, got);
                        if (first.empty()) first.assign(got, got + 4 * N);
                        paths_differ += std::memcmp(first.data(), got, sizeof got) != 0;
                        for (int i = 0; i < 4 * N; ++i) {
                            const bool colour = texture->srgb && i < 3 * N;
                            worst = std::max(
                                worst, std::abs(code(got[i], colour) - code(expected[i], colour)));
                            outside_mask += !(block.mask >> (i % N) & 1u) && got[i] != 0.0f;
                        }
                    }
                }
                CHECK(worst <= 1);
                CHECK(paths_differ == 0);
                CHECK(outside_mask == 0);
            }
}

TEST_CASE("the per-path sampler takes a level of detail per lane", "[texture][isa]") {
    const auto texture = noise_texture(64, 64, true, 8);
    const TextureBinding b{texture, Filter::trilinear, Wrap::repeat};
    std::mt19937 random(9);
    std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f), level(-1.0f, 8.0f);
    int worst = 0;
    for (int k = 0; k < 200; ++k) {
        float u[N], v[N], lod[N];
        for (int i = 0; i < N; ++i)
            u[i] = coordinate(random), v[i] = coordinate(random), lod[i] = level(random);
        if (k == 0) lod[3] = std::numeric_limits<float>::quiet_NaN();  // read as level 0
        float coords[2 * N];
        std::copy(u, u + N, coords);
        std::copy(v, v + N, coords + N);
        for (const Isa isa : supported_isas()) {
            float got[4 * N];
            kernels(isa).sample_lanes(b, coords, lod, nullptr, N, 0xFFFFu, got);
            for (int i = 0; i < N; ++i) {
                const glm::vec4 expected = sample_lod(b, {u[i], v[i]}, lod[i]);
                for (int c = 0; c < 4; ++c)
                    worst = std::max(
                        worst, std::abs(code(got[c * N + i], c < 3) - code(expected[c], c < 3)));
            }
        }
    }
    CHECK(worst <= 1);
}

TEST_CASE("the per-path sampler reads an unbound texture as white", "[texture][isa]") {
    const TextureBinding none{};
    float u[N] = {}, v[N] = {};
    for (const Isa isa : supported_isas()) {
        float got[4 * N];
        kernels(isa).sample_block(none, u, v, 0x00F0u, got);
        for (int i = 0; i < 4 * N; ++i) CHECK(got[i] == ((0x00F0u >> (i % N) & 1u) ? 1.0f : 0.0f));
    }
}

namespace {

// A cube of six n x n faces of noise over a distinct colour each.
std::shared_ptr<Texture> noise_cube(int n, bool srgb, uint32_t seed) {
    auto t = std::make_shared<Texture>();
    t->width = t->height = n;
    t->faces = 6;
    t->srgb = srgb;
    std::mt19937 random(seed);
    for (int f = 0; f < 6; ++f)
        for (int i = 0; i < n * n; ++i)
            t->texels.push_back({uint8_t(40 * f + random() % 40), uint8_t(random()),
                                 uint8_t(255 - 40 * f - random() % 40), uint8_t(random())});
    generate_mipmaps(*t);
    return t;
}

}  // namespace

TEST_CASE("cube maps: each face by the direction's largest component, as GL and Vulkan lay "
          "them out",
          "[texture][cube]") {
    glm::vec2 uv;
    CHECK(cube_face({2, 0.5f, -1}, uv) == 0);
    CHECK(uv == glm::vec2((1.0f / 2 + 1) / 2, (-0.5f / 2 + 1) / 2));  // sc = -z, tc = -y
    CHECK(cube_face({-2, 0, 0}, uv) == 1);
    CHECK(cube_face({0.5f, 3, 1}, uv) == 2);
    CHECK(uv == glm::vec2((0.5f / 3 + 1) / 2, (1.0f / 3 + 1) / 2));  // sc = x, tc = z
    CHECK(cube_face({0, -3, 0}, uv) == 3);
    CHECK(cube_face({0, 0, 1}, uv) == 4);
    CHECK(uv == glm::vec2(0.5f, 0.5f));
    CHECK(cube_face({0, 0, -1}, uv) == 5);
    CHECK(cube_face({1, 1, 1}, uv) == 0);  // ties: x before y before z
    CHECK(cube_face({0, 0, 0}, uv) == 1);  // no direction: as ties go, a face's middle
    CHECK(uv == glm::vec2(0.5f));
}

TEST_CASE("the per-path sampler reads cube maps as the reference does", "[texture][cube][isa]") {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), level(-1.0f, 6.0f);
    for (const bool srgb : {true, false})
        for (const Filter filter :
             {Filter::nearest, Filter::bilinear, Filter::trilinear, Filter::anisotropic}) {
            INFO((srgb ? "sRGB" : "linear") << ", filter " << int(filter));
            const TextureBinding b{noise_cube(16, srgb, 12), filter, Wrap::repeat};
            int worst = 0;
            for (int k = 0; k < 300; ++k) {
                float coords[3 * N], lod[N];
                for (int i = 0; i < N; ++i) {
                    for (int c = 0; c < 3; ++c) coords[c * N + i] = unit(random);
                    lod[i] = level(random);
                }
                if (k == 0) coords[0] = coords[N] = coords[2 * N] = 0.0f;  // no direction
                const uint32_t count = k % 3 == 0 ? 4 : k % 3 == 1 ? 8 : 16;
                float packed[3 * N];  // count lanes a component, as the service takes them
                for (int c = 0; c < 3; ++c)
                    std::copy(coords + c * N, coords + c * N + count, packed + c * count);
                for (const Isa isa : supported_isas()) {
                    float got[4 * N];
                    kernels(isa).sample_lanes(b, packed, lod, nullptr, count, 0xFFFFu, got);
                    for (uint32_t i = 0; i < count; ++i) {
                        const glm::vec3 d(coords[i], coords[N + i], coords[2 * N + i]);
                        const glm::vec4 want = sample_cube(b, d, lod[i]);
                        for (int c = 0; c < 4; ++c)
                            worst = std::max(worst, std::abs(code(got[c * count + i], srgb && c < 3) -
                                                             code(want[c], srgb && c < 3)));
                    }
                }
            }
            CHECK(worst <= 1);
        }
}

// ---- anisotropic filtering

TEST_CASE("anisotropic footprints: samples by the axes' ratio up to the cap, each at its share's "
          "level",
          "[texture][anisotropic]") {
    const auto t = noise_texture(64, 32, false, 20);
    const auto footprint = [&](glm::vec2 dx_texels, glm::vec2 dy_texels, int most) {
        const glm::vec2 size(64.0f, 32.0f);
        return anisotropic_footprint(*t, dx_texels / size, dy_texels / size, most);
    };
    AnisotropicFootprint f = footprint({8, 0}, {0, 1}, 16);  // 8:1 along x
    CHECK(f.samples == 8);
    CHECK(f.lod == 0.0f);
    CHECK(f.step == glm::vec2(8.0f / 64.0f, 0.0f));
    f = footprint({8, 0}, {0, 1}, 4);  // capped: each sample covers 2 texels
    CHECK(f.samples == 4);
    CHECK(f.lod == Approx(1.0f).margin(1e-6));
    f = footprint({0, 1.5f}, {6, 0}, 16);  // 4:1 along y, at 1.5 texels across
    CHECK(f.samples == 4);
    CHECK(f.lod == Approx(std::log2(1.5f)).margin(1e-6));
    CHECK(f.step == glm::vec2(6.0f / 64.0f, 0.0f));
    f = footprint({3, 4}, {-2, 1.5f}, 16);  // 5 : 2.5 texels, turned: 2 samples
    CHECK(f.samples == 2);
    CHECK(f.lod == Approx(std::log2(2.5f)).margin(1e-6));
    CHECK(footprint({2.6f, 0}, {0, 1}, 16).samples == 3);  // a fraction rounds up
    CHECK(footprint({4, 0}, {4, 0}, 16).samples == 1);     // a line: both axes alike
    f = footprint({4, 0}, {0, 0}, 16);  // no width at all: the cap
    CHECK(f.samples == 16);
    CHECK(f.lod == -2.0f);  // 4/16 texels a sample: magnified (read at level 0)
    f = footprint({0, 0}, {0, 0}, 16);  // no footprint: one sample at level 0
    CHECK(f.samples == 1);
    CHECK(f.lod == 0.0f);
    f = footprint({std::nanf(""), 0}, {0, 1}, 16);
    CHECK(f.samples == 1);
    CHECK(f.lod == 0.0f);
}

TEST_CASE("the per-path sampler filters given derivatives as the reference does",
          "[texture][anisotropic][isa]") {
    std::mt19937 random(21);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (const Filter filter : {Filter::trilinear, Filter::anisotropic})
        for (const Wrap wrap : {Wrap::repeat, Wrap::clamp, Wrap::mirror}) {
            INFO("filter " << int(filter) << ", wrap " << int(wrap));
            const TextureBinding b{noise_texture(64, 48, true, 22), filter, wrap};
            int worst = 0, paths_differ = 0;
            for (int k = 0; k < 200; ++k) {
                const uint32_t count = k % 3 == 0 ? 5 : k % 3 == 1 ? 8 : 16;
                float coords[2 * N], lod[N], grads[4 * N];
                for (uint32_t i = 0; i < count; ++i) {
                    coords[i] = unit(random) * 2.0f, coords[count + i] = unit(random) * 2.0f;
                    lod[i] = unit(random) * 4.0f + 2.0f;
                    const float scale = std::exp2(unit(random) * 5.0f) / 64.0f;
                    for (int c = 0; c < 4; ++c) grads[c * count + i] = unit(random) * scale;
                }
                if (k == 1) grads[0] = std::numeric_limits<float>::quiet_NaN();
                std::vector<float> first;
                for (const Isa isa : supported_isas()) {
                    float got[4 * N];
                    kernels(isa).sample_lanes(b, coords, lod, grads, count, 0xFFFFu, got);
                    if (first.empty()) first.assign(got, got + 4 * count);
                    paths_differ += std::memcmp(first.data(), got, 4 * count * sizeof(float)) != 0;
                    for (uint32_t i = 0; i < count; ++i) {
                        const glm::vec2 uv(coords[i], coords[count + i]);
                        // trilinear reads the level given; anisotropic the derivatives
                        const glm::vec4 want =
                            filter == Filter::trilinear
                                ? sample_lod(b, uv, lod[i])
                                : sample_grad(b, uv, {grads[i], grads[count + i]},
                                              {grads[2 * count + i], grads[3 * count + i]});
                        for (int c = 0; c < 4; ++c)
                            worst = std::max(worst, std::abs(code(got[c * count + i], c < 3) -
                                                             code(want[c], c < 3)));
                    }
                }
            }
            CHECK(worst <= 1);
            CHECK(paths_differ == 0);
        }
}

namespace {

// Squares of 2x2 texels, black and white, over 256x256 (linear codes).
std::shared_ptr<Texture> checker_texture() {
    auto t = std::make_shared<Texture>();
    t->width = t->height = 256;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            const uint8_t c = ((x / 2 + y / 2) & 1) ? 255 : 0;
            t->texels.push_back({c, c, c, 255});
        }
    generate_mipmaps(*t);
    return t;
}

}  // namespace

TEST_CASE("anisotropic filtering keeps a grazing footprint as sharp as the box-filtered truth, "
          "where trilinear blurs it",
          "[texture][anisotropic]") {
    // Footprints stretched 6:1 to 12:1, turned at random, their shorter axis
    // under one texel: trilinear takes its level from the longer axis and
    // washes the checker out to grey; the truth, the pixel's parallelogram
    // averaged over level 0 (32x32 bilinear samples), keeps it. RMSE of the
    // red channel, linear.
    const auto texture = checker_texture();
    const TextureBinding truth{texture, Filter::bilinear, Wrap::repeat};
    std::mt19937 random(23);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    double error[2] = {};
    int samples = 0;
    for (int k = 0; k < 300; ++k) {
        const float angle = unit(random) * 6.2831853f, stretch = 6.0f + 6.0f * unit(random);
        const float across = 0.4f + 0.5f * unit(random);  // texels
        const glm::vec2 axis(std::cos(angle), std::sin(angle));
        const glm::vec2 dx = axis * (stretch * across / 256.0f);
        const glm::vec2 dy = glm::vec2(-axis.y, axis.x) * (across / 256.0f);
        const glm::vec2 uv(unit(random), unit(random));
        double box = 0.0;
        for (int a = 0; a < 32; ++a)
            for (int c = 0; c < 32; ++c)
                box += sample(truth, uv + dx * ((a + 0.5f) / 32 - 0.5f) +
                                         dy * ((c + 0.5f) / 32 - 0.5f)).r;
        box /= 32 * 32;
        int i = 0;
        for (const Filter filter : {Filter::trilinear, Filter::anisotropic}) {
            const double got = sample_grad({texture, filter, Wrap::repeat}, uv, dx, dy).r;
            error[i++] += (got - box) * (got - box);
        }
        ++samples;
    }
    const double trilinear = std::sqrt(error[0] / samples), anisotropic = std::sqrt(error[1] / samples);
    INFO("RMSE trilinear " << trilinear << ", anisotropic " << anisotropic);
    CHECK(trilinear > 0.1);
    CHECK(anisotropic < 0.2 * trilinear);  // measured: 0.124 and 0.014
}
