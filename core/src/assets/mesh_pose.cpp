// A deformed mesh at a time: morph targets blended, then linear blend
// skinning with up to 8 joints a vertex (facet/mesh.hpp, pose_mesh).
//
// In float, in the core's baseline code: the same bits on every ISA path and
// for every thread count. The joints' matrices are made in double from the
// nodes' places; each vertex blends its joints' 3x4 rows, 12 lanes of
// float that the compiler keeps in vector registers.
#include "assets/mesh_animation.hpp"

#include <algorithm>
#include <cmath>

namespace facet {

namespace {

// A joint's matrix as three rows of four: x' = row0 . (x, y, z, 1), ...
struct Rows {
    float m[12];
};

Rows to_rows(const glm::dmat4& m) {
    Rows r;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) r.m[row * 4 + col] = float(m[col][row]);
    return r;
}

// The skin's joints posed: from the part's space at bind to the file's, now.
std::vector<Rows> joint_rows(const MeshSkin& skin, const std::vector<glm::dmat4>& places) {
    std::vector<Rows> rows(skin.joints.size());
    for (size_t j = 0; j < skin.joints.size(); ++j)
        rows[j] = to_rows(places[size_t(skin.joints[j])] * glm::dmat4(skin.inverse_binds[j]));
    return rows;
}

Rows blend(const JointWeights& jw, const std::vector<Rows>& joints) {
    Rows m{};
    if (jw.weight[0] == 0.0f) {  // no joint: where the file puts it
        m.m[0] = m.m[5] = m.m[10] = 1.0f;
        return m;
    }
    for (int k = 0; k < kMaxJointsPerVertex && jw.weight[k] > 0.0f; ++k) {
        const float w = jw.weight[k];
        const float* j = joints[jw.joint[k]].m;
        for (int e = 0; e < 12; ++e) m.m[e] += w * j[e];
    }
    return m;
}

glm::vec3 apply(const Rows& r, const glm::vec3& p) {
    return {r.m[0] * p.x + r.m[1] * p.y + r.m[2] * p.z + r.m[3],
            r.m[4] * p.x + r.m[5] * p.y + r.m[6] * p.z + r.m[7],
            r.m[8] * p.x + r.m[9] * p.y + r.m[10] * p.z + r.m[11]};
}

glm::vec3 apply_linear(const Rows& r, const glm::vec3& v) {
    return {r.m[0] * v.x + r.m[1] * v.y + r.m[2] * v.z, r.m[4] * v.x + r.m[5] * v.y + r.m[6] * v.z,
            r.m[8] * v.x + r.m[9] * v.y + r.m[10] * v.z};
}

// The normal through the inverse transpose, as the cofactor matrix times
// the sign of the determinant: no division, and a singular blend gives 0.
// `mirrors`: whether the determinant is negative.
glm::vec3 apply_normal(const Rows& r, const glm::vec3& n, bool& mirrors) {
    const glm::vec3 c0(r.m[0], r.m[4], r.m[8]), c1(r.m[1], r.m[5], r.m[9]), c2(r.m[2], r.m[6], r.m[10]);
    const glm::vec3 x = glm::cross(c1, c2), y = glm::cross(c2, c0), z = glm::cross(c0, c1);
    mirrors = glm::dot(c0, x) < 0.0f;
    const glm::vec3 out = x * n.x + y * n.y + z * n.z;
    return mirrors ? -out : out;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

glm::vec3 unit_or(const glm::vec3& v, const glm::vec3& fallback) {
    const float length = std::sqrt(glm::dot(v, v));
    return std::isfinite(length) && length > 0.0f ? v / length : fallback;
}

// One part's vertices: morphed in its own space, then skinned or placed.
void deform_part(const PartDeformation& d, const MeshPart& part, const std::vector<float>& weights,
                 const std::vector<Rows>& joints, const Rows& place, const Mesh& rest, Mesh& out) {
    const bool tangents = !d.tangents.empty();
    for (uint32_t i = 0; i < part.vertex_count; ++i) {
        glm::vec3 p = d.positions[i], n = d.normals[i];
        glm::vec3 t = tangents ? glm::vec3(d.tangents[i]) : glm::vec3(0.0f);
        for (size_t k = 0; k < d.targets.size(); ++k) {
            const float w = weights[k];
            if (w == 0.0f) continue;
            const MorphTarget& target = d.targets[k];
            p += w * target.positions[i];
            if (!target.normals.empty()) n += w * target.normals[i];
            if (tangents && !target.tangents.empty()) t += w * target.tangents[i];
        }
        const Rows& m = d.skin >= 0 ? blend(d.joints[i], joints) : place;
        const size_t v = part.first_vertex + i;
        // A vertex moved past float's range stays where the file puts it at
        // rest (rest), as does its frame: bounds and culling stay finite.
        const glm::vec3 moved = apply(m, p);
        if (!finite(moved)) {
            out.positions[v] = rest.positions[v];
            out.normals[v] = rest.normals[v];
            if (tangents) out.tangents[v] = rest.tangents[v];
            continue;
        }
        out.positions[v] = moved;
        bool mirrors = false;
        out.normals[v] = unit_or(apply_normal(m, n, mirrors), d.normals[i]);
        if (tangents) {
            const glm::vec3 along = apply_linear(m, t);
            const float length = std::sqrt(glm::dot(along, along));
            // None left: no frame, and a normal map leaves the normal alone.
            // A mirroring blend turns the bitangent's side with it.
            out.tangents[v] = glm::vec4(std::isfinite(length) && length > 0.0f ? along / length
                                                                                : glm::vec3(0.0f),
                                        mirrors ? -d.tangents[i].w : d.tangents[i].w);
        }
    }
}

}  // namespace

void pose_mesh(const Mesh& mesh, int clip, double t, const std::vector<WeightOverride>& overrides,
               Mesh& out) {
    if (mesh.deformations.empty()) return;
    if (out.positions.size() != mesh.positions.size() || out.normals.size() != mesh.normals.size() ||
        out.tangents.size() != mesh.tangents.size() || out.parts.size() != mesh.parts.size())
        throw Error(ErrorCode::out_of_range, "pose_mesh: the posed mesh is not a copy of the mesh",
                    mesh.source);
    std::vector<glm::dmat4> places;
    place_nodes(mesh, clip, t, places);
    const MeshClip* c =
        clip >= 0 && size_t(clip) < mesh.clips.size() ? &mesh.clips[size_t(clip)] : nullptr;
    std::vector<std::vector<Rows>> skins(mesh.skins.size());
    const std::vector<Rows> no_joints;
    std::vector<float> weights;
    for (size_t p = 0; p < mesh.parts.size(); ++p) {
        const PartDeformation& d = mesh.deformations[p];
        if (!d.deforms()) continue;
        weights = d.weights;
        if (c && p < c->weights.size() && !c->weights[p].empty())
            c->weights[p].at(t, weights.size(), weights.data());
        for (const WeightOverride& o : overrides)
            for (size_t k = 0; k < d.targets.size(); ++k)
                if (d.targets[k].name == o.target) weights[k] = o.weight;
        if (d.skin >= 0 && skins[size_t(d.skin)].empty())
            skins[size_t(d.skin)] = joint_rows(mesh.skins[size_t(d.skin)], places);
        const Rows place = d.skin >= 0 ? Rows{} : to_rows(places[size_t(mesh.parts[p].node)]);
        deform_part(d, mesh.parts[p], weights, d.skin >= 0 ? skins[size_t(d.skin)] : no_joints,
                    place, mesh, out);
        MeshPart& part = out.parts[p];
        part.bounds = compute_bounds({out.positions.begin() + part.first_vertex,
                                      out.positions.begin() + part.first_vertex + part.vertex_count});
    }
    out.bounds = compute_bounds(out.positions);
}

}  // namespace facet
