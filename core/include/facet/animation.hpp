// Animation: keyframe tracks for transforms and the camera, and the time
// line a scene plays.
//
//     animation: {fps: 24, start: 0, end: 6}   # the sequence; end: the last key by default
//     camera:
//       position: [0, 1, 3]
//       target: [0, 0.5, 0]
//       animate:
//         orbit: 30                 # degrees a second about the target, around up
//         position: {keys: [{time: 0, value: [0, 1, 3]}, {time: 2, value: [3, 1, 0]}]}
//         target: ...               # and fov_y: {keys: [{time: 0, value: 45}, ...]}
//     objects:
//       - mesh: ...
//         animate:
//           spin: 45                # degrees a second about +Y, or {axis: [0, 0, 1], speed: 45}
//           position: {keys: [...], interpolation: step}   # linear (default) or step
//           rotation: {keys: [{time: 0, value: [0, 0, 0]}, {time: 1, value: {axis: [0, 1, 0], angle: 90}}]}
//           scale: {keys: [{time: 0, value: 1}, {time: 1, value: [1, 2, 1]}]}
//
// A track holds its first key's value before it and its last key's after
// it. Rotation keys are slerped the short way, so keys less than 180 degrees
// apart turn as written; a spin turns without limit. A mesh file's own node
// animation (glTF) plays through the same tracks (Mesh::nodes).
//
// Posing is a pure function of time: the same time gives the same scene,
// bit for bit, whatever was posed before. That is what lets a frame of a
// sequence render alone, or on another machine, as it does in the sequence.
#pragma once

#include "facet/math.hpp"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <vector>

namespace facet {

enum class Interpolation { linear, step };

template <class T>
struct Track {
    std::vector<double> times;  // seconds, strictly increasing
    std::vector<T> values;      // one per time
    Interpolation interpolation = Interpolation::linear;

    bool empty() const { return times.empty(); }
    double end() const { return times.empty() ? 0.0 : times.back(); }
    // The value at time t: held before the first key and after the last;
    // between two keys, the earlier one's (step) or a mix (linear; rotations
    // slerp).
    T at(double t) const;
};

// What animates a transform: tracks for each component, and a spin (a
// turntable) on top of the rotation.
struct TransformTracks {
    Track<glm::vec3> position;
    Track<glm::quat> rotation;
    Track<glm::vec3> scale;
    glm::vec3 spin_axis{0.0f, 1.0f, 0.0f};  // unit length
    double spin = 0.0;                      // degrees a second

    bool empty() const {
        return position.empty() && rotation.empty() && scale.empty() && spin == 0.0;
    }
    // The time the animation ends: its last key, or one turn of its spin.
    double end() const;
    // `rest` with each animated component replaced by its track's value at
    // t, and then turned by the spin.
    Transform at(double t, const Transform& rest) const;
};

struct Camera;

struct CameraTracks {
    Track<glm::vec3> position;
    Track<glm::vec3> target;
    Track<float> fov_y;
    double orbit = 0.0;  // degrees a second about the target, around up

    bool empty() const {
        return position.empty() && target.empty() && fov_y.empty() && orbit == 0.0;
    }
    double end() const;
    Camera at(double t, const Camera& rest) const;
};

// The stretch of time a scene plays (`animation:`): the viewer loops over
// [start, end), and a sequence's frame k is at time k / fps.
struct Timeline {
    double fps = 30.0;
    double start = 0.0;
    double end = 0.0;  // <= start: nothing moves
    bool animated() const { return end > start; }
    // The frame at or after `start` and the first at or after `end`: the
    // frames [first, last) a whole sequence renders.
    long first_frame() const;
    long end_frame() const;
    // The frame showing at time t: the last that starts at or before it.
    long frame_at(double t) const;
    double time_of(long frame) const { return double(frame) / fps; }
};

}  // namespace facet
