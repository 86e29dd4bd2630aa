// Environments: an image all around the scene (`environment:` in a scene),
// shown behind everything, lighting surfaces, or both.
//
// The image is one equirectangular file (longitude across it, its middle
// column looking along -Z, as load_cube takes one) or six cube faces, +X,
// -X, +Y, -Y, +Z, -Z. An HDR file (.hdr, Radiance RGBE) gives radiance as
// it is; an 8-bit one (PNG, JPEG, ...) is decoded from sRGB and stops at 1.
//
// At load it is prefiltered for image-based lighting, as the
// "facet.environment" service hands it to shaders (<facet/shader_abi.h>
// says what each map holds): the diffuse irradiance as nine spherical
// harmonics, and the specular radiance convolved with the GGX lobe of
// rising roughness over the levels of a cube map, by importance sampling
// with filtered samples (each read from the source level whose texels are
// as large as the sample's share of the lobe; Krivanek and Colbert 2008).
// The work is shared out to threads; the result is kept per file content
// and settings while some scene holds it, so that a scene reloaded with
// the same environment takes it at once.
#pragma once

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace facet {

enum class EnvironmentUse { both, background, lighting };

struct EnvironmentSettings {
    // One equirectangular image, or six faces (+X, -X, +Y, -Y, +Z, -Z).
    std::vector<std::filesystem::path> files;
    // Degrees about X, then Y, then Z (world axes), turning the image
    // around the scene.
    glm::vec3 rotation{0.0f};
    float intensity = 1.0f;  // multiplies its radiance, 0..1e6
    EnvironmentUse use = EnvironmentUse::both;
    // The background's perceptual roughness, 0..1: 0 shows the image
    // sharp, more blurs it as a surface of that roughness would.
    float blur = 0.0f;
    // Texels a side of level 0's faces, a power of two 8..2048; 0: the
    // image's own (half an equirectangular image's height, or a face's
    // side), rounded down to a power of two, at most 1024.
    int size = 0;
    // GGX samples per texel of each prefiltered level, 1..4096.
    int samples = 64;

    bool lights() const { return use != EnvironmentUse::background; }
    bool shows() const { return use != EnvironmentUse::lighting; }
};

// An environment prefiltered: the maps of facet_environment, in their own
// frame and at intensity 1 (settings' rotation and intensity apply when a
// frame binds them).
struct EnvironmentMaps {
    std::string source;  // the file, or the first face
    int levels = 0;
    std::array<uint32_t, FACET_ENVIRONMENT_MAX_LEVELS> size{}, offset{};
    std::vector<float> texels;               // RGBA; facet_environment.texels
    std::array<glm::vec3, 9> irradiance{};  // facet_environment.irradiance's polynomial

    uint64_t bytes() const { return texels.size() * sizeof(float); }
    // Level l's texel (x, y) of face f, -1 <= x, y <= size[l] (the border).
    glm::vec3 texel(int l, int f, int x, int y) const {
        const size_t row = size[size_t(l)] + 2;
        const size_t i = offset[size_t(l)] + size_t(f) * row * row + size_t(y + 1) * row + size_t(x + 1);
        return {texels[4 * i], texels[4 * i + 1], texels[4 * i + 2]};
    }
};

// Loads the files of `settings` and prefilters them on `threads` threads
// (0: default_threads()), or takes them from the process's cache when
// the same bytes were prefiltered with the same size and samples and some
// scene still holds the result, or else from the maps an earlier run kept
// on disk (in $FACET_CACHE_DIR, else $XDG_CACHE_HOME/facet, else
// ~/.cache/facet; FACET_CACHE_DIR=off keeps none). Throws
// Error(file_not_found | not_a_file | texture_load_failed | over_budget |
// config_invalid) naming the file.
std::shared_ptr<const EnvironmentMaps> load_environment(const EnvironmentSettings& settings,
                                                         int threads = 0);

// Level l of `maps` in direction d (its frame, any length), bilinear
// across the bordered face: what the SDK's lookup computes, per lane.
glm::vec3 sample_environment(const EnvironmentMaps& maps, int level, glm::vec3 d);

// Irradiance / pi of `maps` at unit normal n (its frame), as the SDK
// evaluates it: the nine-term polynomial, at least 0.
glm::vec3 environment_irradiance(const EnvironmentMaps& maps, glm::vec3 n);

// The split-sum BRDF table of facet_environment.brdf (made once, at the
// first call): A and B per cell, the four floats of each cell as the ABI
// lays them out.
struct BrdfTable {
    int size = 0;
    std::vector<float> cells;  // [size * size][4]
};
const BrdfTable& brdf_table();
// A and B at n.v and perceptual roughness, in double, from `samples` GGX
// samples (Hammersley): what the table holds at its cells.
glm::dvec2 split_sum_brdf(double n_v, double roughness, int samples);

// A scene's environment: its settings and maps.
struct Environment {
    EnvironmentSettings settings;
    std::shared_ptr<const EnvironmentMaps> maps;

    explicit operator bool() const { return maps != nullptr; }
    // World direction -> the maps' frame: the inverse of the rotation.
    glm::mat3 to_environment() const;
    // The record a frame hands shaders (pointing into maps and the BRDF
    // table).
    facet_environment record() const;
};

}  // namespace facet
