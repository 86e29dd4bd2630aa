// Prefiltering an environment (environment_prefilter.hpp): level 0 from the
// radiance function, a box-filtered chain of it for the samples to read,
// the rough levels by GGX importance sampling, and the nine spherical
// harmonics of the irradiance.
#include "assets/environment_prefilter.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace facet {

namespace {

// A cube level of n x n faces with a one-texel border, RGB.
struct CubeLevel {
    int n = 0;
    std::vector<glm::vec3> texels;  // 6 (n + 2)^2

    explicit CubeLevel(int size) : n(size), texels(size_t(6) * size_t(size + 2) * size_t(size + 2)) {}
    size_t index(int f, int x, int y) const {
        const size_t row = size_t(n) + 2;
        return size_t(f) * row * row + size_t(y + 1) * row + size_t(x + 1);
    }
    glm::vec3& at(int f, int x, int y) { return texels[index(f, x, y)]; }
    const glm::vec3& at(int f, int x, int y) const { return texels[index(f, x, y)]; }
    // bilinear_bordered, with the four texels addressed once.
    glm::vec3 bilinear(glm::vec3 d) const {
        glm::vec2 uv;
        const int face = cube_face(d, uv);
        const float s = float(n);
        const float x = std::clamp(uv.x * s - 0.5f, -0.5f, s - 0.5f);
        const float y = std::clamp(uv.y * s - 0.5f, -0.5f, s - 0.5f);
        const float x0 = std::floor(x), y0 = std::floor(y);
        const float fx = x - x0, fy = y - y0;
        const size_t row = size_t(n) + 2;
        const glm::vec3* t = &texels[index(face, int(x0), int(y0))];
        return glm::mix(glm::mix(t[0], t[1], fx), glm::mix(t[row], t[row + 1], fx), fy);
    }
};

// Every texel of `level`, border included, as fn(face, x, y), one row of
// one face a task.
template <class Fn>
void each_texel(CubeLevel& level, ThreadPool& pool, Fn&& fn) {
    const int rows = level.n + 2;
    pool.parallel_for(6 * rows, [&](int task, int) {
        const int f = task / rows, y = task % rows - 1;
        for (int x = -1; x <= level.n; ++x) level.at(f, x, y) = fn(f, x, y);
    });
}

// Half of `finer`: each texel the mean of the 2x2 it covers; the border
// then from the neighbouring faces' texels.
CubeLevel half_of(const CubeLevel& finer, ThreadPool& pool) {
    CubeLevel level(std::max(1, finer.n / 2));
    const int n = level.n;
    pool.parallel_for(6 * n, [&](int task, int) {
        const int f = task / n, y = task % n;
        for (int x = 0; x < n; ++x)
            level.at(f, x, y) = 0.25f * (finer.at(f, 2 * x, 2 * y) + finer.at(f, 2 * x + 1, 2 * y) +
                                         finer.at(f, 2 * x, 2 * y + 1) +
                                         finer.at(f, 2 * x + 1, 2 * y + 1));
    });
    // A border texel reads the face its direction falls on, nearest: that
    // face's texel is inside it, so no border reads another border.
    for (int f = 0; f < 6; ++f)
        for (int y = -1; y <= n; ++y)
            for (int x = -1; x <= n; ++x) {
                if (x >= 0 && x < n && y >= 0 && y < n) continue;
                glm::vec2 uv;
                const int g = cube_face(glm::vec3(cube_texel_direction(f, x, y, n)), uv);
                const int i = std::clamp(int(uv.x * float(n)), 0, n - 1);
                const int j = std::clamp(int(uv.y * float(n)), 0, n - 1);
                level.at(f, x, y) = level.at(g, i, j);
            }
    return level;
}

// A sample of the GGX lobe around the normal, for N = V = R: the direction
// in the normal's frame (z along it), its weight (n.l) and the chain level
// it reads (the nearest: a second, blended, would double the work for a
// difference the lobe's average hides).
struct LobeSample {
    glm::vec3 l;
    float weight;
    int level;  // of the chain: the nearest to the sample's level of detail
};

std::vector<LobeSample> lobe_samples(double roughness, int count, int size0, int chain_levels) {
    const double a = roughness * roughness, a2 = a * a;
    const double texel = 4.0 * kEnvironmentPi / (6.0 * double(size0) * double(size0));
    std::vector<LobeSample> samples;
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 h = ggx_half_vector((i + 0.5) / count, radical_inverse(uint32_t(i)), a2);
        const double cos_h = h.z;
        const glm::dvec3 l = 2.0 * cos_h * h - glm::dvec3(0.0, 0.0, 1.0);
        if (l.z <= 0.0) continue;
        // pdf of l: D(h) (n.h) / (4 v.h), with v.h = n.h
        const double k = cos_h * cos_h * (a2 - 1.0) + 1.0;
        const double pdf = a2 / (kEnvironmentPi * k * k) / 4.0;
        const double solid_angle = 1.0 / (double(count) * pdf);
        const double lod = std::clamp(0.5 * std::log2(solid_angle / texel) + 1.0, 0.0,
                                      double(chain_levels - 1));
        samples.push_back({glm::vec3(l), float(l.z), int(std::lround(lod))});
    }
    return samples;
}

// The GGX-weighted mean of the chain around unit direction n.
glm::vec3 convolve(const std::vector<CubeLevel>& chain, const std::vector<LobeSample>& lobe,
                   glm::dvec3 n) {
    // An orthonormal frame around n (Duff et al. 2017).
    const double sign = std::copysign(1.0, n.z), a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    const glm::vec3 t(glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x));
    const glm::vec3 bt(glm::dvec3(b, sign + n.y * n.y * a, -n.y));
    const glm::vec3 nf(n);
    glm::vec3 sum(0.0f);
    float weights = 0.0f;
    for (const LobeSample& s : lobe) {
        const glm::vec3 l = t * s.l.x + bt * s.l.y + nf * s.l.z;
        const glm::vec3 c = chain[size_t(s.level)].bilinear(l);
        sum += c * s.weight;
        weights += s.weight;
    }
    return weights > 0.0f ? sum / weights : chain[0].bilinear(nf);
}

// The solid angle of the part of a face of the unit cube (from z = 1) from
// its centre to (x, y), in the face's -1..1 coordinates.
double area_to(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0)); }

// Irradiance / pi as the ABI's polynomial, from the radiance of `level`.
std::array<glm::vec3, 9> irradiance_of(const CubeLevel& level) {
    std::array<glm::dvec3, 9> sh{};
    const int n = level.n;
    for (int f = 0; f < 6; ++f)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double x0 = 2.0 * x / n - 1.0, x1 = 2.0 * (x + 1) / n - 1.0;
                const double y0 = 2.0 * y / n - 1.0, y1 = 2.0 * (y + 1) / n - 1.0;
                const double w = area_to(x0, y0) - area_to(x0, y1) - area_to(x1, y0) + area_to(x1, y1);
                const glm::dvec3 d = glm::normalize(cube_texel_direction(f, x, y, n));
                const glm::dvec3 c = glm::dvec3(level.at(f, x, y)) * w;
                const double basis[9] = {1.0, d.y, d.z, d.x, d.x * d.y, d.y * d.z,
                                         3.0 * d.z * d.z - 1.0, d.x * d.z, d.x * d.x - d.y * d.y};
                for (int k = 0; k < 9; ++k) sh[size_t(k)] += c * basis[k];
            }
    // Each projection times its basis constant squared (the polynomial's
    // term is the harmonic's without its constant) and the cosine lobe's
    // band factor over pi: 1, 2/3, 1/4.
    const double y0 = 1.0 / (4.0 * kEnvironmentPi), y1 = 3.0 / (4.0 * kEnvironmentPi), y2 = 15.0 / (4.0 * kEnvironmentPi);
    const double y20 = 5.0 / (16.0 * kEnvironmentPi), y22 = 15.0 / (16.0 * kEnvironmentPi);
    const double scale[9] = {y0,          y1 * 2 / 3, y1 * 2 / 3, y1 * 2 / 3, y2 / 4,
                             y2 / 4,      y20 / 4,    y2 / 4,     y22 / 4};
    std::array<glm::vec3, 9> out{};
    for (int k = 0; k < 9; ++k) out[size_t(k)] = glm::vec3(sh[size_t(k)] * scale[k]);
    return out;
}

// The maps' RGBA texels of `levels`, at the ABI's offsets, a face's row
// a task.
void store_levels(EnvironmentMaps& maps, const std::vector<const CubeLevel*>& levels,
                  ThreadPool& pool) {
    size_t texels = 0;
    for (size_t l = 0; l < levels.size(); ++l) {
        maps.size[l] = uint32_t(levels[l]->n);
        maps.offset[l] = uint32_t(texels);
        texels += levels[l]->texels.size();
    }
    maps.levels = int(levels.size());
    maps.texels.resize(texels * 4);
    std::vector<std::pair<size_t, size_t>> rows;  // (level, first texel of a row)
    for (size_t l = 0; l < levels.size(); ++l)
        for (size_t i = 0; i < levels[l]->texels.size(); i += size_t(levels[l]->n) + 2)
            rows.emplace_back(l, i);
    pool.parallel_for(int(rows.size()), [&](int r, int) {
        const auto [l, first] = rows[size_t(r)];
        const CubeLevel& level = *levels[l];
        float* out = &maps.texels[(maps.offset[l] + first) * 4];
        for (size_t i = first; i < first + size_t(level.n) + 2; ++i, out += 4) {
            std::memcpy(out, &level.texels[i], 12);
            out[3] = 1.0f;
        }
    });
}

}  // namespace

int environment_levels(int size) {
    int levels = 1;
    while ((size >> levels) >= 8 && levels < FACET_ENVIRONMENT_MAX_LEVELS) ++levels;
    return levels;
}

uint64_t prefilter_bytes(int size) {
    // level 0's bordered faces, RGB; the chain and the levels each a third
    // more; the maps' RGBA copy of the levels
    const uint64_t level0 = uint64_t(6) * uint64_t(size + 2) * uint64_t(size + 2);
    return level0 * 12 * 4 / 3 * 2 + level0 * 16 * 4 / 3;
}

EnvironmentMaps prefilter_environment(const PrefilterInput& in, ThreadPool& pool) {
    const int levels = environment_levels(in.size);
    // Level 0: the radiance, each texel the mean over its area.
    std::vector<CubeLevel> chain;
    chain.emplace_back(in.size);
    const int ss = std::max(1, in.supersample);
    each_texel(chain[0], pool, [&](int f, int x, int y) {
        glm::dvec3 sum(0.0);
        for (int j = 0; j < ss; ++j)
            for (int i = 0; i < ss; ++i)
                sum += glm::dvec3(in.radiance(glm::normalize(cube_texel_direction(
                    f, x - 0.5 + (i + 0.5) / ss, y - 0.5 + (j + 0.5) / ss, in.size))));
        return glm::vec3(sum / double(ss * ss));
    });
    while (chain.back().n > 1) chain.push_back(half_of(chain.back(), pool));

    std::vector<CubeLevel> out;  // levels 1 on; level 0 is the chain's
    out.reserve(size_t(levels));
    for (int l = 1; l < levels; ++l) {
        const double roughness = double(l) / double(levels - 1);
        const auto lobe = lobe_samples(roughness, in.samples, in.size, int(chain.size()));
        CubeLevel level(in.size >> l);
        each_texel(level, pool, [&](int f, int x, int y) {
            return convolve(chain, lobe, glm::normalize(cube_texel_direction(f, x, y, level.n)));
        });
        out.push_back(std::move(level));
    }

    EnvironmentMaps maps;
    maps.source = in.source;
    // The harmonics from a level of at most 64 a side: as exact for them
    // (a box filter keeps each texel's energy), and a sixteenth the work.
    size_t coarse = 0;
    while (chain[coarse].n > 64) ++coarse;
    maps.irradiance = irradiance_of(chain[coarse]);
    std::vector<const CubeLevel*> stored = {&chain[0]};
    for (const CubeLevel& level : out) stored.push_back(&level);
    store_levels(maps, stored, pool);
    return maps;
}

}  // namespace facet
