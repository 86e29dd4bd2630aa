#include "camera_controller.hpp"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>

namespace facet::view {

namespace {

constexpr float kMaxElevation = 89.0f;  // degrees from the horizon

// The closest zoom may bring the camera to its target: far enough that
// float positions stay distinct wherever the target is.
float min_distance(const glm::vec3& target) {
    return 1e-4f * std::max(1.0f, glm::length(target));
}

// Any unit vector perpendicular to unit `u`.
glm::vec3 perpendicular(const glm::vec3& u) {
    const glm::vec3 a = std::abs(u.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    return glm::normalize(glm::cross(u, a));
}

}  // namespace

void CameraController::reset(const Camera& home) {
    home_ = home;
    camera_ = home;
    flying_ = false;
    speed_ = std::max(0.1f, glm::length(home.target - home.position));
}

glm::vec3 CameraController::up() const {
    const float n = glm::length(camera_.up);
    return n > 0.0f ? camera_.up / n : glm::vec3(0, 1, 0);
}

// Splits `direction` into elevation above the horizon and a horizontal
// heading, turns the heading about up by yaw, and adds pitch to the
// elevation (clamped short of the poles).
glm::vec3 CameraController::turned(const glm::vec3& direction, float yaw_degrees,
                                   float pitch_degrees) const {
    const float length = glm::length(direction);
    if (!(length > 0.0f)) return direction;
    const glm::vec3 u = up(), d = direction / length;
    const float elevation = std::asin(std::clamp(glm::dot(d, u), -1.0f, 1.0f));
    glm::vec3 heading = d - glm::dot(d, u) * u;
    heading = glm::length(heading) > 1e-6f ? glm::normalize(heading) : perpendicular(u);
    const float yaw = glm::radians(yaw_degrees);
    const glm::vec3 side = glm::cross(u, heading);
    heading = heading * std::cos(yaw) + side * std::sin(yaw);
    const float limit = glm::radians(kMaxElevation);
    const float e = std::clamp(elevation + glm::radians(pitch_degrees), -limit, limit);
    return length * (std::cos(e) * heading + std::sin(e) * u);
}

void CameraController::orbit(float yaw_degrees, float pitch_degrees) {
    camera_.position =
        camera_.target + turned(camera_.position - camera_.target, yaw_degrees, pitch_degrees);
}

void CameraController::look(float yaw_degrees, float pitch_degrees) {
    camera_.target =
        camera_.position + turned(camera_.target - camera_.position, yaw_degrees, -pitch_degrees);
}

void CameraController::pan(float dx, float dy, float height) {
    if (!(height > 0.0f)) return;
    const glm::vec3 offset = camera_.target - camera_.position;
    const float distance = glm::length(offset);
    if (!(distance > 0.0f)) return;
    const float view_height = camera_.orthographic
                                  ? camera_.ortho_height
                                  : 2.0f * distance * std::tan(glm::radians(camera_.fov_y) * 0.5f);
    const glm::vec3 forward = offset / distance;
    const glm::vec3 right = glm::normalize(glm::cross(forward, up()));
    const glm::vec3 screen_up = glm::cross(right, forward);
    const glm::vec3 shift = (-dx * right + dy * screen_up) * (view_height / height);
    camera_.position += shift;
    camera_.target += shift;
}

// Perspective: the camera moves along its view. Orthographic: the view
// height shrinks and the camera stays, so the near plane never cuts in.
void CameraController::zoom(float steps) {
    const float factor = std::pow(0.9f, steps);
    if (camera_.orthographic) {
        camera_.ortho_height = std::max(1e-6f, camera_.ortho_height * factor);
        return;
    }
    const glm::vec3 offset = camera_.position - camera_.target;
    const float distance = glm::length(offset);
    if (!(distance > 0.0f)) return;
    const float scaled = std::max(min_distance(camera_.target), distance * factor);
    camera_.position = camera_.target + offset * (scaled / distance);
}

void CameraController::fly(const glm::vec3& move, float seconds) {
    const glm::vec3 forward = glm::normalize(camera_.target - camera_.position);
    const glm::vec3 right = glm::normalize(glm::cross(forward, up()));
    const glm::vec3 delta = (move.x * right + move.y * up() + move.z * forward) * speed_ * seconds;
    camera_.position += delta;
    camera_.target += delta;
}

}  // namespace facet::view
