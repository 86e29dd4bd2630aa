// A mesh file's node animation: assimp's channels as facet's tracks
// (facet/animation.hpp), and each part's motion at a time.
#include "assets/mesh_animation.hpp"

#include "facet/error.hpp"

#include <assimp/scene.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <string>
#include <unordered_map>

namespace facet {

namespace {

Transform decompose(const aiMatrix4x4& m) {
    aiVector3D scale, position;
    aiQuaternion rotation;
    m.Decompose(scale, rotation, position);
    Transform t;
    t.translation = {position.x, position.y, position.z};
    t.rotation = glm::quat(rotation.w, rotation.x, rotation.y, rotation.z);
    t.scale = {scale.x, scale.y, scale.z};
    return t;
}

// Keys in seconds; a key no later than the one before it is dropped.
template <class T, class Key, class Convert>
Track<T> to_track(const Key* keys, unsigned count, double seconds_per_tick, Convert convert) {
    Track<T> track;
    for (unsigned i = 0; i < count; ++i) {
        const double t = keys[i].mTime * seconds_per_tick;
        if (!track.times.empty() && !(t > track.times.back())) continue;
        track.times.push_back(t);
        track.values.push_back(convert(keys[i].mValue));
    }
    return track;
}

void add_nodes(const aiNode& node, int parent, std::unordered_map<const aiNode*, int>& index,
               Mesh& mesh) {
    const int self = int(mesh.nodes.size());
    index[&node] = self;
    MeshNode& n = mesh.nodes.emplace_back();
    n.name = node.mName.C_Str();
    n.parent = parent;
    n.rest = decompose(node.mTransformation);
    for (unsigned i = 0; i < node.mNumChildren; ++i) add_nodes(*node.mChildren[i], self, index, mesh);
}

template <class T>
bool finite_track(const Track<T>& track) {
    if (track.times.size() != track.values.size()) return false;
    for (size_t i = 0; i < track.times.size(); ++i) {
        if (!std::isfinite(track.times[i]) || (i > 0 && !(track.times[i] > track.times[i - 1])))
            return false;
        const float* v = glm::value_ptr(track.values[i]);
        for (size_t k = 0; k < sizeof(T) / sizeof(float); ++k)
            if (!std::isfinite(v[k])) return false;
    }
    return true;
}

}  // namespace

void import_node_animation(const aiScene& scene, const std::vector<const aiNode*>& placed_by,
                           Mesh& mesh) {
    if (scene.mNumAnimations == 0 || !scene.mAnimations[0]) return;
    const aiAnimation& clip = *scene.mAnimations[0];
    // glTF's times are in seconds; assimp gives them in its ticks.
    const double seconds_per_tick = 1.0 / (clip.mTicksPerSecond > 0.0 ? clip.mTicksPerSecond : 25.0);
    std::unordered_map<const aiNode*, int> index;
    add_nodes(*scene.mRootNode, -1, index, mesh);
    std::unordered_map<std::string, int> by_name;
    for (size_t i = 0; i < mesh.nodes.size(); ++i) by_name.try_emplace(mesh.nodes[i].name, int(i));
    bool moves = false;
    for (unsigned c = 0; c < clip.mNumChannels; ++c) {
        const aiNodeAnim& channel = *clip.mChannels[c];
        const auto found = by_name.find(channel.mNodeName.C_Str());
        if (found == by_name.end()) continue;
        TransformTracks& tracks = mesh.nodes[size_t(found->second)].tracks;
        tracks.position = to_track<glm::vec3>(channel.mPositionKeys, channel.mNumPositionKeys,
                                              seconds_per_tick, [](const aiVector3D& v) {
                                                  return glm::vec3(v.x, v.y, v.z);
                                              });
        tracks.rotation = to_track<glm::quat>(channel.mRotationKeys, channel.mNumRotationKeys,
                                              seconds_per_tick, [](const aiQuaternion& q) {
                                                  return glm::quat(q.w, q.x, q.y, q.z);
                                              });
        tracks.scale = to_track<glm::vec3>(channel.mScalingKeys, channel.mNumScalingKeys,
                                           seconds_per_tick, [](const aiVector3D& v) {
                                               return glm::vec3(v.x, v.y, v.z);
                                           });
        moves |= !tracks.empty();
    }
    if (!moves) {
        mesh.nodes.clear();
        return;
    }
    for (size_t p = 0; p < mesh.parts.size(); ++p) mesh.parts[p].node = index.at(placed_by[p]);
}

void validate_nodes(const Mesh& mesh) {
    const auto invalid = [&](const std::string& problem) {
        return Error(ErrorCode::mesh_invalid, problem, mesh.source);
    };
    for (const MeshPart& p : mesh.parts)
        if (p.node < -1 || p.node >= int(mesh.nodes.size()))
            throw invalid("part '" + p.name + "' names node " + std::to_string(p.node) + " of " +
                          std::to_string(mesh.nodes.size()));
    for (size_t i = 0; i < mesh.nodes.size(); ++i) {
        const MeshNode& n = mesh.nodes[i];
        if (n.parent < -1 || n.parent >= int(i))
            throw invalid("node '" + n.name + "' has a parent that does not come before it");
        if (!finite_track(n.tracks.position) || !finite_track(n.tracks.rotation) ||
            !finite_track(n.tracks.scale))
            throw invalid("node '" + n.name + "' is animated with a key that is not finite or "
                          "not later than the one before it");
    }
}

void pose_parts(const Mesh& mesh, double t, std::vector<glm::mat4>& poses) {
    const size_t n = mesh.nodes.size();
    // In double: a part's motion is its node's place now times the inverse
    // of its place at rest, which is exactly the identity where they agree.
    std::vector<glm::dmat4> now(n), rest(n);
    std::vector<char> moves(n);
    for (size_t i = 0; i < n; ++i) {
        const MeshNode& node = mesh.nodes[i];
        const glm::dmat4 parent_now = node.parent >= 0 ? now[size_t(node.parent)] : glm::dmat4(1.0);
        const glm::dmat4 parent_rest = node.parent >= 0 ? rest[size_t(node.parent)] : glm::dmat4(1.0);
        moves[i] = !node.tracks.empty() || (node.parent >= 0 && moves[size_t(node.parent)]);
        rest[i] = parent_rest * glm::dmat4(node.rest.matrix());
        now[i] = node.tracks.empty() ? parent_now * glm::dmat4(node.rest.matrix())
                                     : parent_now * glm::dmat4(node.tracks.at(t, node.rest).matrix());
    }
    poses.assign(mesh.part_count(), glm::mat4(1.0f));
    for (size_t p = 0; p < mesh.parts.size(); ++p) {
        const int node = mesh.parts[p].node;
        if (node >= 0 && moves[size_t(node)])
            poses[p] = glm::mat4(now[size_t(node)] * glm::inverse(rest[size_t(node)]));
    }
}

double animation_end(const Mesh& mesh) {
    double end = 0.0;
    for (const MeshNode& n : mesh.nodes) end = std::max(end, n.tracks.end());
    return end;
}

}  // namespace facet
