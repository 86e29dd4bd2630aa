// Keyframe tracks and their evaluation (facet/animation.hpp), and posing a
// scene at a time (Scene::pose).
#include "facet/animation.hpp"

#include "facet/error.hpp"
#include "facet/scene.hpp"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

namespace facet {

namespace {

glm::vec3 mix(const glm::vec3& a, const glm::vec3& b, float u) { return a + (b - a) * u; }
float mix(float a, float b, float u) { return a + (b - a) * u; }
glm::quat mix(const glm::quat& a, const glm::quat& b, float u) { return glm::slerp(a, b, u); }

// The rotation by `degrees` about unit `axis`, with the angle reduced to
// one turn in double first: a spin's angle grows without limit, and float
// would lose its fraction after a few hours.
glm::quat turn(const glm::vec3& axis, double degrees) {
    return glm::angleAxis(float(glm::radians(std::fmod(degrees, 360.0))), axis);
}

// What draws of `mesh`: everything but what poses it (its nodes, clips,
// skins and deformations, which pose_mesh reads from the mesh itself).
Mesh drawable_copy(const Mesh& mesh) {
    Mesh m;
    m.source = mesh.source;
    m.positions = mesh.positions;
    m.normals = mesh.normals;
    m.uvs = mesh.uvs;
    m.uvs1 = mesh.uvs1;
    m.colors = mesh.colors;
    m.tangents = mesh.tangents;
    m.indices = mesh.indices;
    m.parts = mesh.parts;
    m.materials = mesh.materials;
    m.images = mesh.images;
    m.bounds = mesh.bounds;
    return m;
}

}  // namespace

template <class T>
T Track<T>::at(double t) const {
    // A NaN time takes the first key, as a time before it does.
    if (times.size() == 1 || !(t > times.front())) return values.front();
    if (!(t < times.back())) return values.back();
    // The key at or before t, and the one after.
    const size_t next = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin());
    const size_t k = next - 1;
    if (interpolation == Interpolation::step) return values[k];
    const double u = (t - times[k]) / (times[next] - times[k]);
    return mix(values[k], values[next], float(u));
}

template struct Track<glm::vec3>;
template struct Track<glm::quat>;
template struct Track<float>;

double TransformTracks::end() const {
    double end = std::max({position.end(), rotation.end(), scale.end()});
    if (spin != 0.0) end = std::max(end, 360.0 / std::abs(spin));
    return end;
}

Transform TransformTracks::at(double t, const Transform& rest) const {
    Transform out = rest;
    if (!position.empty()) out.translation = position.at(t);
    if (!rotation.empty()) out.rotation = rotation.at(t);
    if (!scale.empty()) out.scale = scale.at(t);
    if (spin != 0.0) out.rotation = glm::normalize(turn(spin_axis, spin * t) * out.rotation);
    return out;
}

double CameraTracks::end() const {
    double end = std::max({position.end(), target.end(), fov_y.end()});
    if (orbit != 0.0) end = std::max(end, 360.0 / std::abs(orbit));
    return end;
}

Camera CameraTracks::at(double t, const Camera& rest) const {
    Camera out = rest;
    if (!position.empty()) out.position = position.at(t);
    if (!target.empty()) out.target = target.at(t);
    if (!fov_y.empty()) out.fov_y = fov_y.at(t);
    if (orbit != 0.0)
        out.position = out.target + turn(out.up, orbit * t) * (out.position - out.target);
    return out;
}

namespace {
// Frames that a time falls on up to rounding (0.1 s at 30 fps is frame 3,
// though 0.1 * 30 is 3.0000000000000004 in double) count as that frame.
constexpr double kFrameTolerance = 1e-6;
}  // namespace

long Timeline::first_frame() const { return long(std::ceil(start * fps - kFrameTolerance)); }
long Timeline::end_frame() const { return long(std::ceil(end * fps - kFrameTolerance)); }
long Timeline::frame_at(double t) const { return long(std::floor(t * fps + kFrameTolerance)); }

void Object::pose(double t) {
    if (!animation.empty()) transform = animation.at(t, rest);
    if (!mesh) return;
    if (!mesh->nodes.empty()) pose_parts(*mesh, clip, t, part_poses);
    if (mesh->deformations.empty()) {
        posed = nullptr;
        return;
    }
    if (posed_from != mesh) {  // a new mesh (a reload): copies of it
        pose_buffers[0] = pose_buffers[1] = nullptr;
        posed = nullptr;
        posed_from = mesh;
    }
    std::shared_ptr<Mesh>& into = pose_buffers[0] == posed ? pose_buffers[1] : pose_buffers[0];
    if (!into || into.use_count() > 1) into = std::make_shared<Mesh>(drawable_copy(*mesh));
    pose_mesh(*mesh, clip, t, weights, *into);
    posed = into;
}

void Scene::pose(double t) {
    if (!std::isfinite(t))
        throw Error(ErrorCode::out_of_range, "a scene can only be posed at a finite time",
                    source.string());
    time = t;
    if (!camera_tracks.empty()) camera = camera_tracks.at(t, camera_rest);
    for (Object& o : objects) o.pose(t);
}

}  // namespace facet
