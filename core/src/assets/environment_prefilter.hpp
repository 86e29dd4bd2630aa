// Prefiltering an environment (facet/environment_map.hpp): from a function that
// gives the radiance in any direction to the maps of facet_environment.
//
// Takes: the radiance function, level 0's size, the GGX samples per texel
// and a thread pool. Gives: EnvironmentMaps. Every level is a cube of six
// faces with a border of one texel (the ABI's layout), so that a bilinear
// lookup anywhere reads four texels of one face and shows no seam.
#pragma once

#include "base/thread_pool.hpp"

#include "facet/environment_map.hpp"
#include "facet/texture.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace facet {

constexpr double kEnvironmentPi = 3.14159265358979323846;

// What the maps of an image are, as a number: change it with any change to
// what they hold for the same bytes and settings - prefilter_environment(),
// prefilter_input() (the default size, the supersampling), the decoding
// (environment.cpp: decode_image, equirect_radiance, faces_radiance), or a
// new stb_image - so that maps kept on disk from before
// (environment_cache.hpp) are made again. kBrdfVersion is the same for
// split_sum_brdf() and the table (environment_brdf.cpp).
constexpr uint32_t kPrefilterVersion = 1;
constexpr uint32_t kBrdfVersion = 1;

// Bilinear in a bordered cube level of n x n faces whose texel (x, y) of
// face f (-1 <= x, y <= n) is at(f, x, y), in direction d (any length; no
// direction reads the face's middle).
template <class At>
glm::vec3 bilinear_bordered(int n, glm::vec3 d, const At& at) {
    glm::vec2 uv;
    const int face = cube_face(d, uv);
    const float u = uv.x == uv.x ? uv.x : 0.5f, v = uv.y == uv.y ? uv.y : 0.5f;  // a NaN minor component
    const float s = float(n);
    const float x = std::clamp(u * s - 0.5f, -0.5f, s - 0.5f);
    const float y = std::clamp(v * s - 0.5f, -0.5f, s - 0.5f);
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float fx = x - x0, fy = y - y0;
    const int i = int(x0), j = int(y0);
    const glm::vec3 top = glm::mix(at(face, i, j), at(face, i + 1, j), fx);
    const glm::vec3 bottom = glm::mix(at(face, i, j + 1), at(face, i + 1, j + 1), fx);
    return glm::mix(top, bottom, fy);
}

// i's bits reversed, as a fraction: the Van der Corput sequence.
inline double radical_inverse(uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
    i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
    i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
    i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
    return double(i) * 0x1p-32;
}

// The half vector of GGX sample (u, v) of the unit square for alpha^2
// `a2`, around +Z: its density over half vectors is D(h) (n.h).
inline glm::dvec3 ggx_half_vector(double u, double v, double a2) {
    const double cos_h = std::sqrt((1.0 - v) / (1.0 + (a2 - 1.0) * v));
    const double sin_h = std::sqrt(std::max(0.0, 1.0 - cos_h * cos_h));
    const double phi = 2.0 * kEnvironmentPi * u;
    return {sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h};
}

// Radiance in a direction (unit), in linear RGB.
using RadianceFn = std::function<glm::vec3(glm::dvec3)>;

struct PrefilterInput {
    RadianceFn radiance;
    std::string source;  // names the result
    int size = 0;        // level 0's faces, a power of two 8..2048
    int supersample = 1;  // level 0's texel: the mean of supersample^2 directions
    int samples = 64;    // GGX samples per texel of the rough levels
};

// The levels a cube of `size` gets: one per halving down to 8 texels a
// side, at most FACET_ENVIRONMENT_MAX_LEVELS.
int environment_levels(int size);

// The bytes prefilter_environment() holds at its peak for `size`.
uint64_t prefilter_bytes(int size);

EnvironmentMaps prefilter_environment(const PrefilterInput& in, ThreadPool& pool);

}  // namespace facet
