// Textures: loaded through stb_image (PNG, JPEG, TGA, ...), stored as linear
// float RGBA, sampled with a filter and a wrap mode.
//
// Colour textures are sRGB-encoded in their files and decoded to linear
// light at load, so filtering happens in linear light; data textures
// (normals, masks) are taken as they are.
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace facet {

enum class Filter { nearest, bilinear };
enum class Wrap { repeat, clamp, mirror };

struct Texture {
    std::string source;
    int width = 0;
    int height = 0;
    bool srgb = false;
    std::vector<glm::vec4> texels;  // linear RGBA, row-major, top row first
};

// Throws Error(file_not_found | texture_load_failed).
std::shared_ptr<const Texture> load_texture(const std::filesystem::path& path, bool srgb);

// Loads each (file, srgb) pair once and hands out the shared copy.
class TextureCache {
public:
    std::shared_ptr<const Texture> get(const std::filesystem::path& path, bool srgb);

private:
    std::map<std::pair<std::string, bool>, std::shared_ptr<const Texture>> textures_;
};

struct TextureBinding {
    std::shared_ptr<const Texture> texture;
    Filter filter = Filter::bilinear;
    Wrap wrap = Wrap::repeat;
};

// Sample at texture coordinate uv (0,0 = first texel's corner, v down the
// rows, as OBJ and glTF store it after the loader's flip).
glm::vec4 sample(const TextureBinding& binding, glm::vec2 uv);

// Sample `count` coordinates; writes rgba[c * count + i].
void sample_many(const TextureBinding& binding, const float* u, const float* v, int count,
                 float* rgba);

}  // namespace facet
