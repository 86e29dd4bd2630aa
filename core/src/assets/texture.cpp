// Texture loading (stb_image, kept as 8-bit RGBA) and sampling, which
// decodes each texel to linear light as it reads it.
//
// Texel (i, j) covers [i, i+1) x [j, j+1) in texel units, so its centre is at
// uv ((i + 0.5) / width, (j + 0.5) / height); uv (0, 0) is the top-left corner.
#include "facet/texture.hpp"

#include "facet/error.hpp"
#include "facet/color.hpp"
#include "facet/memory.hpp"
#include "assets/decoder_peak.hpp"
#include "assets/image_decoder.hpp"
#include "assets/png_check.hpp"
#include "base/files.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

namespace facet {

namespace {

// 8-bit code -> linear value: sRGB-encoded colour channels (as the colour
// target decodes them, srgb8_to_linear), and linear channels (alpha, and
// the colour of data textures). Built at first use: srgb8_to_linear's own
// table is initialised with its file, in an order no other file knows.
using DecodeTable = std::array<float, 256>;

struct DecodeTables {
    DecodeTable srgb;
    DecodeTable linear;
};

const DecodeTables& decode_tables() {
    static const DecodeTables tables = [] {
        DecodeTables t;
        for (int i = 0; i < 256; ++i) {
            t.srgb[i] = srgb8_to_linear(uint8_t(i));
            t.linear[i] = float(i) * (1.0f / 255.0f);  // as the per-path sampler decodes
        }
        return t;
    }();
    return tables;
}

// A coordinate folded as its wrap mode repeats it: repeat into [0, 1),
// mirror into [0, 1] (every other period reflected), clamp within [-1, 2]
// (past which every texel is an edge texel); NaN and infinities as 0 (clamp:
// infinities at -1 or 2). Texel indices just past a folded coordinate's
// edge then wrap (repeat) or clamp (clamp, mirror). Folding first keeps
// the position exact (u - floor(u) is) however far u lies, where u times
// the width would round to the whole texels of a large u.
float fold(float u, Wrap wrap) {
    constexpr float kWhole = 8388608.0f;  // 2^23: floats of this size have no fraction
    switch (wrap) {
        case Wrap::clamp: return u == u ? std::clamp(u, -1.0f, 2.0f) : 0.0f;
        case Wrap::mirror: {
            if (!(std::abs(u) < 2.0f * kWhole)) return 0.0f;
            const float m = u - 2.0f * std::floor(u * 0.5f);  // [0, 2)
            return m > 1.0f ? 2.0f - m : m;
        }
        case Wrap::repeat: break;
    }
    return std::abs(u) < kWhole ? u - std::floor(u) : 0.0f;
}

// Texel index i of a folded coordinate into 0..n-1: i is -1 to n.
int wrap_index(int i, int n, Wrap wrap) {
    if (wrap != Wrap::repeat) return std::clamp(i, 0, n - 1);
    return i < 0 ? i + n : i >= n ? i - n : i;
}

// A coordinate in texel units split into its integer part and fraction.
struct Split {
    int index;
    float fraction;
};

Split split(float x) {
    const float whole = std::floor(x);
    return {static_cast<int>(whole), x - whole};
}

// One level of a texture: level 0 or a mip.
struct Level {
    int width;
    int height;
    const Texel8* texels;
};

// Level i of face f (0 but for a cube).
Level level(const Texture& t, int i, int f = 0) {
    if (i == 0)
        return {t.width, t.height, t.texels.data() + size_t(f) * size_t(t.width) * size_t(t.height)};
    const MipLevel& m = t.mips[size_t(i - 1)];
    return {m.width, m.height, m.texels.data() + size_t(f) * size_t(m.width) * size_t(m.height)};
}

// a + (b - a) t, as the per-path sampler mixes.
glm::vec4 lerp(const glm::vec4& a, const glm::vec4& b, float t) { return a + (b - a) * t; }

class Sampler {
public:
    Sampler(Level level, Wrap wrap, bool srgb, const DecodeTables& tables = decode_tables())
        : t_(level), wrap_(wrap), colour_(srgb ? tables.srgb : tables.linear),
          alpha_(tables.linear) {}

    glm::vec4 nearest(glm::vec2 uv) const {
        // A repeated coordinate just below 1 can round to the width: the last texel.
        const auto index = [&](float u, int n) {
            return std::min(split(fold(u, wrap_) * float(n)).index, n - 1);
        };
        return texel(index(uv.x, t_.width), index(uv.y, t_.height));
    }

    glm::vec4 bilinear(glm::vec2 uv) const {
        const Split x = split(fold(uv.x, wrap_) * float(t_.width) - 0.5f);
        const Split y = split(fold(uv.y, wrap_) * float(t_.height) - 0.5f);
        const glm::vec4 top =
            lerp(texel(x.index, y.index), texel(x.index + 1, y.index), x.fraction);
        const glm::vec4 bottom =
            lerp(texel(x.index, y.index + 1), texel(x.index + 1, y.index + 1), x.fraction);
        return lerp(top, bottom, y.fraction);
    }

private:
    glm::vec4 texel(int x, int y) const {
        const size_t row = static_cast<size_t>(wrap_index(y, t_.height, wrap_));
        const Texel8 t = t_.texels[row * t_.width + wrap_index(x, t_.width, wrap_)];
        return {colour_[t.r], colour_[t.g], colour_[t.b], alpha_[t.a]};
    }

    Level t_;
    Wrap wrap_;
    const DecodeTable& colour_;
    const DecodeTable& alpha_;
};

// Face f's levels filtered at uv, lod.
glm::vec4 trilinear(const Texture& t, Wrap wrap, glm::vec2 uv, float lod, int f = 0) {
    const float l = std::clamp(std::isnan(lod) ? 0.0f : lod, 0.0f, float(t.levels() - 1));
    const int lo = int(l);
    const glm::vec4 a = Sampler(level(t, lo, f), wrap, t.srgb).bilinear(uv);
    if (lo + 1 >= t.levels() || l == float(lo)) return a;
    return lerp(a, Sampler(level(t, lo + 1, f), wrap, t.srgb).bilinear(uv), l - float(lo));
}

// The mean, in linear light, of the up-to-2x2 texels of `src` that texel
// (x, y) of the next level covers.
glm::vec4 box(Level src, int x, int y, bool srgb) {
    glm::vec4 sum(0.0f);
    int n = 0;
    for (int j = 2 * y; j < std::min(2 * y + 2, src.height); ++j)
        for (int i = 2 * x; i < std::min(2 * x + 2, src.width); ++i, ++n)
            sum += decode_texel(src.texels[size_t(j) * src.width + i], srgb);
    return sum / float(n);
}

}  // namespace

Texel8 encode_texel(glm::vec4 linear, bool srgb) {
    auto colour = [srgb](float v) { return srgb ? linear_to_srgb8(v) : unorm8(v); };
    return {colour(linear.r), colour(linear.g), colour(linear.b), unorm8(linear.a)};
}

glm::vec4 decode_texel(Texel8 t, bool srgb) {
    const DecodeTables& tables = decode_tables();
    const DecodeTable& colour = srgb ? tables.srgb : tables.linear;
    return {colour[t.r], colour[t.g], colour[t.b], tables.linear[t.a]};
}

namespace {

// Its size from the header, against the budget, before decoding: the file,
// and the most of what the decoder holds at its peak (decoder_peak.hpp)
// and of what the texture holds: the decoded image, the texture with its
// mipmaps (a third more), and the sampler's copy of them (TexelLevels: 8
// bytes a texel for colour, 4 for data, in tiles that hold a fifth more).
void require_decodable(std::string_view bytes, int header_width, int header_height, bool srgb,
                       const std::string& source) {
    // stb_image gives a top-down BMP's height as the file has it: negative.
    const int64_t width = std::abs(int64_t(header_width)), height = std::abs(int64_t(header_height));
    if (width == 0 || height == 0) return;
    const uint64_t texels = uint64_t(width) * uint64_t(height);
    // texels in tiles of 4 x 4 that hold 20 (TexelLevels), with the mipmaps
    const uint64_t sampled = (uint64_t(width) + 3) / 4 * 20 * ((uint64_t(height) + 3) / 4) * 4 / 3;
    // The sampler addresses words with 32-bit indices.
    if (sampled * (srgb ? 2 : 1) > (uint64_t(1) << 31) - 64)
        throw Error(ErrorCode::texture_load_failed,
                    "a " + std::to_string(width) + "x" + std::to_string(height) +
                        " texture: more texels than the sampler addresses (2^30)",
                    source);
    const uint64_t texture = texels * 4 + texels * sizeof(Texel8) * 4 / 3 + sampled * (srgb ? 8 : 4);
    const uint64_t decoding = decoder_peak_bytes(bytes, uint64_t(width), uint64_t(height));
    require_within_budget(bytes.size() + std::max(texture, decoding),
                          "a " + std::to_string(width) + "x" + std::to_string(height) + " texture",
                          source);
}

// A texture of the decoded RGBA `pixels`.
std::shared_ptr<const Texture> adopt_pixels(const Pixels8& pixels, bool srgb,
                                            const std::string& source) {
    const int width = pixels.width, height = pixels.height, channels = pixels.file_channels;
    if (width <= 0 || height <= 0)  // a header that says so (HDR's "+X 0")
        throw Error(ErrorCode::texture_load_failed,
                    "an image of " + std::to_string(width) + "x" + std::to_string(height) +
                        " pixels: it has none",
                    source);
    auto texture = std::make_shared<Texture>();
    texture->source = source;
    texture->width = width;
    texture->height = height;
    texture->srgb = srgb;
    texture->texels.resize(size_t(width) * height);
    static_assert(sizeof(Texel8) == 4);
    std::memcpy(texture->texels.data(), pixels.data.get(), texture->texels.size() * sizeof(Texel8));
    generate_mipmaps(*texture);
    texture->sampled();  // the sampler's levels now, not in the first frame
    spdlog::debug("texture {}: {}x{}, {} channels{}, {} levels", texture->source, width, height,
                 channels, srgb ? ", sRGB" : "", texture->levels());
    return texture;
}

}  // namespace

std::string read_image_file(const std::filesystem::path& path) {
    require_regular_file(path);
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw Error(ErrorCode::texture_load_failed, ec.message(), path.string());
    if (size > uintmax_t(std::numeric_limits<int>::max()))
        throw Error(ErrorCode::texture_load_failed, "an image over 2 GiB", path.string());
    require_within_budget(size, "the image file", path.string());
    std::string bytes(size_t(size), '\0');
    std::ifstream in(path, std::ios::binary);
    if (!in.read(bytes.data(), std::streamsize(size)))
        throw Error(ErrorCode::texture_load_failed, "cannot read the file", path.string());
    return bytes;
}

std::shared_ptr<const Texture> load_texture(const std::filesystem::path& path, bool srgb) {
    // The file's bytes, then as decode_texture: one way in for every image.
    return decode_texture(read_image_file(path), srgb, path.string());
}

std::shared_ptr<const Texture> decode_texture(std::string_view bytes, bool srgb,
                                              const std::string& source) {
    if (bytes.size() > size_t(std::numeric_limits<int>::max()))
        throw Error(ErrorCode::texture_load_failed, "an image over 2 GiB", source);
    if (looks_like_png(bytes)) check_png(bytes, source);
    if (const std::optional<ImageInfo> info = image_info(bytes, source))
        require_decodable(bytes, info->width, info->height, srgb, source);
    return adopt_pixels(decode_8bit(bytes, 4, source), srgb, source);
}

namespace {

// A file's name in the cache: its canonical path where there is one (the
// name of an embedded image need not exist), so that two spellings of one
// file share one copy.
std::string texture_cache_key(const std::filesystem::path& path) {
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
    return ec ? path.string() : canonical.string();
}

}  // namespace

std::shared_ptr<const Texture> TextureCache::get(const std::filesystem::path& path, bool srgb) {
    const std::string name = texture_cache_key(path);
    const auto key = std::make_pair(name, srgb);
    if (const auto found = textures_.find(key); found != textures_.end()) return found->second;
    const auto encoded = encoded_.find(name);
    std::shared_ptr<const Texture> texture =
        encoded != encoded_.end() ? decode_texture(*encoded->second, srgb, path.string())
                                  : load_texture(path, srgb);
    textures_.emplace(key, texture);
    return texture;
}

void TextureCache::forget(const std::filesystem::path& path) {
    const std::string name = texture_cache_key(path);
    for (const bool srgb : {false, true}) textures_.erase({name, srgb});
}

void TextureCache::add_encoded(const std::filesystem::path& name,
                               std::shared_ptr<const std::string> bytes) {
    encoded_[texture_cache_key(name)] = std::move(bytes);
}

void generate_mipmaps(Texture& texture) {
    texture.mips.clear();
    for (int w = texture.width, h = texture.height; w > 1 || h > 1;) {
        const int below = texture.levels() - 1;
        MipLevel next;
        next.width = w = std::max(1, w / 2);
        next.height = h = std::max(1, h / 2);
        const size_t face_texels = size_t(w) * size_t(h);
        next.texels.resize(face_texels * size_t(texture.faces));
        for (int f = 0; f < texture.faces; ++f) {
            const Level src = level(texture, below, f);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    next.texels[size_t(f) * face_texels + size_t(y) * size_t(w) + size_t(x)] =
                        encode_texel(box(src, x, y, texture.srgb), texture.srgb);
        }
        texture.mips.push_back(std::move(next));
    }
}

float level_of_detail(const Texture& t, glm::vec2 duv_dx, glm::vec2 duv_dy) {
    const glm::vec2 size(float(t.width), float(t.height));
    const glm::vec2 x = duv_dx * size, y = duv_dy * size;
    // log2 of the longer axis as half that of its square (the per-path
    // sampler's steps, NaN included: std::max keeps its first argument).
    const float rho2 = std::max(x.x * x.x + x.y * x.y, y.x * y.x + y.y * y.y);
    return rho2 > 0.0f ? 0.5f * std::log2(rho2) : 0.0f;
}

glm::vec4 sample(const TextureBinding& binding, glm::vec2 uv) {
    if (!binding.texture) return glm::vec4(1.0f);  // nothing bound reads as white
    const Sampler sampler(level(*binding.texture, 0), binding.wrap, binding.texture->srgb);
    return binding.filter == Filter::nearest ? sampler.nearest(uv) : sampler.bilinear(uv);
}

AnisotropicFootprint anisotropic_footprint(const Texture& t, glm::vec2 duv_dx, glm::vec2 duv_dy,
                                           int most) {
    const glm::vec2 size(float(t.width), float(t.height));
    const glm::vec2 x = duv_dx * size, y = duv_dy * size;
    const float x2 = x.x * x.x + x.y * x.y, y2 = y.x * y.x + y.y * y.y;
    const bool along_y = y2 > x2;
    const float longer = along_y ? y2 : x2, shorter = along_y ? x2 : y2;
    AnisotropicFootprint f;
    if (!(longer > 0.0f)) return f;  // no size, or NaN: one sample at level 0
    most = std::clamp(most, 1, kMaxAnisotropy);
    const float ratio = std::sqrt(longer / shorter);  // shorter 0: infinite
    f.samples = ratio < float(most) ? int(std::ceil(ratio)) : most;
    f.lod = 0.5f * std::log2(longer / float(f.samples * f.samples));
    f.step = along_y ? duv_dy : duv_dx;
    return f;
}

namespace {

// The mean of a footprint's trilinear samples (anisotropic_footprint).
glm::vec4 anisotropic(const TextureBinding& b, glm::vec2 uv, const AnisotropicFootprint& f) {
    glm::vec4 sum(0.0f);
    for (int k = 0; k < f.samples; ++k) {
        const float at = (float(k) + 0.5f) / float(f.samples) - 0.5f;
        sum += trilinear(*b.texture, b.wrap, {uv.x + f.step.x * at, uv.y + f.step.y * at}, f.lod);
    }
    return sum / float(f.samples);
}

}  // namespace

glm::vec4 sample_grad(const TextureBinding& binding, glm::vec2 uv, glm::vec2 duv_dx,
                      glm::vec2 duv_dy) {
    if (!binding.texture || !mipmapped(binding.filter)) return sample(binding, uv);
    if (binding.filter == Filter::trilinear)
        return trilinear(*binding.texture, binding.wrap, uv,
                         level_of_detail(*binding.texture, duv_dx, duv_dy));
    return anisotropic(binding, uv,
                       anisotropic_footprint(*binding.texture, duv_dx, duv_dy, binding.anisotropy));
}

void sample_block(const TextureBinding& binding, const float* u, const float* v, uint32_t mask,
                  float* rgba) {
    constexpr int N = 16;
    std::fill(rgba, rgba + 4 * N, 0.0f);
    for (int quad : {0, 2, 8, 10}) {  // top-left lane of each 2x2 quad
        const uint32_t lanes = mask & (0x33u << quad);
        if (!lanes) continue;
        const glm::vec2 o(u[quad], v[quad]);
        const glm::vec2 dx = glm::vec2(u[quad + 1], v[quad + 1]) - o;
        const glm::vec2 dy = glm::vec2(u[quad + 4], v[quad + 4]) - o;
        for (uint32_t m = lanes; m; m &= m - 1) {
            const int lane = std::countr_zero(m);
            const glm::vec4 c = sample_grad(binding, {u[lane], v[lane]}, dx, dy);
            for (int k = 0; k < 4; ++k) rgba[k * N + lane] = c[k];
        }
    }
}

glm::vec4 sample_lod(const TextureBinding& binding, glm::vec2 uv, float lod) {
    if (!mipmapped(binding.filter) || !binding.texture) return sample(binding, uv);
    return trilinear(*binding.texture, binding.wrap, uv, lod);
}

int cube_face(glm::vec3 d, glm::vec2& uv) {
    const float ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    int face;
    float sc, tc, ma;
    if (ax >= ay && ax >= az)
        face = d.x > 0.0f ? 0 : 1, sc = d.x > 0.0f ? -d.z : d.z, tc = -d.y, ma = ax;
    else if (ay >= az)
        face = d.y > 0.0f ? 2 : 3, sc = d.x, tc = d.y > 0.0f ? d.z : -d.z, ma = ay;
    else
        face = d.z > 0.0f ? 4 : 5, sc = d.z > 0.0f ? d.x : -d.x, tc = -d.y, ma = az;
    uv = {(sc / ma + 1.0f) * 0.5f, (tc / ma + 1.0f) * 0.5f};
    if (!(ma > 0.0f)) uv = glm::vec2(0.5f);  // no direction (0, or NaN): the face's middle
    return face;
}

glm::vec4 sample_cube(const TextureBinding& binding, glm::vec3 dir, float lod) {
    if (!binding.texture || binding.texture->faces != 6) return glm::vec4(1.0f);
    glm::vec2 uv;
    const int f = cube_face(dir, uv);
    const Texture& t = *binding.texture;
    if (mipmapped(binding.filter)) return trilinear(t, Wrap::clamp, uv, lod, f);
    const Sampler face(level(t, 0, f), Wrap::clamp, t.srgb);
    return binding.filter == Filter::nearest ? face.nearest(uv) : face.bilinear(uv);
}

void sample_many(const TextureBinding& binding, const float* u, const float* v, int count,
                 float* rgba) {
    for (int i = 0; i < count; ++i) {
        const glm::vec4 c = sample(binding, {u[i], v[i]});
        for (int k = 0; k < 4; ++k) rgba[k * count + i] = c[k];
    }
}

}  // namespace facet
