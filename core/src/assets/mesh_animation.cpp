// A mesh file's animation: assimp's nodes and animations as facet's nodes
// and clips (facet/animation.hpp), their checks, and each part's motion at
// a time.
#include "assets/mesh_animation.hpp"

#include "facet/error.hpp"
#include "facet/memory.hpp"

#include <assimp/scene.h>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <string>

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
    // A singular matrix (a scale of 0) has no rotation to find.
    const float length = glm::length(t.rotation);
    t.rotation = std::isfinite(length) && length > 1e-6f ? t.rotation / length : glm::quat(1, 0, 0, 0);
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

void add_nodes(const aiNode& node, int parent, NodeIndex& index, Mesh& mesh) {
    const int self = int(mesh.nodes.size());
    index.by_node[&node] = self;
    if (!index.by_name.try_emplace(node.mName.C_Str(), self).second)
        index.ambiguous.insert(node.mName.C_Str());
    MeshNode& n = mesh.nodes.emplace_back();
    n.name = node.mName.C_Str();
    n.parent = parent;
    n.rest = decompose(node.mTransformation);
    for (unsigned i = 0; i < node.mNumChildren; ++i) add_nodes(*node.mChildren[i], self, index, mesh);
}

// glTF's rotation keys are unit quaternions; a file's may not be. Each is
// made unit, and one of zero length or not finite (no rotation) is dropped.
size_t drop_non_rotations(Track<glm::quat>& track) {
    Track<glm::quat> kept;
    for (size_t i = 0; i < track.times.size(); ++i) {
        const glm::quat q = track.values[i];
        const float length = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
        if (!std::isfinite(length) || !(length > 1e-6f)) continue;
        kept.times.push_back(track.times[i]);
        kept.values.push_back(q / length);
    }
    const size_t dropped = track.times.size() - kept.times.size();
    track = std::move(kept);
    return dropped;
}

// The channel's tracks; the number of rotation keys dropped.
size_t read_node_channel(const aiNodeAnim& channel, double seconds_per_tick, TransformTracks& tracks) {
    tracks.position = to_track<glm::vec3>(channel.mPositionKeys, channel.mNumPositionKeys,
                                          seconds_per_tick, [](const aiVector3D& v) {
                                              return glm::vec3(v.x, v.y, v.z);
                                          });
    tracks.rotation = to_track<glm::quat>(channel.mRotationKeys, channel.mNumRotationKeys,
                                          seconds_per_tick, [](const aiQuaternion& q) {
                                              return glm::quat(q.w, q.x, q.y, q.z);
                                          });
    const size_t dropped = drop_non_rotations(tracks.rotation);
    tracks.scale = to_track<glm::vec3>(channel.mScalingKeys, channel.mNumScalingKeys,
                                       seconds_per_tick, [](const aiVector3D& v) {
                                           return glm::vec3(v.x, v.y, v.z);
                                       });
    return dropped;
}

// A morph channel's keys as weights for `targets` targets: a key's values
// name targets, and a target a key leaves out keeps weight 0.
WeightsTrack read_weights(const aiMeshMorphAnim& channel, double seconds_per_tick, size_t targets) {
    WeightsTrack track;
    for (unsigned k = 0; k < channel.mNumKeys; ++k) {
        const aiMeshMorphKey& key = channel.mKeys[k];
        const double t = key.mTime * seconds_per_tick;
        if (!track.times.empty() && !(t > track.times.back())) continue;
        track.times.push_back(t);
        const size_t first = track.values.size();
        track.values.resize(first + targets, 0.0f);
        for (unsigned i = 0; i < key.mNumValuesAndWeights; ++i)
            if (key.mValues[i] < targets) track.values[first + key.mValues[i]] = float(key.mWeights[i]);
    }
    return track;
}

size_t target_count(const Mesh& mesh, size_t part) {
    return mesh.deformations.empty() ? 0 : mesh.deformations[part].targets.size();
}

// Morph weights for the parts that `channel` names (by their node's name).
void read_morph_channel(const aiMeshMorphAnim& channel, double seconds_per_tick,
                        const std::vector<const aiNode*>& placed_by, MeshClip& clip, Mesh& mesh) {
    bool found = false;
    for (size_t p = 0; p < mesh.parts.size(); ++p) {
        if (placed_by[p]->mName != channel.mName || target_count(mesh, p) == 0) continue;
        found = true;
        const size_t targets = target_count(mesh, p);
        unsigned most = 0;
        for (unsigned k = 0; k < channel.mNumKeys; ++k)
            most = std::max(most, channel.mKeys[k].mNumValuesAndWeights);
        if (most > targets)
            mesh.notes += "clip '" + clip.name + "' sets " + std::to_string(most) +
                          " morph weights of part '" + mesh.parts[p].name + "', which has " +
                          std::to_string(targets) + " targets: the weights past them are left out\n";
        clip.weights.resize(mesh.parts.size());
        clip.weights[p] = read_weights(channel, seconds_per_tick, targets);
    }
    if (!found)
        mesh.notes += "clip '" + clip.name + "' animates morph weights of '" +
                      std::string(channel.mName.C_Str()) +
                      "', which places no part with morph targets: left out\n";
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

// One weight a target a key, each within [-1000, 1000], at increasing times.
// Rotations are unit quaternions (the import makes them so).
bool unit_rotations(const Track<glm::quat>& track) {
    return std::all_of(track.values.begin(), track.values.end(),
                       [](const glm::quat& q) { return std::abs(glm::length(q) - 1.0f) < 1e-3f; });
}

bool finite_weights(const WeightsTrack& track, size_t targets) {
    if (track.values.size() != track.times.size() * targets) return false;
    for (size_t i = 0; i < track.times.size(); ++i)
        if (!std::isfinite(track.times[i]) || (i > 0 && !(track.times[i] > track.times[i - 1])))
            return false;
    return std::all_of(track.values.begin(), track.values.end(),
                       [](float w) { return std::abs(w) <= 1000.0f; });
}

bool all_finite(const glm::mat4& m) {
    const float* v = glm::value_ptr(m);
    return std::all_of(v, v + 16, [](float x) { return std::isfinite(x); });
}

// The most a transform's matrix can hold in a row: its translation and
// scale at rest and at every key (a rotation's entries are at most 1).
double reach(const TransformTracks& tracks, const Transform& rest) {
    double t = glm::length(glm::dvec3(rest.translation)), s = glm::length(glm::dvec3(rest.scale));
    for (const glm::vec3& v : tracks.position.values) t = std::max(t, glm::length(glm::dvec3(v)));
    for (const glm::vec3& v : tracks.scale.values) s = std::max(s, glm::length(glm::dvec3(v)));
    return 1.0 + t + 3.0 * s;
}

// Every node's place, at every time of the clip, within 1e30 (so that its
// matrices, and the vertices they move, stay within float): a bound on
// each node's matrix, its parent's times its own.
void check_reach(const Mesh& mesh, const MeshClip& clip) {
    std::vector<double> bound(mesh.nodes.size());
    for (size_t i = 0; i < mesh.nodes.size(); ++i) {
        const int parent = mesh.nodes[i].parent;
        const TransformTracks none;
        bound[i] = (parent >= 0 ? bound[size_t(parent)] : 1.0) *
                   reach(clip.nodes.empty() ? none : clip.nodes[i], mesh.nodes[i].rest);
        if (!(bound[i] <= 1e30))
            throw mesh_invalid(mesh, "clip '" + clip.name + "' may place node '" + mesh.nodes[i].name +
                                    "' past 1e30, beyond what float holds");
    }
}

void validate_clip(const Mesh& mesh, const MeshClip& clip) {
    if (!clip.nodes.empty() && clip.nodes.size() != mesh.nodes.size())
        throw mesh_invalid(mesh, "clip '" + clip.name + "' has tracks for " +
                                std::to_string(clip.nodes.size()) + " nodes of " +
                                std::to_string(mesh.nodes.size()));
    for (size_t i = 0; i < clip.nodes.size(); ++i) {
        const TransformTracks& tracks = clip.nodes[i];
        if (!finite_track(tracks.position) || !finite_track(tracks.rotation) ||
            !finite_track(tracks.scale) || !unit_rotations(tracks.rotation))
            throw mesh_invalid(mesh, "clip '" + clip.name + "' animates node '" + mesh.nodes[i].name +
                                    "' with a key that is not finite, not later than the one "
                                    "before it, or a rotation that is not unit length");
    }
    check_reach(mesh, clip);
    if (!clip.weights.empty() && clip.weights.size() != mesh.part_count())
        throw mesh_invalid(mesh, "clip '" + clip.name + "' has morph weights for " +
                                std::to_string(clip.weights.size()) + " parts of " +
                                std::to_string(mesh.part_count()));
    for (size_t p = 0; p < clip.weights.size(); ++p)
        if (!finite_weights(clip.weights[p], target_count(mesh, p)))
            throw mesh_invalid(mesh, "clip '" + clip.name + "' gives part '" + mesh.part(p).name +
                                    "' morph weights that are not within [-1000, 1000], not one "
                                    "per target, or not later than the key before");
}

}  // namespace

void WeightsTrack::at(double t, size_t targets, float* out) const {
    const auto key = [&](size_t k) { return values.begin() + std::ptrdiff_t(k * targets); };
    if (times.size() == 1 || !(t > times.front())) {
        std::copy(key(0), key(1), out);
        return;
    }
    if (!(t < times.back())) {
        std::copy(key(times.size() - 1), key(times.size()), out);
        return;
    }
    const size_t next = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin());
    const size_t k = next - 1;
    if (interpolation == Interpolation::step) {
        std::copy(key(k), key(next), out);
        return;
    }
    const float u = float((t - times[k]) / (times[next] - times[k]));
    for (size_t i = 0; i < targets; ++i) {
        const float a = values[k * targets + i], b = values[next * targets + i];
        out[i] = a + (b - a) * u;
    }
}

double MeshClip::end() const {
    double end = 0.0;
    for (const TransformTracks& n : nodes) end = std::max(end, n.end());
    for (const WeightsTrack& w : weights) end = std::max(end, w.end());
    return end;
}

bool MeshClip::moves_nodes() const {
    return std::any_of(nodes.begin(), nodes.end(), [](const TransformTracks& n) { return !n.empty(); });
}

bool has_animation(const aiScene& scene) {
    if (scene.mNumAnimations > 0) return true;
    for (unsigned i = 0; i < scene.mNumMeshes; ++i)
        if (scene.mMeshes[i]->mNumBones > 0 || scene.mMeshes[i]->mNumAnimMeshes > 0) return true;
    return false;
}

NodeIndex import_nodes(const aiScene& scene, Mesh& mesh) {
    NodeIndex index;
    add_nodes(*scene.mRootNode, -1, index, mesh);
    return index;
}

void import_clips(const aiScene& scene, const std::vector<const aiNode*>& placed_by,
                  const NodeIndex& nodes, Mesh& mesh) {
    for (size_t p = 0; p < mesh.parts.size(); ++p) mesh.parts[p].node = nodes.by_node.at(placed_by[p]);
    for (unsigned a = 0; a < scene.mNumAnimations; ++a) {
        if (!scene.mAnimations[a]) continue;
        const aiAnimation& animation = *scene.mAnimations[a];
        MeshClip& clip = mesh.clips.emplace_back();
        clip.name = animation.mName.length > 0 ? animation.mName.C_Str() : "clip " + std::to_string(a);
        if (animation.mNumChannels > 0) {  // a clip of morph weights alone keeps no node tracks
            require_within_budget(uint64_t(mesh.nodes.size()) * sizeof(TransformTracks),
                                  "the tracks of clip '" + clip.name + "'", mesh.source);
            clip.nodes.resize(mesh.nodes.size());
        }
        // glTF's times are in seconds; assimp gives them in its ticks.
        const double seconds_per_tick =
            1.0 / (animation.mTicksPerSecond > 0.0 ? animation.mTicksPerSecond : 25.0);
        for (unsigned c = 0; c < animation.mNumChannels; ++c) {
            const aiNodeAnim& channel = *animation.mChannels[c];
            const auto found = nodes.by_name.find(channel.mNodeName.C_Str());
            if (found == nodes.by_name.end()) {
                mesh.notes += "clip '" + clip.name + "' animates a node named '" +
                              channel.mNodeName.C_Str() + "', which the file does not have: left out\n";
                continue;
            }
            if (const size_t dropped =
                    read_node_channel(channel, seconds_per_tick, clip.nodes[size_t(found->second)]))
                mesh.notes += "clip '" + clip.name + "': " + std::to_string(dropped) +
                              " rotation keys of node '" + channel.mNodeName.C_Str() +
                              "' are no rotation (zero length or not finite): left out\n";
        }
        for (unsigned c = 0; c < animation.mNumMorphMeshChannels; ++c)
            read_morph_channel(*animation.mMorphMeshChannels[c], seconds_per_tick, placed_by, clip,
                               mesh);
        if (animation.mNumMeshChannels > 0)
            mesh.notes += "clip '" + clip.name + "' swaps whole meshes (mesh channels): left out\n";
    }
}

void validate_nodes(const Mesh& mesh) {
    for (const MeshPart& p : mesh.parts)
        if (p.node < -1 || p.node >= int(mesh.nodes.size()))
            throw mesh_invalid(mesh, "part '" + p.name + "' names node " + std::to_string(p.node) + " of " +
                                    std::to_string(mesh.nodes.size()));
    for (size_t i = 0; i < mesh.nodes.size(); ++i) {
        if (mesh.nodes[i].parent < -1 || mesh.nodes[i].parent >= int(i))
            throw mesh_invalid(mesh, "node '" + mesh.nodes[i].name +
                                    "' has a parent that does not come before it");
        const Transform& rest = mesh.nodes[i].rest;
        const Track<glm::vec3> t{{0.0, 1.0}, {rest.translation, rest.scale}};
        const Track<glm::quat> r{{0.0}, {rest.rotation}};
        if (!finite_track(t) || !finite_track(r) || !unit_rotations(r))
            throw mesh_invalid(mesh, "node '" + mesh.nodes[i].name +
                                         "' has a place that is not finite, or a rotation that is "
                                         "not unit length");
    }
    validate_deformations(mesh);
    MeshClip rest;  // the nodes at rest, which a mesh that deforms is posed at
    rest.name = "(at rest)";
    check_reach(mesh, rest);
    for (const MeshClip& clip : mesh.clips) validate_clip(mesh, clip);
}

void place_nodes(const Mesh& mesh, int clip, double t, std::vector<glm::dmat4>& places) {
    const size_t n = mesh.nodes.size();
    places.resize(n);
    const MeshClip* c = clip >= 0 && size_t(clip) < mesh.clips.size() ? &mesh.clips[size_t(clip)] : nullptr;
    for (size_t i = 0; i < n; ++i) {
        const MeshNode& node = mesh.nodes[i];
        const glm::dmat4 parent = node.parent >= 0 ? places[size_t(node.parent)] : glm::dmat4(1.0);
        const bool animated = c && !c->nodes.empty() && !c->nodes[i].empty();
        places[i] = parent * glm::dmat4((animated ? c->nodes[i].at(t, node.rest) : node.rest).matrix());
    }
}

void pose_parts(const Mesh& mesh, int clip, double t, std::vector<glm::mat4>& poses) {
    poses.assign(mesh.part_count(), glm::mat4(1.0f));
    if (clip < 0 || size_t(clip) >= mesh.clips.size() || !mesh.clips[size_t(clip)].moves_nodes())
        return;
    // In double: a part's motion is its node's place now times the inverse
    // of its place at rest, which is exactly the identity where they agree.
    std::vector<glm::dmat4> now, rest;
    place_nodes(mesh, clip, t, now);
    place_nodes(mesh, -1, 0.0, rest);
    const MeshClip& c = mesh.clips[size_t(clip)];
    std::vector<char> moves(mesh.nodes.size());
    for (size_t i = 0; i < mesh.nodes.size(); ++i) {
        const int parent = mesh.nodes[i].parent;
        moves[i] = (!c.nodes.empty() && !c.nodes[i].empty()) || (parent >= 0 && moves[size_t(parent)]);
    }
    for (size_t p = 0; p < mesh.parts.size(); ++p) {
        const int node = mesh.parts[p].node;
        const bool deformed = !mesh.deformations.empty() && mesh.deformations[p].deforms();
        if (node < 0 || !moves[size_t(node)] || deformed) continue;
        const glm::mat4 pose(now[size_t(node)] * glm::inverse(rest[size_t(node)]));
        // (The import keeps a part whose place at rest is singular in its
        // own space, as a deformed one; this holds where float and double
        // disagree on that.)
        if (all_finite(pose)) poses[p] = pose;
    }
}

double animation_end(const Mesh& mesh, int clip) {
    return clip >= 0 && size_t(clip) < mesh.clips.size() ? mesh.clips[size_t(clip)].end() : 0.0;
}

int find_clip(const Mesh& mesh, const std::string& name) {
    for (size_t i = 0; i < mesh.clips.size(); ++i)
        if (mesh.clips[i].name == name) return int(i);
    return -1;
}

}  // namespace facet
