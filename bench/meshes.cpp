#include "meshes.hpp"

#include <cmath>

namespace facet::bench {

std::shared_ptr<Mesh> uv_sphere(int rings) {
    const int segments = 2 * rings;
    auto m = std::make_shared<Mesh>();
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            const float theta = float(M_PI) * r / rings, phi = 2.0f * float(M_PI) * s / segments;
            const glm::vec3 p(std::sin(theta) * std::cos(phi), std::cos(theta),
                              std::sin(theta) * std::sin(phi));
            m->positions.push_back(p);
            m->normals.push_back(p);
            m->uvs.push_back({float(s) / segments, float(r) / rings});
        }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = uint32_t(r * (segments + 1) + s), b = a + 1,
                           c = a + uint32_t(segments + 1), d = c + 1;
            m->indices.insert(m->indices.end(), {a, b, c, b, d, c});
        }
    m->bounds = compute_bounds(m->positions);
    return m;
}

}  // namespace facet::bench
