// Tangent frames where a file has none (tangents.hpp).
#include "assets/tangents.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace facet {

namespace {

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// v without its component along unit n, at unit length; zero if nothing is left.
glm::dvec3 in_plane(const glm::dvec3& v, const glm::dvec3& n) {
    const glm::dvec3 p = v - n * glm::dot(n, v);
    const double length = glm::length(p);
    return length > 1e-12 && std::isfinite(length) ? p / length : glm::dvec3(0.0);
}

// The angle of triangle (a, b, c) at a.
double corner_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 e = b - a, f = c - a;
    const double le = glm::length(e), lf = glm::length(f);
    if (!(le > 0.0) || !(lf > 0.0)) return 0.0;
    return std::acos(std::clamp(glm::dot(e, f) / (le * lf), -1.0, 1.0));
}

// A copy of vertex i at the end of every array; its index.
uint32_t split_vertex(Mesh& m, uint32_t i) {
    const auto copy = [i](auto& v) {
        if (!v.empty()) v.push_back(v[i]);
    };
    copy(m.positions);
    copy(m.normals);
    copy(m.uvs);
    copy(m.uvs1);
    copy(m.colors);
    return uint32_t(m.positions.size() - 1);
}

}  // namespace

void generate_tangents(Mesh& m) {
    const size_t corners = m.indices.size();
    // Each corner's tangent direction, weighted by its angle, and its
    // handedness (0: its triangle has no UV area and says nothing).
    std::vector<glm::dvec3> direction(corners, glm::dvec3(0.0));
    std::vector<int> handedness(corners, 0);
    for (size_t t = 0; t + 2 < corners; t += 3) {
        const uint32_t* idx = &m.indices[t];
        glm::dvec3 p[3];
        glm::dvec2 uv[3];
        for (int k = 0; k < 3; ++k) {
            p[k] = glm::dvec3(m.positions[idx[k]]);
            uv[k] = {m.uvs[idx[k]].x, -double(m.uvs[idx[k]].y)};  // u, and up the texture
        }
        const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
        const glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
        const double area = d1.x * d2.y - d2.x * d1.y;  // twice the UV area, signed
        if (!(std::abs(area) > 0.0)) continue;
        const glm::dvec3 along_u = (e1 * d2.y - e2 * d1.y) / area;
        const glm::dvec3 along_up = (e2 * d1.x - e1 * d2.x) / area;
        if (!finite(along_u) || !finite(along_up)) continue;
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 n(m.normals[idx[k]]);
            const glm::dvec3 tangent = in_plane(along_u, n);
            if (tangent == glm::dvec3(0.0)) continue;
            direction[t + k] = tangent * corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            handedness[t + k] = glm::dot(glm::cross(n, along_u), along_up) < 0.0 ? -1 : 1;
        }
    }

    // A vertex whose corners disagree on handedness: the left-handed ones
    // move to a copy of it.
    const size_t original = m.positions.size();
    std::vector<int> seen(original, 0);  // bit 0: right-handed corners, bit 1: left
    for (size_t c = 0; c < corners; ++c)
        if (handedness[c]) seen[m.indices[c]] |= handedness[c] > 0 ? 1 : 2;
    std::vector<uint32_t> copy_of(original, UINT32_MAX);
    for (size_t c = 0; c < corners; ++c) {
        const uint32_t i = m.indices[c];
        if (seen[i] != 3 || handedness[c] >= 0) continue;
        if (copy_of[i] == UINT32_MAX) copy_of[i] = split_vertex(m, i);
        m.indices[c] = copy_of[i];
    }

    const size_t count = m.positions.size();
    std::vector<glm::dvec3> sum(count, glm::dvec3(0.0));
    std::vector<int> sign(count, 0);
    for (size_t c = 0; c < corners; ++c) {
        const uint32_t i = m.indices[c];
        sum[i] += direction[c];
        if (handedness[c]) sign[i] = handedness[c];
    }
    m.tangents.resize(count);
    for (size_t i = 0; i < count; ++i) {
        const glm::dvec3 n(m.normals[i]);
        const glm::dvec3 t = in_plane(sum[i], n);  // zero: no frame
        m.tangents[i] = glm::vec4(glm::vec3(t), sign[i] < 0 ? -1.0f : 1.0f);
    }
}

}  // namespace facet
