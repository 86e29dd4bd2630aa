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
// for its mipmaps.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace facet {

// nearest and bilinear read level 0; trilinear picks the level of detail
// from the UV derivatives and blends the two nearest levels.
enum class Filter { nearest, bilinear, trilinear };
enum class Wrap { repeat, clamp, mirror };

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

struct Texture {
    std::string source;
    int width = 0;                // level 0
    int height = 0;
    bool srgb = false;
    std::vector<Texel8> texels;   // level 0, row-major, top row first
    std::vector<MipLevel> mips;   // levels 1, 2, ... down to 1x1 (may be empty)

    int levels() const { return 1 + int(mips.size()); }
    // Texel i of level 0, decoded to linear RGBA.
    glm::vec4 linear(size_t i) const { return decode_texel(texels[i], srgb); }
};

// Fills texture.mips from level 0 (each level half the size, rounded down,
// at least 1; each texel the mean, in linear light, of the 2x2 (or fewer)
// texels it covers, encoded as the texture is).
void generate_mipmaps(Texture& texture);

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

    // Makes `name` (which need not exist on disk) stand for the image file
    // `bytes`: get(name) decodes them. For textures embedded in a mesh
    // file (Mesh::images).
    void add_encoded(const std::filesystem::path& name, std::shared_ptr<const std::string> bytes);

private:
    std::map<std::pair<std::string, bool>, std::shared_ptr<const Texture>> textures_;
    std::map<std::string, std::shared_ptr<const std::string>> encoded_;
};

struct TextureBinding {
    std::shared_ptr<const Texture> texture;
    Filter filter = Filter::trilinear;
    Wrap wrap = Wrap::repeat;
};

// Sample at texture coordinate uv (0,0 = first texel's corner, v down the
// rows, as OBJ and glTF store it after the loader's flip).
glm::vec4 sample(const TextureBinding& binding, glm::vec2 uv);

// Sample `count` coordinates at level 0; writes rgba[c * count + i].
void sample_many(const TextureBinding& binding, const float* u, const float* v, int count,
                 float* rgba);

// Level of detail (0 = level 0) for UV derivatives in UV units per pixel,
// as trilinear filtering uses it: log2 of the longer footprint axis in texels.
float level_of_detail(const Texture& texture, glm::vec2 duv_dx, glm::vec2 duv_dy);

// Sample one 4x4 fragment block (lane i at pixel (i % 4, i / 4)) at the
// lanes of `mask`, taking each 2x2 quad's UV differences as its derivatives
// (all 16 UVs must be there); writes rgba[c * 16 + i], 0 at other lanes.
void sample_block(const TextureBinding& binding, const float* u, const float* v, uint32_t mask,
                  float* rgba);

}  // namespace facet
