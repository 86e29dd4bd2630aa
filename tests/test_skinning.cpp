// Skins, morph targets and clips: a mesh file's own deformation and
// animation, held to a double-precision reference (facet/mesh.hpp,
// pose_mesh; scene_clip.hpp).
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/mesh.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <spdlog/spdlog.h>

#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace facet;
using facet::test::SceneDir;

namespace {

const std::string kAssets = std::string(FACET_SOURCE_DIR) + "/assets/skin/";

// A small deterministic generator (no std:: distributions, whose output
// differs between standard libraries).
struct Lcg {
    uint64_t state = 12345;
    double next() {  // [0, 1)
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) / double(1ull << 53);
    }
    double in(double a, double b) { return a + (b - a) * next(); }
};

glm::dmat4 trs(const glm::dvec3& t, const glm::dquat& r, const glm::dvec3& s) {
    return glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(r) * glm::scale(glm::dmat4(1.0), s);
}

// A chain of 9 nodes, each a little turned and scaled unevenly, and a
// clip that turns node 2, and moves and scales node 5, over a second.
Mesh chain_mesh() {
    Mesh m;
    m.source = "chain (made in code)";
    for (int i = 0; i < 9; ++i) {
        MeshNode n;
        n.name = "node" + std::to_string(i);
        n.parent = i - 1;
        n.rest.translation = {0.3f, 0.5f, 0.1f * float(i)};
        n.rest.rotation = glm::angleAxis(0.1f * float(i), glm::normalize(glm::vec3(1, 2, 3)));
        n.rest.scale = {i == 6 ? -1.1f : 1.1f, 0.9f, 1.0f};  // node 6 mirrors
        m.nodes.push_back(n);
    }
    MeshClip clip;
    clip.name = "bend";
    clip.nodes.resize(m.nodes.size());
    clip.nodes[2].rotation.times = {0.0, 1.0};
    clip.nodes[2].rotation.values = {m.nodes[2].rest.rotation,
                                     glm::angleAxis(1.2f, glm::normalize(glm::vec3(0, 0, 1)))};
    clip.nodes[5].position.times = {0.0, 0.5, 1.0};
    clip.nodes[5].position.values = {{0.3f, 0.5f, 0.5f}, {0.8f, 0.1f, 0.4f}, {0.3f, -0.4f, 0.2f}};
    clip.nodes[5].scale.times = {0.25, 1.0};
    clip.nodes[5].scale.values = {{1, 1, 1}, {1.5f, 0.7f, 1.2f}};
    m.clips.push_back(clip);
    return m;
}

// `chain_mesh` skinned: 200 vertices, each on 8 of the chain's joints.
Mesh skinned_chain() {
    Lcg rng;
    Mesh m = chain_mesh();
    const size_t n = 200;
    MeshSkin skin;
    skin.name = "chain";
    // Bound where the chain is at rest, but unmirrored: the joints from
    // node 6 on mirror the vertices they carry.
    std::vector<glm::dmat4> bind(m.nodes.size());
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        const Transform& r = m.nodes[i].rest;
        bind[i] = (i ? bind[i - 1] : glm::dmat4(1.0)) *
                  trs(glm::dvec3(r.translation), glm::dquat(r.rotation), glm::abs(glm::dvec3(r.scale)));
    }
    for (int j = 1; j < 9; ++j) {
        skin.joints.push_back(j);
        skin.inverse_binds.push_back(glm::mat4(glm::inverse(bind[size_t(j)])));
    }
    m.skins.push_back(skin);
    PartDeformation d;
    d.skin = 0;
    for (size_t v = 0; v < n; ++v) {
        d.positions.emplace_back(rng.in(-1, 1), rng.in(0, 3), rng.in(-1, 1));
        d.normals.push_back(glm::normalize(glm::vec3(rng.in(-1, 1), rng.in(-1, 1), rng.in(0.1, 1))));
        d.tangents.emplace_back(glm::normalize(glm::vec3(rng.in(0.1, 1), rng.in(-1, 1), rng.in(-1, 1))),
                                v % 2 ? 1.0f : -1.0f);
        JointWeights jw;
        double w[8], sum = 0.0;
        for (double& x : w) sum += x = rng.in(0.05, 1.0);
        std::sort(w, w + 8, [](double a, double b) { return a > b; });
        for (int k = 0; k < 8; ++k) {
            jw.joint[k] = uint16_t((v + size_t(k) * 3) % 8);  // 8 distinct joints
            jw.weight[k] = float(w[k] / sum);
        }
        d.joints.push_back(jw);
    }
    m.positions = d.positions;
    m.normals = d.normals;
    m.tangents = d.tangents;
    for (uint32_t i = 0; i + 2 < n; i += 3) m.indices.insert(m.indices.end(), {i, i + 1, i + 2});
    MeshPart part;
    part.name = "body";
    part.index_count = uint32_t(m.indices.size());
    part.vertex_count = uint32_t(n);
    part.node = 0;
    m.parts.push_back(part);
    m.deformations.push_back(d);
    return m;
}

// Track values in double: held, mixed, or slerped, as animation.hpp says.
template <class T>
T track_at(const Track<T>& track, double t, const T& rest) {
    if (track.empty()) return rest;
    if (t <= track.times.front()) return track.values.front();
    if (t >= track.times.back()) return track.values.back();
    size_t k = 0;
    while (track.times[k + 1] <= t) ++k;
    const double u = (t - track.times[k]) / (track.times[k + 1] - track.times[k]);
    if constexpr (std::is_same_v<T, glm::quat>)
        return glm::quat(glm::slerp(glm::dquat(track.values[k]), glm::dquat(track.values[k + 1]), u));
    else
        return T(glm::mix(glm::dvec3(track.values[k]), glm::dvec3(track.values[k + 1]), u));
}

// The reference: each node's place in double, each vertex through the
// weighted sum of its joints' matrices, its normal through the inverse
// transpose.
void reference_skin(const Mesh& m, double t, std::vector<glm::dvec3>& positions,
                    std::vector<glm::dvec3>& normals, std::vector<glm::dvec4>& tangents) {
    const MeshClip& clip = m.clips[0];
    std::vector<glm::dmat4> place(m.nodes.size());
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        const Transform& r = m.nodes[i].rest;
        const TransformTracks& k = clip.nodes[i];
        const glm::dmat4 local = trs(glm::dvec3(track_at(k.position, t, r.translation)),
                                     glm::dquat(track_at(k.rotation, t, r.rotation)),
                                     glm::dvec3(track_at(k.scale, t, r.scale)));
        place[i] = m.nodes[i].parent >= 0 ? place[size_t(m.nodes[i].parent)] * local : local;
    }
    const PartDeformation& d = m.deformations[0];
    const MeshSkin& skin = m.skins[0];
    positions.clear();
    normals.clear();
    tangents.clear();
    for (size_t v = 0; v < d.positions.size(); ++v) {
        glm::dmat4 blend(0.0);
        for (int k = 0; k < 8; ++k) {
            const uint16_t j = d.joints[v].joint[k];
            blend += double(d.joints[v].weight[k]) *
                     (place[size_t(skin.joints[j])] * glm::dmat4(skin.inverse_binds[j]));
        }
        positions.push_back(glm::dvec3(blend * glm::dvec4(glm::dvec3(d.positions[v]), 1.0)));
        normals.push_back(glm::normalize(glm::transpose(glm::inverse(glm::dmat3(blend))) *
                                         glm::dvec3(d.normals[v])));
        // A mirroring blend turns the bitangent's side.
        const double w = glm::determinant(glm::dmat3(blend)) < 0.0 ? -d.tangents[v].w : d.tangents[v].w;
        tangents.emplace_back(glm::normalize(glm::dmat3(blend) * glm::dvec3(d.tangents[v])), w);
    }
}

Scene scene_with(SceneDir& dir, const std::string& object, const std::string& extra = "") {
    return dir.load(extra + "objects:\n  - {" + object + ", material: {shader: unlit}}\n");
}

}  // namespace

TEST_CASE("skinning with 8 joints a vertex matches a double-precision reference", "[skin]") {
    const Mesh m = skinned_chain();
    REQUIRE_NOTHROW(validate_mesh(m));
    Mesh posed = m;
    std::vector<glm::dvec3> want, want_normals;
    std::vector<glm::dvec4> want_tangents;
    const double size = 4.0;  // the chain's vertices lie within a few units
    size_t mirrored = 0;
    for (const double t : {0.0, 0.3, 0.5, 0.75, 1.0, 2.0}) {
        pose_mesh(m, 0, t, {}, posed);
        reference_skin(m, t, want, want_normals, want_tangents);
        double worst = 0.0, worst_normal = 0.0, worst_tangent = 0.0;
        for (size_t v = 0; v < want.size(); ++v) {
            worst = std::max(worst, glm::length(glm::dvec3(posed.positions[v]) - want[v]));
            worst_normal = std::max(worst_normal, glm::length(glm::dvec3(posed.normals[v]) - want_normals[v]));
            worst_tangent = std::max(worst_tangent, glm::length(glm::dvec4(posed.tangents[v]) - want_tangents[v]));
            mirrored += want_tangents[v].w != double(m.deformations[0].tangents[v].w);
        }
        INFO("t = " << t);
        CHECK(worst / size < 1e-5);
        CHECK(worst_normal < 1e-5);
        CHECK(worst_tangent < 1e-5);
    }
    CHECK(mirrored > 0);  // some blends mirror, and the handedness follows
    // The bounds follow the pose.
    pose_mesh(m, 0, 1.0, {}, posed);
    CHECK(posed.bounds.max == compute_bounds(posed.positions).max);
    CHECK(posed.parts[0].bounds.min == compute_bounds(posed.positions).min);
}

TEST_CASE("bad skins are refused with the file and the cause", "[skin][errors]") {
    Mesh m = skinned_chain();
    SECTION("a joint outside the skin") {
        m.deformations[0].joints[7].joint[2] = 8;
        CHECK_THROWS_WITH(validate_mesh(m), Catch::Matchers::Contains("joint outside its skin"));
    }
    SECTION("a weight that is not a number") {
        m.deformations[0].joints[3].weight[0] = std::nanf("");
        CHECK_THROWS_WITH(validate_mesh(m), Catch::Matchers::Contains("chain (made in code)") &&
                                                Catch::Matchers::Contains("joint weight outside [0, 1]"));
    }
    SECTION("a deformed part in a mesh without normals") {
        m.normals.clear();
        CHECK_THROWS_WITH(validate_mesh(m), Catch::Matchers::Contains("deforms a part but has no normals"));
    }
    SECTION("a rotation key that is not unit length") {
        m.clips[0].nodes[2].rotation.values[1] = glm::quat(2, 0, 0, 0);
        CHECK_THROWS_WITH(validate_mesh(m), Catch::Matchers::Contains("not unit length"));
    }
    SECTION("morph weights a key that do not match the targets") {
        m.deformations[0].targets.push_back({"t", std::vector<glm::vec3>(200), {}, {}});
        m.deformations[0].weights.push_back(0.0f);
        m.clips[0].weights.resize(1);
        m.clips[0].weights[0].times = {0.0, 1.0};
        m.clips[0].weights[0].values = {0.0f, 1.0f, 0.5f};  // 3 values for 2 keys of 1 target
        CHECK_THROWS_WITH(validate_mesh(m), Catch::Matchers::Contains("one per target"));
    }
    SECTION("a node placed past float's range") {
        m.clips[0].nodes[5].scale.values[1] = glm::vec3(1e20f);
        m.clips[0].nodes[6].position.times = {0.0};
        m.clips[0].nodes[6].position.values = {glm::vec3(1e15f)};
        CHECK_THROWS_WITH(validate_mesh(m), Catch::Matchers::Contains("past 1e30"));
    }
}

TEST_CASE("a skinned glTF plays its first clip, as its joints pose it", "[skin][model]") {
    SceneDir dir;
    Scene scene = scene_with(dir, "mesh: " + kAssets + "tentacle.gltf");
    Object& o = scene.objects[0];
    REQUIRE(o.mesh->skins.size() == 1);
    CHECK(o.mesh->skins[0].joints.size() == 5);
    REQUIRE(o.mesh->clips.size() == 2);
    CHECK(o.mesh->clips[0].name == "wave");
    CHECK(o.mesh->clips[1].name == "curl");
    CHECK(o.clip == 0);
    CHECK(scene.timeline.end == Approx(2.0));
    // At 0.5 s, a key of "wave": joint k turns 0.45 cos(0.9 k) about +Z.
    // The top ring and its cap hang on joint 4 (1.05 / 1.1) and joint 3
    // (0.05 / 1.1), as make_skin.py weighs them.
    scene.pose(0.5);
    std::vector<glm::dmat4> place(5);
    for (int k = 0; k < 5; ++k) {
        const glm::dmat4 local = glm::translate(glm::dmat4(1.0), glm::dvec3(0, k ? 0.5 : 0.0, 0)) *
                                 glm::rotate(glm::dmat4(1.0), 0.45 * std::cos(0.9 * k), glm::dvec3(0, 0, 1));
        place[size_t(k)] = k ? place[size_t(k) - 1] * local : local;
    }
    const auto joint = [&](int k) {
        return place[size_t(k)] * glm::translate(glm::dmat4(1.0), glm::dvec3(0, -0.5 * k, 0));
    };
    const glm::dmat4 blend = (1.05 * joint(4) + 0.05 * joint(3)) / 1.1;
    const Mesh& rest = *o.mesh;
    const Mesh& posed = *o.drawn_mesh();
    size_t top = 0;
    for (size_t v = 0; v < rest.vertex_count(); ++v) {
        if (rest.positions[v].y < 2.4999f) continue;
        ++top;
        const glm::dvec3 want = glm::dvec3(blend * glm::dvec4(glm::dvec3(rest.positions[v]), 1.0));
        CHECK(glm::length(glm::dvec3(posed.positions[v]) - want) / 2.5 < 1e-5);
    }
    CHECK(top == 51);  // the top ring, and the cap's centre and rim
    CHECK(posed.bounds.max.x != rest.bounds.max.x);
}

TEST_CASE("morph targets blend by the clip's weights, or the scene's", "[skin][model][morph]") {
    SceneDir dir;
    // make_skin.py's blob: a sphere of radius 0.5, "spikes" bumps it along
    // its normal by 0.12 max(0, sin 6 theta sin 5 phi)^2, and "squash" moves
    // it by (0.15 x, -0.2 y, 0.15 z) of its normal. At 1 s both weigh 1.
    const auto spiked = [](const glm::dvec3& n) {
        const double phi = std::acos(std::clamp(n.y, -1.0, 1.0));
        const double theta = std::atan2(-n.z, n.x);
        return 0.12 * std::pow(std::max(0.0, std::sin(6 * theta) * std::sin(5 * phi)), 2.0);
    };
    const auto squash = [](const glm::dvec3& n) { return glm::dvec3(0.15 * n.x, -0.2 * n.y, 0.15 * n.z); };
    SECTION("the file's clip") {
        Scene scene = scene_with(dir, "mesh: " + kAssets + "blob.gltf");
        const Object& o = scene.objects[0];
        REQUIRE(o.mesh->deformations.size() == 1);
        CHECK(o.mesh->deformations[0].targets.size() == 2);
        scene.pose(1.0);
        for (size_t v = 0; v < o.mesh->vertex_count(); ++v) {
            const glm::dvec3 n = glm::dvec3(o.mesh->positions[v]) / 0.5;
            const glm::dvec3 want = n * (0.5 + spiked(n)) + squash(n);
            CHECK(glm::length(glm::dvec3(o.drawn_mesh()->positions[v]) - want) < 1e-5);
        }
    }
    SECTION("weights the scene sets, with no clip") {
        Scene scene = scene_with(dir, "mesh: " + kAssets + "blob.gltf, animate: {clip: none, weights: {squash: 1}}");
        const Object& o = scene.objects[0];
        CHECK(o.clip == -1);
        CHECK_FALSE(scene.animated());
        for (size_t v = 0; v < o.mesh->vertex_count(); ++v) {
            const glm::dvec3 n = glm::dvec3(o.mesh->positions[v]) / 0.5;
            CHECK(glm::length(glm::dvec3(o.drawn_mesh()->positions[v]) - (n * 0.5 + squash(n))) < 1e-6);
        }
        CHECK_THAT(dir.error("objects:\n  - {mesh: " + kAssets + "blob.gltf, material: {shader: unlit}, "
                             "animate: {weights: {spike: 1}}}\n"),
                   Catch::Matchers::Contains("'spike' is no morph target") &&
                       Catch::Matchers::Contains("'spikes', 'squash'"));
    }
}

TEST_CASE("a scene chooses a file's clip by name or index", "[skin][model][clips]") {
    SceneDir dir;
    const std::string mesh = "mesh: " + kAssets + "tentacle.gltf";
    Scene wave = scene_with(dir, mesh);
    Scene curl = scene_with(dir, mesh + ", animate: {clip: curl}");
    Scene by_index = scene_with(dir, mesh + ", animate: {clip: 1}");
    Scene scene_wide = scene_with(dir, mesh, "animation: {clip: curl}\n");
    CHECK(curl.objects[0].clip == 1);
    CHECK(by_index.objects[0].clip == 1);
    CHECK(scene_wide.objects[0].clip == 1);
    for (Scene* s : {&wave, &curl, &by_index, &scene_wide}) s->pose(0.5);
    CHECK(wave.objects[0].drawn_mesh()->positions != curl.objects[0].drawn_mesh()->positions);
    CHECK(curl.objects[0].drawn_mesh()->positions == by_index.objects[0].drawn_mesh()->positions);
    CHECK(curl.objects[0].drawn_mesh()->positions == scene_wide.objects[0].drawn_mesh()->positions);
    const std::string error = dir.error("objects:\n  - {" + mesh +
                                        ", material: {shader: unlit}, animate: {clip: jump}}\n");
    CHECK_THAT(error, Catch::Matchers::Contains("'jump' is no clip of") &&
                          Catch::Matchers::Contains("0 'wave', 1 'curl'"));
    CHECK_THAT(dir.error("objects:\n  - {" + mesh + ", material: {shader: unlit}, animate: {clip: 2}}\n"),
               Catch::Matchers::Contains("'2' is no clip"));
}

TEST_CASE("a deformed mesh draws and casts as posed; posing is a pure function of time",
          "[skin][model]") {
    SceneDir dir;
    Scene scene = dir.load("render: {size: [48, 48], color_format: rgba32f}\n"
                           "camera: {position: [0, 1.3, 5], target: [0, 1.3, 0]}\n"
                           "lights:\n  - {type: directional, direction: [-0.3, -1, -0.4], casts_shadow: true}\n"
                           "objects:\n"
                           "  - {mesh: " + kAssets + "tentacle.gltf, material: {shader: phong}}\n"
                           "  - {mesh: " + std::string(FACET_SOURCE_DIR) + "/assets/plane/plane.obj, scale: 4, "
                           "material: {shader: phong}}\n");
    Renderer renderer(1);
    Framebuffer rest, moved, again, fresh;
    scene.pose(0.0);
    renderer.render(scene, rest);
    scene.pose(0.5);
    renderer.render(scene, moved);
    CHECK_FALSE(test::same_image(rest, moved));
    // Posed twice with no frame between (so that the pose written second
    // goes into the copy the shadow map's key still holds, unless pose()
    // takes a new one), then drawn: the same image, bit for bit, as a
    // renderer that never drew another pose.
    scene.pose(1.2);
    scene.pose(0.0);
    renderer.render(scene, again);
    Scene other = scene;
    Renderer new_renderer(1);
    other.pose(0.0);
    new_renderer.render(other, fresh);
    CHECK(test::same_image(again, fresh));
    CHECK(test::same_image(rest, fresh));
    scene.pose(0.5);
    renderer.render(scene, again);
    CHECK(test::same_image(moved, again));
}

TEST_CASE("a skinned file's import comes back whole from facet-sandbox", "[skin][model][sandbox]") {
    const auto isolated = load_mesh(kAssets + "tentacle.gltf", MeshImport::isolated);
    const auto in_process = load_mesh(kAssets + "tentacle.gltf", MeshImport::in_process);
    REQUIRE(isolated->clips.size() == in_process->clips.size());
    CHECK(isolated->positions == in_process->positions);
    CHECK(isolated->nodes.size() == in_process->nodes.size());
    CHECK(isolated->skins[0].joints == in_process->skins[0].joints);
    CHECK(isolated->deformations[0].joints.size() == in_process->deformations[0].joints.size());
    Mesh a = *isolated, b = *in_process;
    pose_mesh(*isolated, 1, 0.7, {}, a);
    pose_mesh(*in_process, 1, 0.7, {}, b);
    CHECK(a.positions == b.positions);
    CHECK(a.normals == b.normals);
    const auto blob_isolated = load_mesh(kAssets + "blob.gltf", MeshImport::isolated);
    const auto blob_in_process = load_mesh(kAssets + "blob.gltf", MeshImport::in_process);
    Mesh c = *blob_isolated, d = *blob_in_process;
    pose_mesh(*blob_isolated, 0, 1.3, {{"squash", 0.25f}}, c);
    pose_mesh(*blob_in_process, 0, 1.3, {{"squash", 0.25f}}, d);
    CHECK(c.positions == d.positions);
    CHECK(c.positions != blob_isolated->positions);
}

namespace {

// Every corner of the object's bounds, as posed, inside the camera's view.
bool in_view(const Scene& scene, size_t index) {
    const Object& o = scene.objects[index];
    const Bounds& b = o.drawn_mesh()->bounds;
    const float aspect = float(scene.settings.width) / float(scene.settings.height);
    const glm::mat4 clip = scene.camera.projection(aspect, false) * scene.camera.view() *
                           o.transform.matrix();
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec4 p = clip * glm::vec4((corner & 1 ? b.max : b.min).x,
                                             (corner & 2 ? b.max : b.min).y,
                                             (corner & 4 ? b.max : b.min).z, 1.0f);
        if (!(p.w > 0.0f) || std::abs(p.x) > p.w * 1.0001f || std::abs(p.y) > p.w * 1.0001f ||
            p.z < -p.w * 1.0001f || p.z > p.w * 1.0001f)
            return false;
    }
    return true;
}

}  // namespace

TEST_CASE("a model file renders with no scene: its materials, framed and lit", "[model][frame]") {
    test::TempDir dir("model");
    PluginRegistry registry;
    SECTION("a skinned glTF plays its first clip, in view") {
        CHECK(is_model_file(kAssets + "tentacle.gltf"));
        CHECK_FALSE(is_model_file(std::string(FACET_SOURCE_DIR) + "/configs/default.yaml"));
        Scene scene = load_scene(kAssets + "tentacle.gltf", registry);
        REQUIRE(scene.objects.size() == 1);
        CHECK(scene.lights.size() == 3);
        CHECK(scene.objects[0].clip == 0);
        CHECK(scene.objects[0].material_of(0)->shader == "pbr");  // the file's own
        CHECK(in_view(scene, 0));
        CHECK(scene.animated());
    }
    SECTION("an OBJ in centimetres with no .mtl: as large in the frame, drawn grey") {
        // A 2 cm cube, and the same cube 100 times larger: the same image.
        std::string cube;
        for (int i = 0; i < 8; ++i)
            cube += "v " + std::to_string(i & 1 ? 0.02 : 0.0) + " " + std::to_string(i & 2 ? 0.02 : 0.0) +
                    " " + std::to_string(i & 4 ? 0.02 : 0.0) + "\n";
        cube += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
        test::write(dir.path / "small.obj", cube);
        std::string big = cube;
        for (size_t at = 0; (at = big.find("0.020000", at)) != std::string::npos;) big.replace(at, 8, "2.0");
        test::write(dir.path / "big.obj", big);
        Scene small = load_scene(dir.path / "small.obj", registry);
        Scene large = load_scene(dir.path / "big.obj", registry);
        CHECK(in_view(small, 0));
        CHECK(small.objects[0].material_of(0)->shader == "phong");
        for (Scene* s : {&small, &large}) {
            s->settings.width = s->settings.height = 64;
            s->settings.color_format = ColorFormat::srgb8;
        }
        Renderer renderer(1);
        Framebuffer a, b;
        renderer.render(small, a);
        renderer.render(large, b);
        const std::vector<uint8_t> pa = a.resolve_srgb8(), pb = b.resolve_srgb8();
        size_t covered = 0, differ = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                covered += a.depth_at(x, y) < 1.0f;
                differ += std::memcmp(&pa[size_t(y * 64 + x) * 4], &pb[size_t(y * 64 + x) * 4], 4) != 0;
            }
        CHECK(covered > 64 * 64 / 8);  // the cube fills the view's middle, not a pixel
        CHECK(differ < 64);            // the same picture, up to rounding at edges
    }
    SECTION("a model that cannot be read: its own error, with no place in a scene") {
        const auto missing = dir.path / "missing.glb";
        try {
            load_scene(missing, registry);
            FAIL("a missing model loaded");
        } catch (const Error& e) {
            CHECK(e.code() == ErrorCode::file_not_found);
            CHECK(e.line() == 0);
            CHECK(e.file() == missing.string());
        }
    }
    SECTION("a glTF with a camera of its own is seen through it") {
        // blob.gltf and a camera node at (0, 1, 5), turned 45 degrees about
        // +Y, with a vertical field of view of 0.7 radians.
        const std::string model = test::read_file(kAssets + "blob.gltf");
        std::string with_camera = model;
        const std::string nodes = "\"nodes\":[{\"name\":\"blob\",\"mesh\":0}]";
        const size_t at = with_camera.find(nodes);
        REQUIRE(at != std::string::npos);
        with_camera.replace(at, nodes.size(),
                            "\"nodes\":[{\"name\":\"blob\",\"mesh\":0},{\"name\":\"eye\",\"camera\":0,"
                            "\"translation\":[0,1,5],\"rotation\":[0,0.38268343,0,0.92387953]}],"
                            "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.7,"
                            "\"znear\":0.1,\"zfar\":100,\"aspectRatio\":1.5}}]");
        const std::string scenes = "\"scenes\":[{\"nodes\":[0]}]";
        const size_t s_at = with_camera.find(scenes);
        REQUIRE(s_at != std::string::npos);
        with_camera.replace(s_at, scenes.size(), "\"scenes\":[{\"nodes\":[0,1]}]");
        Scene scene = load_scene(dir.write("eye.gltf", with_camera), registry);
        const Camera& c = scene.camera;
        CHECK(glm::length(c.position - glm::vec3(0, 1, 5)) < 1e-5f);
        CHECK(glm::length(glm::normalize(c.target - c.position) - glm::vec3(-0.70710678f, 0, -0.70710678f)) < 1e-5f);
        CHECK(c.fov_y == Approx(40.107f).margin(0.01f));
        CHECK(c.near == Approx(0.1f));
        CHECK(c.far == Approx(100.0f));
    }
    SECTION("camera: {frame: NAME} in a scene") {
        SceneDir sd;
        Scene scene = sd.load("camera: {position: [0, 0, 50], target: [0, 0, 0], frame: blob}\n"
                              "objects:\n  - {name: blob, mesh: " + kAssets + "blob.gltf, position: [7, 3, 0]}\n");
        CHECK(in_view(scene, 0));
        CHECK(scene.camera.target.x == Approx(7.0f).margin(0.01f));
        CHECK_THAT(sd.error("camera: {frame: nothing}\nobjects:\n  - {name: blob, mesh: " + kAssets +
                            "blob.gltf}\n"),
                   Catch::Matchers::Contains("'nothing' names no object") &&
                       Catch::Matchers::Contains("'blob'"));
    }
}

TEST_CASE("a glTF file's extensions are each named, with what is done with it", "[model][extensions]") {
    test::TempDir dir("extensions");
    const std::string model = test::read_file(kAssets + "blob.gltf");
    REQUIRE(model.front() == '{');
    const auto path = dir.write(
        "ext.gltf", "{\"extensionsUsed\": [\"KHR_materials_sheen\", \"KHR_materials_unlit\", "
                    "\"EXT_fancy\"]," + model.substr(1));
    test::LogCapture log;
    const spdlog::level::level_enum before = spdlog::get_level();
    spdlog::set_level(spdlog::level::debug);  // -v: the drawn ones too
    load_mesh(path, MeshImport::in_process);
    spdlog::set_level(before);
    CHECK_THAT(log.text(), Catch::Matchers::Contains(
                               "extension KHR_materials_sheen: left out: no sheen"));
    CHECK_THAT(log.text(), Catch::Matchers::Contains("extension KHR_materials_unlit: drawn"));
    CHECK_THAT(log.text(), Catch::Matchers::Contains("extension EXT_fancy: left out: facet does not know it"));
}
