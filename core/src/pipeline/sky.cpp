// The sky pass's pixel directions (sky.hpp).
#include "pipeline/sky.hpp"

namespace facet {

void sky_directions(SkyRows& sky, const glm::mat4& view, const glm::mat4& projection,
                    const glm::vec3& camera, bool orthographic, int width, int height) {
    const glm::mat4 to_world = glm::inverse(projection * view);
    if (orthographic) {
        const glm::vec3 forward = -glm::vec3(glm::inverse(view)[2]);
        sky.origin = forward, sky.dx = sky.dy = glm::vec3(0.0f);
        return;
    }
    // A point of the image on a plane of constant clip w in front of the
    // camera: affine in the pixel's position, as is its direction.
    const glm::vec4 ahead = projection * glm::vec4(0.0f, 0.0f, -1.0f, 1.0f);
    const float z = ahead.z / ahead.w;
    const auto direction = [&](float x, float y) {
        const glm::vec4 p = to_world * glm::vec4(2.0f * x / float(width) - 1.0f,
                                                 1.0f - 2.0f * y / float(height), z, 1.0f);
        return glm::vec3(p) / p.w - camera;
    };
    sky.origin = direction(0.0f, 0.0f);
    sky.dx = direction(1.0f, 0.0f) - sky.origin;
    sky.dy = direction(0.0f, 1.0f) - sky.origin;
}

}  // namespace facet
