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
    for (const auto& texture : textures)
        for (const Filter filter : {Filter::nearest, Filter::bilinear, Filter::trilinear})
            for (const Wrap wrap : {Wrap::repeat, Wrap::clamp, Wrap::mirror}) {
                INFO(texture->width << "x" << texture->height << (texture->srgb ? " sRGB" : "")
                                    << ", filter " << int(filter) << ", wrap " << int(wrap));
                const TextureBinding b{texture, filter, wrap};
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
        for (const Isa isa : supported_isas()) {
            float got[4 * N];
            kernels(isa).sample_lod(b, u, v, lod, 0xFFFFu, got);
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
