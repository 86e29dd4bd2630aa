// Fuzz target: texture decoding, decode_texture() (core/src/assets/texture.cpp:
// stb_image, the size check against the memory budget, the mipmaps and the
// sampler's tiled levels, texel_levels.cpp), then the per-path sampler
// (core/src/pipeline/sampler.hpp) on what was decoded.
//
// Input: a flags byte, then the image file's bytes (PNG, JPEG, BMP, TGA,
// PNM, HDR, ... as stb_image reads by content). Flags: bit 0 sRGB colour
// (else data), bits 1-2 the filter, bits 3-4 the wrap, bits 5-7 how far the
// sampled coordinates reach.
//
// The memory budget is 4 MiB here (about 200,000 texels, with mipmaps and
// the sampler's copy): an image whose header asks for more is refused with
// over_budget before it is decoded, and one that fits decodes within the
// fuzzer's time limit under the sanitizers.
//
// Checks:
//  - decode_texture() returns a texture or throws facet::Error with
//    texture_load_failed or over_budget; anything else is a finding;
//  - the texture: a positive size within the budget, one texel per pixel,
//    mipmaps halving (rounded down, at least 1) to 1x1, and sampler levels
//    of the same sizes;
//  - eight blocks of coordinates (magnified to minified, far outside,
//    NaN) sampled on every instruction-set path: within one 8-bit code of
//    the reference sampler, the same floats on every path, in [0, 1], and 0
//    at lanes outside the mask.
#include "support.hpp"

#include "pipeline/kernels.hpp"

#include <facet/error.hpp>
#include <facet/framebuffer.hpp>
#include <facet/isa.hpp>
#include <facet/memory.hpp>
#include <facet/texture.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace facet::fuzz {

namespace {

constexpr int N = 16;
constexpr uint64_t kBudget = uint64_t(4) << 20;

// A channel as the 8-bit code it is stored as: sRGB for colour, else linear.
int code(float v, bool srgb) {
    if (srgb) return linear_to_srgb8(v);
    return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

void check_levels(const Texture& t) {
    check(t.width > 0 && t.height > 0, "a decoded texture has no texels");
    check(uint64_t(t.width) * uint64_t(t.height) * 4 <= kBudget,
          "a texture larger than the memory budget was decoded");
    check(t.faces == 1, "a decoded image is not one face");
    check(t.texels.size() == size_t(t.width) * size_t(t.height),
          "a decoded texture's texels are not one per pixel");
    int w = t.width, h = t.height;
    for (const MipLevel& m : t.mips) {
        w = std::max(1, w / 2), h = std::max(1, h / 2);
        check(m.width == w && m.height == h && m.texels.size() == size_t(w) * size_t(h),
              "a mipmap level does not halve its parent");
    }
    check(w == 1 && h == 1, "the mipmaps do not end at 1x1");
    const TexelLevels& s = t.sampled();
    check(s.levels == t.levels() && s.faces == 1 && s.level.size() == size_t(t.levels()),
          "the sampler's levels are not the texture's");
    for (int l = 0; l < s.levels; ++l) {
        const int lw = l == 0 ? t.width : t.mips[size_t(l - 1)].width;
        const int lh = l == 0 ? t.height : t.mips[size_t(l - 1)].height;
        check(s.level[size_t(l)].width == lw && s.level[size_t(l)].height == lh,
              "a sampler level's size is not its mipmap's");
    }
}

// Block k's coordinates: a patch of a plane whose scale and place come
// from k and the flags (`reach`: 0 near the texture .. 7 far and NaN).
void coordinates(int k, int reach, float* u, float* v, uint32_t& mask) {
    const float scale = std::exp2(float(k - 4) * 1.5f) / 8.0f;  // magnified .. minified
    const float u0 = float(k % 3) - 0.7f + (reach >= 4 ? std::ldexp(1.0f, 3 * reach) : 0.0f);
    const float v0 = float(k % 2) * 0.4f - 0.2f - (reach >= 6 ? 3e7f : 0.0f);
    for (int i = 0; i < N; ++i) {
        const float x = float(i % 4), y = float(i / 4);
        u[i] = u0 + (x * 0.9f + y * 0.3f) * scale;
        v[i] = v0 + (y * 1.1f - x * 0.2f) * scale;
    }
    if (reach == 7 && k % 2) u[k] = std::numeric_limits<float>::quiet_NaN();
    if (reach == 7 && k % 4 == 2) v[k] = std::numeric_limits<float>::infinity();
    mask = k % 3 == 0 ? 0xFFFFu : 0x9A5Cu >> (k % 4);
}

void check_sampling(const std::shared_ptr<const Texture>& texture, uint8_t flags) {
    static constexpr Filter kFilters[] = {Filter::nearest, Filter::bilinear, Filter::trilinear,
                                          Filter::trilinear};
    static constexpr Wrap kWraps[] = {Wrap::repeat, Wrap::clamp, Wrap::mirror, Wrap::repeat};
    const TextureBinding b{texture, kFilters[(flags >> 1) & 3], kWraps[(flags >> 3) & 3]};
    for (int k = 0; k < 8; ++k) {
        float u[N], v[N];
        uint32_t mask = 0;
        coordinates(k, flags >> 5, u, v, mask);
        float expected[4 * N];
        sample_block(b, u, v, mask, expected);
        float first[4 * N];
        bool have_first = false;
        for (const Isa isa : supported_isas()) {
            float got[4 * N];
            kernels(isa).sample_block(b, u, v, mask, got);
            check(!have_first || std::memcmp(first, got, sizeof got) == 0,
                  "the sampler's paths give different floats");
            std::memcpy(first, got, sizeof got);
            have_first = true;
            for (int i = 0; i < 4 * N; ++i) {
                const bool lane = (mask >> (i % N)) & 1u;
                check(lane || got[i] == 0.0f, "the sampler wrote a lane outside the mask");
                check(got[i] >= 0.0f && got[i] <= 1.0f, "a sample is not in [0, 1]");
                const bool colour = texture->srgb && i < 3 * N;
                check(std::abs(code(got[i], colour) - code(expected[i], colour)) <= 1,
                      "the " + std::string(isa_name(isa)) +
                          " sampler differs from the reference by more than one code");
            }
        }
    }
}

}  // namespace

void texture_decode(const uint8_t* data, size_t size) {
    if (size == 0) return;
    set_memory_budget(kBudget);
    const uint8_t flags = data[0];
    const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
    std::shared_ptr<const Texture> texture;
    try {
        texture = decode_texture(bytes, flags & 1, "fuzz");
    } catch (const Error& e) {
        check(e.code() == ErrorCode::texture_load_failed || e.code() == ErrorCode::over_budget,
              std::string("decode_texture threw an undocumented error id: ") + e.what());
        return;
    } catch (const std::exception& e) {
        unexpected("decode_texture", e);
    }
    check(texture != nullptr, "decode_texture returned no texture");
    check_levels(*texture);
    check_sampling(texture, flags);
}

}  // namespace facet::fuzz
