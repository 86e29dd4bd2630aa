// A mesh file's cameras (Mesh::cameras): assimp's, each placed by its node.
//
// assimp 5.2.5 (Debian 12's) gives a glTF camera's node translation again
// as its position, and its vertical field of view times the aspect ratio
// as its "horizontal" one; glTF itself says a camera looks down its node's
// -Z with +Y up. So a glTF camera is read from its node alone, and the
// other formats as assimp documents its cameras: position, look-at and up
// in the node's space, half the horizontal angle.
#include "assets/mesh_cameras.hpp"

#include "assets/mesh_materials.hpp"

#include <assimp/scene.h>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>

namespace facet {

namespace {

// The node's place in the file's space.
glm::dmat4 place_of(const aiNode* node) {
    glm::dmat4 m(1.0);
    for (; node; node = node->mParent)
        m = glm::dmat4(glm::transpose(glm::make_mat4(&node->mTransformation.a1))) * m;
    return m;
}

glm::vec3 direction_or(const glm::dvec3& v, const glm::vec3& fallback) {
    const double length = glm::length(v);
    return std::isfinite(length) && length > 0.0 ? glm::vec3(v / length) : fallback;
}

glm::dvec3 dvec(const aiVector3D& v) { return {v.x, v.y, v.z}; }

}  // namespace

std::vector<MeshCamera> import_cameras(const aiScene& scene, const std::filesystem::path& path) {
    std::vector<MeshCamera> out;
    const bool gltf = is_gltf(path);
    for (unsigned i = 0; i < scene.mNumCameras; ++i) {
        const aiCamera& c = *scene.mCameras[i];
        const aiNode* node = scene.mRootNode->FindNode(c.mName);
        const glm::dmat4 place = place_of(node);
        const glm::dmat3 turn(place);
        MeshCamera cam;
        cam.name = c.mName.length ? c.mName.C_Str() : "camera " + std::to_string(i);
        const double aspect = c.mAspect > 0.0f ? double(c.mAspect) : 1.0;
        if (gltf) {
            cam.position = glm::vec3(place * glm::dvec4(0.0, 0.0, 0.0, 1.0));
            cam.forward = direction_or(turn * glm::dvec3(0, 0, -1), cam.forward);
            cam.up = direction_or(turn * glm::dvec3(0, 1, 0), cam.up);
            cam.fov_y = float(glm::degrees(double(c.mHorizontalFOV) / aspect));
        } else {
            cam.position = glm::vec3(place * glm::dvec4(dvec(c.mPosition), 1.0));
            cam.forward = direction_or(turn * dvec(c.mLookAt), cam.forward);
            cam.up = direction_or(turn * dvec(c.mUp), cam.up);
            cam.fov_y = float(glm::degrees(2.0 * std::atan(std::tan(double(c.mHorizontalFOV)) / aspect)));
        }
        cam.orthographic = c.mOrthographicWidth > 0.0f;
        cam.ortho_height = float(2.0 * double(c.mOrthographicWidth) / aspect);
        cam.near = c.mClipPlaneNear;
        cam.far = c.mClipPlaneFar;
        out.push_back(cam);
    }
    return out;
}

}  // namespace facet
