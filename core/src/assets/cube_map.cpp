// Cube maps (facet/texture.hpp, load_cube): six faces read as they are, or
// one equirectangular image resampled into six. Takes image files; gives a
// Texture of six faces with its mipmaps and the sampler's levels.
#include "facet/texture.hpp"

#include "facet/error.hpp"
#include "facet/memory.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

namespace facet {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A cube texture of six n x n faces, level 0 zeroed, named `source`: within
// the budget with its mipmaps (a third more) and the sampler's copy of them
// (tiles of 4 x 4 texels that hold 20; 8 bytes a texel for colour, 4 for
// data).
std::shared_ptr<Texture> empty_cube(int n, bool srgb, const std::string& source) {
    const uint64_t texels = uint64_t(6) * uint64_t(n) * uint64_t(n);
    require_within_budget(texels * 4 * 4 / 3 + texels * 20 / 16 * 4 / 3 * (srgb ? 8 : 4),
                          "a cube map of six " + std::to_string(n) + "x" + std::to_string(n) +
                              " faces",
                          source);
    auto cube = std::make_shared<Texture>();
    cube->source = source;
    cube->width = cube->height = n;
    cube->srgb = srgb;
    cube->faces = 6;
    cube->texels.resize(size_t(n) * size_t(n) * 6);
    return cube;
}

// Level 0 of `image` bilinearly at (u, v) in texels, in linear light:
// columns wrap around (longitude), rows clamp at the poles.
glm::vec4 equirect_texel(const Texture& image, double u, double v) {
    const int w = image.width, h = image.height;
    const double x = u - 0.5, y = std::clamp(v - 0.5, 0.0, double(h - 1));
    const int x0 = int(std::floor(x)), y0 = int(y);
    const double fx = x - x0, fy = y - y0;
    const auto at = [&](int i, int j) {
        i = ((i % w) + w) % w;
        j = std::min(j, h - 1);
        return glm::dvec4(decode_texel(image.texels[size_t(j) * size_t(w) + size_t(i)], image.srgb));
    };
    const glm::dvec4 top = glm::mix(at(x0, y0), at(x0 + 1, y0), fx);
    const glm::dvec4 bottom = glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx);
    return glm::vec4(glm::mix(top, bottom, fy));
}

std::shared_ptr<Texture> cube_from_equirect(const Texture& image) {
    const int n = std::max(1, image.height / 2);
    auto cube = empty_cube(n, image.srgb, image.source);
    for (int f = 0; f < 6; ++f)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const glm::dvec3 d = glm::normalize(cube_texel_direction(f, i, j, n));
                const double u = (0.5 + std::atan2(d.x, -d.z) / (2.0 * kPi)) * image.width;
                const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi * image.height;
                cube->texels[(size_t(f) * size_t(n) + size_t(j)) * size_t(n) + size_t(i)] =
                    encode_texel(equirect_texel(image, u, v), image.srgb);
            }
    return cube;
}

std::shared_ptr<Texture> cube_from_faces(const std::vector<std::filesystem::path>& files,
                                         bool srgb) {
    std::shared_ptr<Texture> cube;
    for (int f = 0; f < 6; ++f) {
        const std::shared_ptr<const Texture> face = load_texture(files[size_t(f)], srgb);
        if (face->width != face->height || (cube && face->width != cube->width))
            throw Error(ErrorCode::texture_load_failed,
                        "a cube map's faces must be square and all one size; this one is " +
                            std::to_string(face->width) + "x" + std::to_string(face->height),
                        files[size_t(f)].string());
        if (!cube) cube = empty_cube(face->width, srgb, files[0].string());
        std::copy(face->texels.begin(), face->texels.end(),
                  cube->texels.begin() + std::ptrdiff_t(size_t(f) * face->texels.size()));
    }
    return cube;
}

}  // namespace

glm::dvec3 cube_texel_direction(int f, double x, double y, int n) {
    const double sc = 2.0 * (x + 0.5) / n - 1.0, tc = 2.0 * (y + 0.5) / n - 1.0;
    switch (f) {
        case 0: return {1.0, -tc, -sc};
        case 1: return {-1.0, -tc, sc};
        case 2: return {sc, 1.0, tc};
        case 3: return {sc, -1.0, -tc};
        case 4: return {sc, -tc, 1.0};
        default: return {-sc, -tc, -1.0};
    }
}

std::shared_ptr<const Texture> load_cube(const std::vector<std::filesystem::path>& faces,
                                         bool srgb) {
    if (faces.size() != 1 && faces.size() != 6)
        throw Error(ErrorCode::texture_load_failed,
                    "a cube map is six faces or one equirectangular image, not " +
                        std::to_string(faces.size()) + " files");
    std::shared_ptr<Texture> cube =
        faces.size() == 6 ? cube_from_faces(faces, srgb)
                          : cube_from_equirect(*load_texture(faces[0], srgb));
    generate_mipmaps(*cube);
    cube->sampled();  // the sampler's levels now, not in the first frame
    spdlog::debug("cube map {}: faces of {}x{}, {} levels", cube->source, cube->width,
                  cube->height, cube->levels());
    return cube;
}

std::shared_ptr<const Texture> TextureCache::get_cube(
    const std::vector<std::filesystem::path>& faces, bool srgb) {
    std::string key = "cube:";
    for (const std::filesystem::path& f : faces) {
        std::error_code ec;
        const std::filesystem::path canonical = std::filesystem::weakly_canonical(f, ec);
        key += (ec ? f : canonical).string() + "|";
    }
    if (const auto found = textures_.find({key, srgb}); found != textures_.end())
        return found->second;
    std::shared_ptr<const Texture> cube = load_cube(faces, srgb);
    textures_.emplace(std::make_pair(key, srgb), cube);
    return cube;
}

}  // namespace facet
