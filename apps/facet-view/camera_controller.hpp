// Camera controls for facet-view, with no window system in them: the viewer
// turns SDL events into these calls, and the tests call them directly.
//
// Orbit mode (the default) turns the camera around its target: drag to
// orbit, pan to move camera and target together, wheel to zoom (the
// distance to the target scales). Fly mode turns the camera in place and
// moves it: WASD along the view, up and down along the world's up axis,
// at `speed` scene units per second.
#pragma once

#include <facet/scene.hpp>

#include <glm/glm.hpp>

namespace facet::view {

class CameraController {
public:
    explicit CameraController(const Camera& home = {}) { reset(home); }

    // Back to `home` (the scene file's camera), in orbit mode.
    void reset(const Camera& home);
    void reset() { reset(home_); }

    // Orbit: yaw and pitch in degrees; pitch stays within +-89 degrees of
    // the horizon, so the view never flips over the pole.
    void orbit(float yaw_degrees, float pitch_degrees);
    // Pan by a drag of (dx, dy) points in a view `height` points tall: the
    // point under the cursor at the target's depth follows it.
    void pan(float dx, float dy, float height);
    // Zoom by wheel steps: each step brings the camera 10% closer (an
    // orthographic camera's view height shrinks 10% instead).
    void zoom(float steps);

    // Fly: turns in place (degrees), and moves by `move` in view axes
    // (x right, y world up, z forward) scaled by speed and `seconds`.
    void look(float yaw_degrees, float pitch_degrees);
    void fly(const glm::vec3& move, float seconds);
    void faster() { speed_ *= 1.5f; }
    void slower() { speed_ /= 1.5f; }
    float speed() const { return speed_; }

    bool flying() const { return flying_; }
    void set_flying(bool on) { flying_ = on; }

    const Camera& camera() const { return camera_; }
    const Camera& home() const { return home_; }

private:
    glm::vec3 up() const;  // the world up axis, normalised
    // `direction` turned by yaw about the up axis and pitch towards it.
    glm::vec3 turned(const glm::vec3& direction, float yaw_degrees, float pitch_degrees) const;

    Camera home_;
    Camera camera_;
    bool flying_ = false;
    float speed_ = 1.0f;
};

}  // namespace facet::view
