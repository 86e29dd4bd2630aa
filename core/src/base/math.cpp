#include "facet/math.hpp"

#include <cmath>

namespace facet {

glm::mat4 Transform::matrix() const {
    glm::mat4 m = glm::mat4_cast(rotation);
    m[0] *= scale.x;
    m[1] *= scale.y;
    m[2] *= scale.z;
    m[3] = glm::vec4(translation, 1.0f);
    return m;
}

glm::quat euler_degrees(const glm::vec3& degrees) {
    const glm::vec3 r = glm::radians(degrees);
    const glm::quat qx = glm::angleAxis(r.x, glm::vec3(1, 0, 0));
    const glm::quat qy = glm::angleAxis(r.y, glm::vec3(0, 1, 0));
    const glm::quat qz = glm::angleAxis(r.z, glm::vec3(0, 0, 1));
    return qz * qy * qx;
}

namespace {

// look_at in precision T.
template <class T>
glm::mat<4, 4, T> look_at_in(const glm::vec<3, T>& eye, const glm::vec<3, T>& target,
                             const glm::vec<3, T>& up) {
    const glm::vec<3, T> f = glm::normalize(target - eye);
    const glm::vec<3, T> s = glm::normalize(glm::cross(f, up));
    const glm::vec<3, T> u = glm::cross(s, f);
    glm::mat<4, 4, T> m(T(1));
    m[0][0] = s.x; m[1][0] = s.y; m[2][0] = s.z;
    m[0][1] = u.x; m[1][1] = u.y; m[2][1] = u.z;
    m[0][2] = -f.x; m[1][2] = -f.y; m[2][2] = -f.z;
    m[3][0] = -glm::dot(s, eye);
    m[3][1] = -glm::dot(u, eye);
    m[3][2] = glm::dot(f, eye);
    return m;
}

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

}  // namespace

glm::mat4 look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up) {
    const glm::mat4 m = look_at_in<float>(eye, target, up);
    if (finite(m)) return m;
    // Float's squares overflow past about 1.8e19 (a camera 1e20 away) and
    // underflow below 1e-19: the same matrix, worked out in double.
    return glm::mat4(look_at_in<double>(glm::dvec3(eye), glm::dvec3(target), glm::dvec3(up)));
}

// Both projections write z_clip = a * z_view + b * w_view, chosen so that
// depth = z_clip / w_clip is 0 at `near` and 1 at `far` (or the reverse).
glm::mat4 perspective(float fov_y, float aspect, float near, float far, bool reversed_z) {
    const float f = 1.0f / std::tan(fov_y * 0.5f);
    const float n = reversed_z ? far : near;   // plane that maps to depth 0
    const float d = reversed_z ? near : far;   // plane that maps to depth 1
    glm::mat4 m(0.0f);
    m[0][0] = f / aspect;
    m[1][1] = f;
    // depth(zv) = (A*zv + B) / -zv with depth(-n) = 0 and depth(-d) = 1.
    m[2][2] = d / (n - d);
    m[3][2] = n * d / (n - d);
    m[2][3] = -1.0f;
    return m;
}

glm::mat4 orthographic(float height, float aspect, float near, float far, bool reversed_z) {
    const float n = reversed_z ? far : near;
    const float d = reversed_z ? near : far;
    glm::mat4 m(1.0f);
    m[0][0] = 2.0f / (height * aspect);
    m[1][1] = 2.0f / height;
    // depth(zv) = (-zv - n) / (d - n).
    m[2][2] = -1.0f / (d - n);
    m[3][2] = -n / (d - n);
    return m;
}

// The cofactor matrix of M is det(M) times its inverse-transpose, so it maps
// normals to the same directions (times the sign of det, for mirrors), and
// unlike the inverse it stays finite when M is singular or nearly so.
glm::mat3 normal_matrix(const glm::mat4& model) {
    const glm::vec3 a(model[0]), b(model[1]), c(model[2]);
    const float det = glm::dot(a, glm::cross(b, c));
    const glm::mat3 cofactor(glm::cross(b, c), glm::cross(c, a), glm::cross(a, b));
    return det < 0.0f ? -cofactor : cofactor;
}

}  // namespace facet
