// A model file rendered with no scene file (load_scene given a .glb, .obj,
// .fbx, ...), and framing a camera on an object (facet/scene.hpp).
#include "facet/scene.hpp"

#include "facet/error.hpp"

#include <assimp/Importer.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

namespace fs = std::filesystem;

namespace facet {

namespace {

// `text` as a YAML single-quoted scalar.
std::string quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
    return out + "'";
}

// A three-light rig (key with shadows, fill, rim) from above and in front,
// as a studio lights a model.
constexpr const char* kLightRig =
    "lights:\n"
    "  - {name: key, type: directional, direction: [-0.5, -0.7, -0.5], color: [1.0, 0.96, 0.9],\n"
    "     intensity: 2.0, casts_shadow: true}\n"
    "  - {name: fill, type: directional, direction: [0.7, -0.3, -0.4], color: [0.6, 0.7, 0.85],\n"
    "     intensity: 0.6}\n"
    "  - {name: rim, type: directional, direction: [0.2, -0.4, 0.9], color: [1, 1, 1],\n"
    "     intensity: 0.8}\n";

// The file's own camera, where it is one: its place and field of view, with
// the framed camera's clip distances where the file gives none.
void use_file_camera(Scene& scene, const MeshCamera& file, const fs::path& path) {
    Camera c = scene.camera;
    c.position = file.position;
    c.target = file.position + file.forward;
    c.up = file.up;
    c.orthographic = file.orthographic;
    c.fov_y = file.fov_y;
    if (file.orthographic && file.ortho_height > 0.0f) c.ortho_height = file.ortho_height;
    if (file.near > 0.0f) c.near = file.near;
    if (file.far > c.near) c.far = file.far;
    if (glm::length(glm::cross(file.forward, file.up)) < 1e-6f || !(c.far > c.near)) {
        spdlog::warn("{}: camera '{}' looks along its up, or clips everything; the model is "
                     "framed instead", path.string(), file.name);
        return;
    }
    scene.camera = scene.camera_rest = c;
    spdlog::info("{}: seen through the file's camera '{}'", path.string(), file.name);
}

}  // namespace

bool is_model_file(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext.empty() || ext == ".yaml" || ext == ".yml") return false;
    return Assimp::Importer().IsExtensionSupported(ext);
}

Camera framed_camera(const Object& o, const Camera& like) {
    Camera c = like;
    if (!o.mesh) return c;
    // The object's bounds in the world: its mesh's corners, moved.
    const Bounds& b = o.drawn_mesh()->bounds;
    const glm::dmat4 model(o.transform.matrix());
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p((corner & 1 ? b.max : b.min).x, (corner & 2 ? b.max : b.min).y,
                           (corner & 4 ? b.max : b.min).z);
        const glm::dvec3 world(model * glm::dvec4(p, 1.0));
        lo = glm::min(lo, world);
        hi = glm::max(hi, world);
    }
    const glm::dvec3 centre = (lo + hi) * 0.5;
    const double radius = std::max(glm::length(hi - lo) * 0.5, 1e-6);
    // Seen from in front, a little right and above: the bounding sphere
    // fills the height of the view.
    const double fov = glm::radians(double(c.orthographic ? 45.0f : c.fov_y));
    const double distance = radius / std::sin(fov * 0.5) * 1.05;
    const glm::dvec3 direction = glm::normalize(glm::dvec3(0.55, 0.4, 1.0));
    c.target = glm::vec3(centre);
    c.position = glm::vec3(centre + direction * distance);
    c.up = {0.0f, 1.0f, 0.0f};
    c.ortho_height = float(radius * 2.1);
    c.near = float(std::max((distance - radius) * 0.5, distance * 1e-4));
    c.far = float((distance + radius) * 2.0);
    return c;
}

void frame_object(Scene& scene, size_t index) {
    scene.camera = scene.camera_rest = framed_camera(scene.objects.at(index), scene.camera);
    scene.camera_tracks = {};
}

Scene load_model_scene(const fs::path& path, PluginRegistry& registry) {
    // The scene reads as if it were beside the model, so that errors name
    // the model and its folder resolves the files it names.
    const std::string yaml = std::string(kLightRig) + "objects:\n  - {name: " +
                             quoted(path.stem().string()) + ", mesh: " +
                             quoted(path.filename().string()) + "}\n";
    Scene scene;
    try {
        scene = load_scene_text(yaml, path, registry);
    } catch (const Error& e) {
        // A place in the YAML made here means nothing to the user: the
        // error is the model's (its detail names the model's own file).
        if (e.line() == 0 || e.file() != path.string()) throw;
        const std::string prefix = path.string() + ": ";
        const bool named = e.detail().compare(0, prefix.size(), prefix) == 0;
        throw Error(e.code(), named ? e.detail().substr(prefix.size()) : e.detail(), path.string());
    }
    frame_object(scene, 0);
    if (const std::vector<MeshCamera>& cameras = scene.objects[0].mesh->cameras; !cameras.empty())
        use_file_camera(scene, cameras[0], path);
    const Bounds& b = scene.objects[0].mesh->bounds;
    const glm::vec3 size = b.max - b.min;
    spdlog::info("{}: a model with no scene, {:g} x {:g} x {:g} in its file's units, framed and lit "
                 "by a three-light rig",
                 path.string(), size.x, size.y, size.z);
    return scene;
}

}  // namespace facet
