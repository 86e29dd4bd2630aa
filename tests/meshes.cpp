#include "meshes.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>

namespace facet::test {

Mesh uv_sphere(int rings, glm::vec3 radii, glm::vec3 centre) {
    const int segments = 2 * rings;
    const size_t vertices = size_t(rings + 1) * size_t(segments + 1);
    Mesh m;
    m.positions.reserve(vertices);
    m.normals.reserve(vertices);
    m.uvs.reserve(vertices);
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            const float theta = glm::pi<float>() * float(r) / float(rings);
            const float phi = glm::two_pi<float>() * float(s % segments) / float(segments);
            const glm::vec3 unit(std::sin(theta) * std::cos(phi), std::cos(theta),
                                 std::sin(theta) * std::sin(phi));
            m.positions.push_back(centre + radii * unit);
            m.normals.push_back(glm::normalize(unit / radii));
            m.uvs.push_back({float(s) / float(segments), float(r) / float(rings)});
        }
    m.indices.reserve(size_t(rings) * size_t(segments) * 6);
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            // a, b along the ring; c, d one ring down (towards -Y).
            const uint32_t a = uint32_t(r * (segments + 1) + s), b = a + 1,
                           c = a + uint32_t(segments + 1), d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
        }
    m.bounds = compute_bounds(m.positions);
    return m;
}

}  // namespace facet::test
