// Textures: loaded through stb_image (PNG, JPEG, TGA, ...), stored as the
// files give them, 8 bits a channel (RGBA), sampled with a filter and a wrap
// mode.
//
// Colour textures are sRGB-encoded in their files and kept so; a texel is
// decoded to linear light as it is read, so filtering happens in linear
// light. Data textures (normals, masks) are taken as they are. Alpha is
// always linear. A mipmap chain (2x2 box filter in linear light, each level
// encoded again as its texture is, down to 1x1) is generated at load for
// trilinear filtering. A texture costs 4 bytes a texel, and a third more
// for its mipmaps; the sampler's copy of its levels (TexelLevels) 4 bytes
// more for data and 8 more for colour, and a third more again.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace facet {

// nearest and bilinear read level 0; trilinear picks the level of detail
// from the UV derivatives and blends the two nearest levels; anisotropic
// takes up to TextureBinding::anisotropy trilinear samples along the
// longer axis of the pixel's footprint, each at the level of its share
// (anisotropic_footprint). A cube map's anisotropic filter is trilinear.
enum class Filter { nearest, bilinear, trilinear, anisotropic };
enum class Wrap { repeat, clamp, mirror };

// Whether a filter reads the mipmap levels.
constexpr bool mipmapped(Filter f) { return f == Filter::trilinear || f == Filter::anisotropic; }

// The most samples anisotropic filtering takes (GL's and D3D's 16x).
constexpr int kMaxAnisotropy = 16;

// A texel as stored: red, green, blue (sRGB-encoded in an sRGB texture) and
// alpha (linear), 8 bits each.
struct Texel8 {
    uint8_t r = 0, g = 0, b = 0, a = 0;
    bool operator==(const Texel8&) const = default;
};

// Linear RGBA -> the nearest texel of an sRGB (or linear) texture, each
// channel clamped to 0..1; and back.
Texel8 encode_texel(glm::vec4 linear, bool srgb);
glm::vec4 decode_texel(Texel8 texel, bool srgb);

struct MipLevel {
    int width = 0;
    int height = 0;
    std::vector<Texel8> texels;
};

// A texture's levels as the per-path sampler reads them
// (core/src/pipeline/sampler.hpp), made once from the 8-bit levels
// (texel_levels.cpp). A level lies in tiles of 4 x 4 texels, a row of tiles
// after another, so that the blocks of pixels a frame's 4x4 blocks sample
// mostly lie in one tile. Each of a tile's four rows holds five texels:
// its own four and the one after them (the next tile's first, or past the
// level's last texel its row's first, as repeat wraps), so that the two
// texels a bilinear footprint takes from a row are always next to each
// other, and one 8- or 16-byte load a lane brings both (clamp and mirror
// weight the fifth 0 where it is not theirs). Texel (x, y) of a level is
// texel offset + (y / 4) tile_row + (x / 4) 20 + (y % 4) 5 + x % 4.
enum class TexelFormat : uint8_t { rgba8, rgba16 };

// One level's numbers, as the sampler reads them: a 16-byte record, one
// load a lane where lanes read different levels.
struct TexelLevel {
    int32_t width = 0, height = 0;
    int32_t tile_row = 0;  // texels from one row of tiles to the next: 20 a tile
    int32_t offset = 0;    // where texel (0, 0) lies in `words`, in texels
};

struct TexelLevels {
    TexelFormat format = TexelFormat::rgba8;
    int levels = 0;      // a face's, as Texture::levels(); 0 for a texture with no texels
    int faces = 1;       // 6 for a cube map
    // Level l of face f is level[f * levels + l].
    std::vector<TexelLevel> level;
    // The texels (texel k at words[k * words_per_texel()]): 64-byte
    // aligned, inside storage; readable 16 bytes past any texel.
    const uint32_t* words = nullptr;
    std::vector<uint32_t> storage;

    int words_per_texel() const { return format == TexelFormat::rgba16 ? 2 : 1; }

    TexelLevels() = default;
    TexelLevels(TexelLevels&&) = default;  // `words` keeps pointing into the moved storage
    TexelLevels& operator=(TexelLevels&&) = default;
    TexelLevels(const TexelLevels&) = delete;
    TexelLevels& operator=(const TexelLevels&) = delete;
};

struct Texture {
    std::string source;
    int width = 0;                // level 0 (of each face, for a cube)
    int height = 0;
    bool srgb = false;
    // 1, or 6 for a cube map: each level then holds its faces one after
    // another (+X, -X, +Y, -Y, +Z, -Z of the direction, as GL and Vulkan
    // lay them out: a face's rows go down and its columns right as seen
    // from inside the cube), each width x height of that level.
    int faces = 1;
    std::vector<Texel8> texels;   // level 0, row-major, top row first
    std::vector<MipLevel> mips;   // levels 1, 2, ... down to 1x1 (may be empty)

    int levels() const { return 1 + int(mips.size()); }
    // Texel i of level 0, decoded to linear RGBA.
    glm::vec4 linear(size_t i) const { return decode_texel(texels[i], srgb); }

    // The levels as the sampler reads them, made from texels and mips at
    // the first call (load_texture and decode_texture make them at once).
    // Thread-safe, and one load once made; change neither texels nor mips
    // after it.
    const TexelLevels& sampled() const {
        const TexelLevels* made = sampled_->made.load(std::memory_order_acquire);
        return made ? *made : make_sampled();
    }

private:
    struct Sampled {
        std::atomic<const TexelLevels*> made{nullptr};
        std::mutex making;
        TexelLevels levels;
    };
    const TexelLevels& make_sampled() const;
    std::unique_ptr<Sampled> sampled_ = std::make_unique<Sampled>();
};

// The sampler's levels of `texture` (texel_levels.cpp); Texture::sampled()
// makes them once.
TexelLevels make_texel_levels(const Texture& texture);

// Fills texture.mips from level 0 (each level half the size, rounded down,
// at least 1; each texel the mean, in linear light, of the 2x2 (or fewer)
// texels it covers, encoded as the texture is; a cube's faces each on their
// own).
void generate_mipmaps(Texture& texture);

// A cube map from six square images of one size, +X, -X, +Y, -Y, +Z, -Z
// (`faces`), or from one equirectangular image (`faces` holding one file):
// longitude across it from -180 to 180 degrees, the image's middle column
// looking along -Z and its left edge along +Z past -X; latitude down it
// from +Y (the top row) to -Y. An equirectangular image is resampled
// (bilinearly, in linear light) into faces of half its height. Throws as
// load_texture does, and Error(texture_load_failed) for faces that are not
// square or not all one size.
std::shared_ptr<const Texture> load_cube(const std::vector<std::filesystem::path>& faces,
                                         bool srgb);

// An image file's bytes: a regular file of at most 2 GiB, within the
// memory budget. Throws Error(file_not_found | not_a_file |
// texture_load_failed | over_budget).
std::string read_image_file(const std::filesystem::path& path);

// Throws Error(file_not_found | not_a_file | texture_load_failed), or
// Error(over_budget) when its header gives a size over the memory budget.
std::shared_ptr<const Texture> load_texture(const std::filesystem::path& path, bool srgb);

// The same from an image file's bytes (PNG, JPEG, ...); `source` names it
// in errors and in Texture::source.
std::shared_ptr<const Texture> decode_texture(std::string_view bytes, bool srgb,
                                              const std::string& source);

// Loads each (file, srgb) pair once and hands out the shared copy.
class TextureCache {
public:
    std::shared_ptr<const Texture> get(const std::filesystem::path& path, bool srgb);
    // The cube map of load_cube, loaded once.
    std::shared_ptr<const Texture> get_cube(const std::vector<std::filesystem::path>& faces,
                                            bool srgb);

    // Drops the copies of `path` (either encoding), so that the next get()
    // reads the file again: hot reload, when it changed on disk.
    void forget(const std::filesystem::path& path);

    // Makes `name` (which need not exist on disk) stand for the image file
    // `bytes`: get(name) decodes them. For textures embedded in a mesh
    // file (Mesh::images).
    void add_encoded(const std::filesystem::path& name, std::shared_ptr<const std::string> bytes);

private:
    std::map<std::pair<std::string, bool>, std::shared_ptr<const Texture>> textures_;
    std::map<std::string, std::shared_ptr<const std::string>> encoded_;
};

// Where a 2D texture lies on its UVs (a texture parameter's `transform:`),
// as glTF's KHR_texture_transform defines it: the texture is read at
// uv' = offset + R * S * uv, S scaling u and v, R = [cos r, sin r;
// -sin r, cos r] (row by row). Its UVs are the mesh's, v down the rows, as
// glTF's are.
struct UvTransform {
    glm::vec2 offset{0.0f};
    float rotation = 0.0f;  // radians
    glm::vec2 scale{1.0f};

    bool identity() const { return offset == glm::vec2(0.0f) && rotation == 0.0f && scale == glm::vec2(1.0f); }
    // u' = m[0] u + m[1] v + offset.x, v' = m[2] u + m[3] v + offset.y
    std::array<float, 4> matrix() const;
    // Applied to `count` lanes: u[i], v[i] to out_u[i], out_v[i].
    void apply(const float* u, const float* v, int count, float* out_u, float* out_v) const;
    // What the transform adds to a level of detail taken from the
    // untransformed UVs' derivatives: log2 of its mean scale,
    // sqrt(|scale.x scale.y|) (exact for equal scales, at any rotation).
    float lod_shift() const;
};

struct TextureBinding {
    TextureBinding() = default;
    TextureBinding(std::shared_ptr<const Texture> t, Filter f = Filter::trilinear,
                   Wrap w = Wrap::repeat, UvTransform placed = {}, int set = 0,
                   int most = kMaxAnisotropy)
        : texture(std::move(t)), filter(f), wrap(w), transform(placed), uv_set(set),
          anisotropy(most) {}

    std::shared_ptr<const Texture> texture;
    Filter filter = Filter::trilinear;
    Wrap wrap = Wrap::repeat;
    UvTransform transform;  // 2D textures only
    // The set of texture coordinates the host samples it at: 0, or 1, the
    // second (Mesh::uvs1), at the shader's second_uv varying.
    int uv_set = 0;
    // Filter::anisotropic's most samples a pixel, held to 1..kMaxAnisotropy.
    int anisotropy = kMaxAnisotropy;
};

// The scalar reference sampler: plain per-lane code over the 8-bit levels,
// decoding each texel as it reads it. The per-path sampler that draws
// (core/src/pipeline/sampler.hpp) is held to it by tests.
//
// Sample at texture coordinate uv (0,0 = first texel's corner, v down the
// rows, as OBJ and glTF store it after the loader's flip).
glm::vec4 sample(const TextureBinding& binding, glm::vec2 uv);

// The same at level of detail `lod` (trilinear; the others read level 0),
// clamped to the levels there are, NaN read as 0.
glm::vec4 sample_lod(const TextureBinding& binding, glm::vec2 uv, float lod);

// A cube map in direction `dir` (facet_textures_service.sample says how),
// at level of detail `lod` as sample_lod takes it.
glm::vec4 sample_cube(const TextureBinding& binding, glm::vec3 dir, float lod);

// The face of direction d (+X, -X, +Y, -Y, +Z, -Z: 0 to 5) and where d
// meets it, (u, v) in 0..1, as the cube sampler reads them.
int cube_face(glm::vec3 d, glm::vec2& uv);
// The inverse: the direction (not unit) through point (x + 1/2, y + 1/2),
// in texels, of face f of n x n texels; x and y may lie past the face.
glm::dvec3 cube_texel_direction(int f, double x, double y, int n);

// Sample `count` coordinates at level 0; writes rgba[c * count + i].
void sample_many(const TextureBinding& binding, const float* u, const float* v, int count,
                 float* rgba);

// Level of detail (0 = level 0) for UV derivatives in UV units per pixel,
// as trilinear filtering uses it: log2 of the longer footprint axis in texels.
float level_of_detail(const Texture& texture, glm::vec2 duv_dx, glm::vec2 duv_dy);

// How anisotropic filtering reads the footprint that UV derivatives
// duv_dx and duv_dy (UV units a pixel) span, as EXT_texture_filter_
// anisotropic describes it. With px and py their lengths in level-0 texels
// and pmax >= pmin the longer and shorter:
//   samples = min(ceil(pmax / pmin), most) (most where pmin is 0),
//   lod     = log2(pmax / samples),
//   step    = the longer derivative (UV units),
// and sample k of n is the trilinear one at uv + step ((k + 1/2) / n - 1/2):
// n samples spread evenly over the pixel's extent along its longer axis
// (`most` held to 1..kMaxAnisotropy).
// The filtered value is their mean. A footprint of no size (or NaN) is one
// sample at level 0. Worked in float, step by step as the per-path sampler
// works it (squares compared; x where they are unordered).
struct AnisotropicFootprint {
    int samples = 1;
    float lod = 0.0f;
    glm::vec2 step{0.0f};
};
AnisotropicFootprint anisotropic_footprint(const Texture& texture, glm::vec2 duv_dx,
                                           glm::vec2 duv_dy, int most);

// A 2D binding sampled at uv with UV derivatives duv_dx and duv_dy, as
// textureGrad: its filter at the level of detail they give (anisotropic:
// over their footprint); nearest and bilinear read level 0.
glm::vec4 sample_grad(const TextureBinding& binding, glm::vec2 uv, glm::vec2 duv_dx,
                      glm::vec2 duv_dy);

// Sample one 4x4 fragment block (lane i at pixel (i % 4, i / 4)) at the
// lanes of `mask`, taking each 2x2 quad's UV differences as its derivatives
// (all 16 UVs must be there); writes rgba[c * 16 + i], 0 at other lanes.
void sample_block(const TextureBinding& binding, const float* u, const float* v, uint32_t mask,
                  float* rgba);

}  // namespace facet
