// Transforms and camera matrices.
//
// Conventions: right-handed world, camera looks down -Z in view space,
// column-major GLM matrices. Projections map view-space depth to clip-space
// z in [0, w] (D3D/Vulkan range). With reversed-Z (the default) the near
// plane maps to depth 1 and the far plane to 0, which spreads float32 depth
// precision evenly over distance; the depth test is then "greater" (the
// scene default is greater_equal).
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace facet {

struct Transform {
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z
    glm::vec3 scale{1.0f};

    // Model matrix M = T * R * S.
    glm::mat4 matrix() const;
};

// Rotation from Euler angles in degrees, applied X, then Y, then Z
// (R = Rz * Ry * Rx).
glm::quat euler_degrees(const glm::vec3& degrees);

// View matrix of a camera at `eye` looking at `target`.
glm::mat4 look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& up);

// Perspective projection; fov_y in radians. Depth 0..w, reversed if asked.
glm::mat4 perspective(float fov_y, float aspect, float near, float far, bool reversed_z);

// Orthographic projection of a box `height` tall centred on the view axis.
glm::mat4 orthographic(float height, float aspect, float near, float far, bool reversed_z);

// Transforms normals by `model`: the inverse-transpose of its upper 3x3 up to
// a positive scale (normalise the result), computed as the cofactor matrix,
// which stays finite where the model matrix is singular or nearly so.
glm::mat3 normal_matrix(const glm::mat4& model);

}  // namespace facet
