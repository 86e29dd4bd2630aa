// What deforms a mesh file's part: assimp's bones as a skin with up to 8
// joints a vertex, and its anim meshes as morph targets; and their checks.
#include "assets/mesh_animation.hpp"

#include "facet/error.hpp"

#include <assimp/scene.h>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace facet {

namespace {

glm::mat4 bind_matrix(const aiMatrix4x4& m) {
    return glm::transpose(glm::make_mat4(&m.a1));  // assimp is row-major
}

glm::vec3 vec(const aiVector3D& v) { return {v.x, v.y, v.z}; }

bool finite(const float* v, size_t n) {
    return std::all_of(v, v + n, [](float x) { return std::isfinite(x); });
}

// What mending the weights took, for one line of notes each.
struct Mended {
    size_t over_eight = 0;   // vertices with more joints than 8: the 8 heaviest kept
    size_t unweighted = 0;   // vertices with no weight: they stay where the file puts them
    size_t rescaled = 0;     // vertices whose weights did not sum to 1
    size_t negative = 0;     // weights below 0, left out
};

void note_mended(const Mended& m, const std::string& part, Mesh& mesh) {
    const auto note = [&](size_t count, const std::string& what) {
        if (count > 0)
            mesh.notes += "part '" + part + "': " + std::to_string(count) + " vertices " + what + "\n";
    };
    note(m.over_eight, "have more than 8 joints; the 8 heaviest are kept");
    note(m.unweighted, "have no joint weight; they stay where the file puts them");
    note(m.rescaled, "have joint weights that do not sum to 1; they are scaled to sum to 1");
    note(m.negative, "have a negative joint weight, which is left out");
}

// Each vertex's joints, heaviest first, at most 8, weights scaled to sum to 1.
std::vector<JointWeights> gather_weights(const aiMesh& src, const std::string& part, Mesh& mesh) {
    std::vector<std::vector<std::pair<float, uint16_t>>> per(src.mNumVertices);
    Mended mended;
    for (unsigned b = 0; b < src.mNumBones; ++b) {
        const aiBone& bone = *src.mBones[b];
        for (unsigned w = 0; w < bone.mNumWeights; ++w) {
            const aiVertexWeight& vw = bone.mWeights[w];
            if (!std::isfinite(vw.mWeight))
                throw mesh_invalid(mesh, "part '" + part + "': joint '" + bone.mName.C_Str() +
                                        "' has a weight that is not finite");
            if (vw.mVertexId >= src.mNumVertices)
                throw mesh_invalid(mesh, "part '" + part + "': joint '" + bone.mName.C_Str() +
                                        "' weighs vertex " + std::to_string(vw.mVertexId) + " of " +
                                        std::to_string(src.mNumVertices));
            if (vw.mWeight < 0.0f) ++mended.negative;
            if (vw.mWeight > 0.0f) per[vw.mVertexId].emplace_back(vw.mWeight, uint16_t(b));
        }
    }
    std::vector<JointWeights> out(src.mNumVertices);
    for (size_t v = 0; v < per.size(); ++v) {
        auto& list = per[v];
        // Heaviest first; equal weights by joint, so that the order is the file's.
        std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) {
            return a.first != b.first ? a.first > b.first : a.second < b.second;
        });
        if (list.size() > size_t(kMaxJointsPerVertex)) {
            ++mended.over_eight;
            list.resize(kMaxJointsPerVertex);
        }
        double sum = 0.0;
        for (const auto& [w, joint] : list) sum += w;
        if (list.empty()) ++mended.unweighted;
        else if (std::abs(sum - 1.0) > 1e-3) ++mended.rescaled;
        for (size_t k = 0; k < list.size(); ++k) {
            out[v].joint[k] = list[k].second;
            out[v].weight[k] = float(list[k].first / sum);
        }
    }
    note_mended(mended, part, mesh);
    return out;
}

MeshSkin import_skin(const aiMesh& src, const std::string& part, const NodeIndex& nodes,
                     Mesh& mesh) {
    if (src.mNumBones > 65535)
        throw mesh_invalid(mesh, "part '" + part + "' has " + std::to_string(src.mNumBones) +
                                " joints (at most 65535)");
    MeshSkin skin;
    skin.name = src.mName.length > 0 ? src.mName.C_Str() : part;
    for (unsigned b = 0; b < src.mNumBones; ++b) {
        const aiBone& bone = *src.mBones[b];
        const auto found = nodes.by_name.find(bone.mName.C_Str());
        if (found == nodes.by_name.end())
            throw mesh_invalid(mesh, "part '" + part + "': joint '" + bone.mName.C_Str() +
                                    "' is no node of the file");
        if (nodes.ambiguous.count(bone.mName.C_Str()))
            mesh.notes += "part '" + part + "': joint '" + bone.mName.C_Str() +
                          "' names more than one node; the first is used\n";
        skin.joints.push_back(found->second);
        skin.inverse_binds.push_back(bind_matrix(bone.mOffsetMatrix));
    }
    return skin;
}

// The file gives a target's vertices whole (assimp adds glTF's offsets to
// the base); facet keeps the offsets.
MorphTarget import_target(const aiMesh& src, const aiAnimMesh& target, size_t index,
                          const std::string& part, const Mesh& raw, const Mesh& mesh) {
    MorphTarget t;
    t.name = target.mName.length > 0 ? target.mName.C_Str() : "target " + std::to_string(index);
    if (target.mNumVertices != src.mNumVertices)
        throw mesh_invalid(mesh, "part '" + part + "': morph target '" + t.name + "' has " +
                                std::to_string(target.mNumVertices) + " vertices for " +
                                std::to_string(src.mNumVertices));
    for (unsigned i = 0; i < src.mNumVertices; ++i) {
        t.positions.push_back(target.HasPositions() ? vec(target.mVertices[i]) - vec(src.mVertices[i])
                                                    : glm::vec3(0.0f));
        if (target.HasNormals() && src.HasNormals())
            t.normals.push_back(vec(target.mNormals[i]) - vec(src.mNormals[i]));
        if (target.HasTangentsAndBitangents() && src.HasTangentsAndBitangents() && !raw.tangents.empty())
            t.tangents.push_back(vec(target.mTangents[i]) - vec(src.mTangents[i]));
    }
    return t;
}

void validate_skin(const Mesh& mesh, const MeshSkin& skin) {
    if (skin.joints.size() != skin.inverse_binds.size() || skin.joints.size() > 65535)
        throw mesh_invalid(mesh, "skin '" + skin.name + "' does not have one inverse bind matrix a joint");
    for (size_t j = 0; j < skin.joints.size(); ++j) {
        if (skin.joints[j] < 0 || skin.joints[j] >= int(mesh.nodes.size()))
            throw mesh_invalid(mesh, "skin '" + skin.name + "' names node " + std::to_string(skin.joints[j]) +
                                    " of " + std::to_string(mesh.nodes.size()));
        const float* m = glm::value_ptr(skin.inverse_binds[j]);
        if (!std::all_of(m, m + 16, [](float x) { return std::abs(x) <= 1e30f; }))
            throw mesh_invalid(mesh, "skin '" + skin.name + "' has an inverse bind matrix that is not "
                                "finite or past 1e30");
    }
}

template <class V>
bool sized(const std::vector<V>& v, size_t n, bool may_be_empty) {
    return v.size() == n || (may_be_empty && v.empty());
}

template <class V>
bool all_finite(const std::vector<V>& v) {
    return v.empty() || finite(reinterpret_cast<const float*>(v.data()), v.size() * sizeof(V) / sizeof(float));
}

void validate_influences(const Mesh& mesh, const PartDeformation& d, const std::string& part) {
    const size_t joints = mesh.skins[size_t(d.skin)].joints.size();
    for (const JointWeights& jw : d.joints)
        for (int k = 0; k < kMaxJointsPerVertex; ++k)
            if (!(jw.weight[k] >= 0.0f && jw.weight[k] <= 1.0f) ||
                (jw.weight[k] > 0.0f && jw.joint[k] >= joints))
                throw mesh_invalid(mesh, "part '" + part + "' has a joint weight outside [0, 1] or a "
                                    "joint outside its skin's " + std::to_string(joints));
}

void validate_deformation(const Mesh& mesh, const PartDeformation& d, const MeshPart& p) {
    const size_t n = p.vertex_count;
    const std::string part = "part '" + p.name + "'";
    if (d.skin < -1 || d.skin >= int(mesh.skins.size()))
        throw mesh_invalid(mesh, part + " names skin " + std::to_string(d.skin) + " of " +
                                std::to_string(mesh.skins.size()));
    if (!d.deforms()) {
        if (d.skin >= 0 || !d.targets.empty())
            throw mesh_invalid(mesh, part + " has a skin or morph targets but no vertices of its own");
        return;
    }
    if (p.node < 0 && d.skin < 0) throw mesh_invalid(mesh, part + " deforms but has no node to place it");
    if (!sized(d.positions, n, false) || !sized(d.normals, n, false) ||
        d.tangents.size() != (mesh.tangents.empty() ? 0 : n) ||
        !sized(d.joints, n, d.skin < 0) || d.weights.size() != d.targets.size())
        throw mesh_invalid(mesh, part + "'s own vertices, joints or morph weights do not match its " +
                                std::to_string(n) + " vertices and " +
                                std::to_string(d.targets.size()) + " targets");
    if (!all_finite(d.positions) || !all_finite(d.normals) || !all_finite(d.tangents) ||
        !std::all_of(d.weights.begin(), d.weights.end(), [](float w) { return std::abs(w) <= 1000.0f; }))
        throw mesh_invalid(mesh, part + " has an own vertex that is not finite, or a morph weight "
                                        "outside [-1000, 1000]");
    if (d.skin >= 0) validate_influences(mesh, d, p.name);
    for (const MorphTarget& t : d.targets) {
        if (!sized(t.positions, n, false) || !sized(t.normals, n, true) ||
            !sized(t.tangents, n, true))
            throw mesh_invalid(mesh, part + ": morph target '" + t.name + "' does not have one offset "
                                       "a vertex");
        if (!all_finite(t.positions) || !all_finite(t.normals) || !all_finite(t.tangents))
            throw mesh_invalid(mesh, part + ": morph target '" + t.name + "' has an offset that is "
                                       "not finite");
    }
}

}  // namespace

PartDeformation import_deformation(const aiMesh& src, const Mesh& raw,
                                   const NodeIndex& nodes, Mesh& mesh) {
    const std::string part = mesh.parts.empty() ? "" : mesh.parts.back().name;
    PartDeformation d;
    d.positions = raw.positions;
    d.normals = raw.normals;
    d.tangents = raw.tangents;
    if (src.mNumBones > 0) {
        d.skin = int(mesh.skins.size());
        mesh.skins.push_back(import_skin(src, part, nodes, mesh));
        d.joints = gather_weights(src, part, mesh);
    }
    for (unsigned a = 0; a < src.mNumAnimMeshes; ++a) {
        if (!src.mAnimMeshes[a]) continue;
        d.targets.push_back(import_target(src, *src.mAnimMeshes[a], a, part, raw, mesh));
        const float w = src.mAnimMeshes[a]->mWeight;
        if (!std::isfinite(w))
            throw mesh_invalid(mesh, "part '" + part + "': morph target '" + d.targets.back().name +
                                    "' has a weight that is not finite");
        d.weights.push_back(w);
    }
    return d;
}

void validate_deformations(const Mesh& mesh) {
    for (const MeshSkin& skin : mesh.skins) validate_skin(mesh, skin);
    if (mesh.deformations.empty()) return;
    if (mesh.normals.size() != mesh.vertex_count())
        throw mesh_invalid(mesh, "it deforms a part but has no normals");
    if (mesh.deformations.size() != mesh.parts.size())
        throw mesh_invalid(mesh, "it has deformations for " + std::to_string(mesh.deformations.size()) +
                                " parts of " + std::to_string(mesh.parts.size()));
    for (size_t p = 0; p < mesh.parts.size(); ++p)
        validate_deformation(mesh, mesh.deformations[p], mesh.parts[p]);
}

}  // namespace facet
