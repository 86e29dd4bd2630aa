// The sampler's copy of a texture's levels (facet/texture.hpp, TexelLevels):
// tiles of 4 x 4 texels whose rows hold the texel after them too, and for
// colour textures decoded from sRGB once. Takes a Texture's 8-bit levels;
// gives the words the per-path sampler loads.
#include "facet/texture.hpp"

#include "facet/color.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace facet {

namespace {

// Level i's texels, row-major: face f's.
const Texel8* level_texels(const Texture& t, int i, int f) {
    const Texel8* first = i == 0 ? t.texels.data() : t.mips[size_t(i - 1)].texels.data();
    const int w = i == 0 ? t.width : t.mips[size_t(i - 1)].width;
    const int h = i == 0 ? t.height : t.mips[size_t(i - 1)].height;
    return first + size_t(f) * size_t(w) * size_t(h);
}

// Each 8-bit code's 14-bit linear one: sRGB-decoded for colour, c / 255
// for alpha.
struct Codes14 {
    std::array<uint32_t, 256> colour, alpha;
};

const Codes14& codes14() {
    static const Codes14 codes = [] {
        Codes14 c;
        for (int i = 0; i < 256; ++i) {
            c.colour[size_t(i)] = uint32_t(std::lround(double(srgb8_to_linear(uint8_t(i))) * 16383.0));
            c.alpha[size_t(i)] = uint32_t(std::lround(i / 255.0 * 16383.0));
        }
        return c;
    }();
    return codes;
}

// A colour texel's 14-bit linear codes, as two words: red and green, then
// blue and alpha (linear already).
void encode_rgba16(Texel8 t, uint32_t* out) {
    const Codes14& c = codes14();
    out[0] = c.colour[t.r] | c.colour[t.g] << 16;
    out[1] = c.colour[t.b] | c.alpha[t.a] << 16;
}

uint32_t encode_rgba8(Texel8 t) {
    return uint32_t(t.r) | uint32_t(t.g) << 8 | uint32_t(t.b) << 16 | uint32_t(t.a) << 24;
}

// Texels a row of a tile holds (its four and the next), and a tile.
constexpr int kTileRow = 5, kTileTexels = 4 * kTileRow;

// Level i of face f of `t` into its tiles at `out` (its texel (0, 0)'s
// words): texel x of a row, for x from 0 to the width (the texel after the
// last being the row's first), where x's tile holds it, and where x begins
// a tile, also as the fifth of the tile before.
void tile_level(const Texture& t, const TexelLevels& l, int i, int f, uint32_t* out) {
    const Texel8* src = level_texels(t, i, f);
    const TexelLevel& level = l.level[size_t(f * l.levels + i)];
    const int w = level.width, tiles_x = (w + 3) / 4, words = l.words_per_texel();
    const auto put = [&](Texel8 c, int tile, int y, int column) {
        const size_t texel = size_t(y / 4) * size_t(level.tile_row) + size_t(tile) * kTileTexels +
                             size_t(y % 4 * kTileRow + column);
        if (words == 2)
            encode_rgba16(c, out + texel * 2);
        else
            out[texel] = encode_rgba8(c);
    };
    for (int y = 0; y < level.height; ++y)
        for (int x = 0; x <= w; ++x) {
            const Texel8 c = src[size_t(y) * size_t(w) + size_t(x < w ? x : 0)];
            if (x / 4 < tiles_x) put(c, x / 4, y, x % 4);
            if (x % 4 == 0 && x > 0) put(c, x / 4 - 1, y, 4);
        }
}

}  // namespace

TexelLevels make_texel_levels(const Texture& t) {
    TexelLevels l;
    if (t.width <= 0 || t.height <= 0 || (t.faces != 1 && t.faces != 6) ||
        t.texels.size() != size_t(t.width) * size_t(t.height) * size_t(t.faces))
        return l;  // levels 0: nothing to sample
    l.format = t.srgb ? TexelFormat::rgba16 : TexelFormat::rgba8;
    l.levels = t.levels();
    l.faces = t.faces;
    l.level.resize(size_t(l.faces * l.levels));
    size_t texels = 0;
    for (int f = 0; f < l.faces; ++f)
        for (int i = 0; i < l.levels; ++i) {
            TexelLevel& level = l.level[size_t(f * l.levels + i)];
            level.width = i == 0 ? t.width : t.mips[size_t(i - 1)].width;
            level.height = i == 0 ? t.height : t.mips[size_t(i - 1)].height;
            level.tile_row = (level.width + 3) / 4 * kTileTexels;
            level.offset = int32_t(texels);
            texels += size_t(level.tile_row) * size_t((level.height + 3) / 4);
        }
    // 15 words before, so that a 64-byte boundary lies within them, and 4
    // after, so that a 16-byte load at any texel stays inside.
    const size_t words = texels * size_t(l.words_per_texel());
    l.storage.assign(words + 15 + 4, 0u);
    const uintptr_t at = reinterpret_cast<uintptr_t>(l.storage.data());
    uint32_t* out = l.storage.data() + ((64 - at % 64) % 64) / sizeof(uint32_t);
    l.words = out;
    for (int f = 0; f < l.faces; ++f)
        for (int i = 0; i < l.levels; ++i)
            tile_level(t, l, i, f,
                       out + size_t(l.level[size_t(f * l.levels + i)].offset) *
                                 size_t(l.words_per_texel()));
    return l;
}

const TexelLevels& Texture::make_sampled() const {
    const std::lock_guard<std::mutex> lock(sampled_->making);
    if (!sampled_->made.load(std::memory_order_relaxed)) {
        sampled_->levels = make_texel_levels(*this);
        sampled_->made.store(&sampled_->levels, std::memory_order_release);
    }
    return sampled_->levels;
}

}  // namespace facet
