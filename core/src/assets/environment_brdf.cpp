// The split-sum BRDF (facet/environment_map.hpp, facet_environment.brdf): how
// much of the prefiltered radiance a GGX surface reflects towards the
// viewer, as a scale A of its Fresnel reflectance f0 and a bias B.
//
// With Schlick's Fresnel F = f0 + (1 - f0) (1 - v.h)^5, the integral of
// the specular BRDF times n.l over the hemisphere is f0 A + B, where, for
// directions l sampled by the GGX distribution of half vectors h,
//     A = mean of (1 - Fc) W,  B = mean of Fc W,  Fc = (1 - v.h)^5,
//     W = V(n.l, n.v) n.l 4 (v.h) / (n.h)
// (V the height-correlated Smith visibility pbr shades with, and the
// sample's pdf D (n.h) / (4 v.h) divided out).
#include "assets/environment_cache.hpp"
#include "assets/environment_prefilter.hpp"

#include "facet/pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace facet {

namespace {

constexpr int kTableSize = 32;
constexpr int kTableSamples = 4096;

}  // namespace

// (A change to what this or the table holds changes kept tables:
// kBrdfVersion, environment_prefilter.hpp.)
glm::dvec2 split_sum_brdf(double n_v, double roughness, int samples) {
    n_v = std::max(n_v, 1e-4);  // as pbr holds it
    const double a = roughness * roughness, a2 = a * a;
    const glm::dvec3 v(std::sqrt(1.0 - n_v * n_v), 0.0, n_v);
    glm::dvec2 sum(0.0);
    for (int i = 0; i < samples; ++i) {
        const glm::dvec3 h = ggx_half_vector((i + 0.5) / samples, radical_inverse(uint32_t(i)), a2);
        const double cos_h = h.z;
        const double v_h = glm::dot(v, h);
        const glm::dvec3 l = 2.0 * v_h * h - v;
        const double n_l = l.z;
        if (n_l <= 0.0 || v_h <= 0.0) continue;
        const double vis = 0.5 / (n_l * std::sqrt(n_v * n_v * (1.0 - a2) + a2) +
                                  n_v * std::sqrt(n_l * n_l * (1.0 - a2) + a2));
        const double weight = vis * n_l * 4.0 * v_h / cos_h;
        const double fc = std::pow(1.0 - v_h, 5.0);
        sum += glm::dvec2((1.0 - fc) * weight, fc * weight);
    }
    return sum / double(samples);
}

namespace {

// The table's cells, computed: A and B of each, then those of the next
// cell along n.v (the ABI's record of four floats).
std::vector<float> computed_table() {
    std::vector<glm::vec2> cell(size_t(kTableSize) * kTableSize);
    ThreadPool pool(default_threads());
    pool.parallel_for(kTableSize, [&](int j, int) {
        for (int i = 0; i < kTableSize; ++i)
            cell[size_t(j) * kTableSize + size_t(i)] = glm::vec2(split_sum_brdf(
                double(i) / (kTableSize - 1), double(j) / (kTableSize - 1), kTableSamples));
    });
    std::vector<float> cells(cell.size() * 4);
    for (int j = 0; j < kTableSize; ++j)
        for (int i = 0; i < kTableSize; ++i) {
            const size_t k = size_t(j) * kTableSize + size_t(i);
            const size_t next = size_t(j) * kTableSize + size_t(std::min(i + 1, kTableSize - 1));
            const float record[4] = {cell[k].x, cell[k].y, cell[next].x, cell[next].y};
            std::memcpy(&cells[k * 4], record, sizeof record);
        }
    return cells;
}

}  // namespace

// Made once a process, or read from where an earlier run kept it.
const BrdfTable& brdf_table() {
    static const BrdfTable table = [] {
        BrdfTable t;
        t.size = kTableSize;
        const auto kept = brdf_cache_file(kTableSize, kTableSamples);
        if (kept)
            if (auto cells = read_brdf_cache(*kept, size_t(kTableSize) * kTableSize * 4)) {
                t.cells = std::move(*cells);
                return t;
            }
        t.cells = computed_table();
        if (kept) write_brdf_cache(*kept, t.cells);
        return t;
    }();
    return table;
}

}  // namespace facet
