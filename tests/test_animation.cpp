// Animation and output at scale: keyframe tracks and posing, the time every
// draw sees, a mesh file's node animation, bands of rows that render as the
// whole image does, and the PNG written in segments.
#include "support.hpp"

#include <facet/animation.hpp>
#include <facet/error.hpp>
#include <facet/png.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/sequence.hpp>

#include <catch2/catch.hpp>
#include <glm/gtc/quaternion.hpp>
#include <stb/stb_image.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>

using namespace facet;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = FACET_SOURCE_DIR;

// The angle (degrees) by which q turns about +Y, for rotations about +Y.
double yaw_degrees(const glm::quat& q) {
    return glm::degrees(2.0 * std::atan2(double(q.y), double(q.w)));
}

// Degrees reduced to (-180, 180].
double wrap(double degrees) {
    degrees = std::fmod(degrees, 360.0);
    if (degrees > 180.0) degrees -= 360.0;
    if (degrees <= -180.0) degrees += 360.0;
    return degrees;
}

using test::SceneDir;

std::string plane_object(const std::string& animate) {
    return "objects:\n  - name: board\n    mesh: " + (kSource / "assets/plane/plane.obj").string() +
           "\n    material: {shader: unlit}\n    rotation: [0, 30, 0]\n" + animate;
}

bool same_matrix(const glm::mat4& a, const glm::mat4& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// CRC-32 as the PNG specification defines it (ISO 3309), bit by bit: an
// oracle that shares nothing with zlib's.
uint32_t crc32_of(const std::string& bytes) {
    uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return c ^ 0xFFFFFFFFu;
}

uint32_t big_endian(const std::string& s, size_t at) {
    return uint32_t(uint8_t(s[at])) << 24 | uint32_t(uint8_t(s[at + 1])) << 16 |
           uint32_t(uint8_t(s[at + 2])) << 8 | uint32_t(uint8_t(s[at + 3]));
}

// The file's chunk types in order; fails the test at a chunk whose CRC is
// not its type's and data's.
std::vector<std::string> checked_chunks(const std::string& png) {
    std::vector<std::string> types;
    REQUIRE(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    for (size_t at = 8; at + 12 <= png.size();) {
        const size_t length = big_endian(png, at);
        REQUIRE(at + 12 + length <= png.size());
        const std::string type = png.substr(at + 4, 4);
        CAPTURE(type, types.size());
        CHECK(big_endian(png, at + 8 + length) == crc32_of(png.substr(at + 4, 4 + length)));
        types.push_back(type);
        at += 12 + length;
    }
    return types;
}

}  // namespace

TEST_CASE("keyframe tracks hold, step, mix and slerp as documented", "[animation]") {
    Track<glm::vec3> move;
    move.times = {1.0, 3.0};
    move.values = {glm::vec3(0.0f), glm::vec3(2.0f, 4.0f, 6.0f)};
    CHECK(move.at(0.0) == glm::vec3(0.0f));                 // held before the first key
    CHECK(move.at(9.0) == glm::vec3(2.0f, 4.0f, 6.0f));     // and after the last
    CHECK(move.at(2.0) == glm::vec3(1.0f, 2.0f, 3.0f));     // halfway
    CHECK(move.at(2.5).z == Approx(4.5));
    move.interpolation = Interpolation::step;
    CHECK(move.at(2.999) == glm::vec3(0.0f));
    CHECK(move.at(3.0) == glm::vec3(2.0f, 4.0f, 6.0f));

    Track<glm::quat> turn;
    turn.times = {0.0, 1.0};
    turn.values = {euler_degrees({0, 0, 0}), euler_degrees({0, 90, 0})};
    CHECK(yaw_degrees(turn.at(0.5)) == Approx(45.0).margin(1e-4));
    CHECK(yaw_degrees(turn.at(0.25)) == Approx(22.5).margin(1e-4));  // constant angular speed
    turn.values[1] = euler_degrees({0, 350, 0});  // the short way: back through -5
    CHECK(wrap(yaw_degrees(turn.at(0.5))) == Approx(-5.0).margin(1e-4));

    TransformTracks spin;
    spin.spin = 90.0;
    Transform rest;
    rest.rotation = euler_degrees({0, 30, 0});
    rest.translation = {1, 2, 3};
    CHECK(wrap(yaw_degrees(spin.at(1.0, rest).rotation)) == Approx(120.0).margin(1e-4));
    // Ten hours in, the angle is still exact to well under a thousandth of a degree.
    CHECK(wrap(yaw_degrees(spin.at(36001.0, rest).rotation)) == Approx(120.0).margin(1e-3));
    CHECK(spin.at(1.0, rest).translation == rest.translation);  // no position track: at rest
    CHECK(spin.end() == Approx(4.0));                            // one turn

    CameraTracks orbit;
    orbit.orbit = 90.0;
    Camera camera;
    camera.position = {0, 0, 3};
    const Camera turned = orbit.at(1.0, camera);
    CHECK(turned.position.x == Approx(3.0).margin(1e-5));
    CHECK(turned.position.z == Approx(0.0).margin(1e-5));
    CHECK(turned.target == camera.target);
}

TEST_CASE("scenes animate objects and the camera from YAML; posing is a pure function of time",
          "[animation]") {
    SceneDir dir;
    const std::string yaml =
        "animation: {fps: 10}\n"
        "camera:\n  position: [0, 1, 4]\n  animate:\n    position: {keys: [{time: 0, value: [0, 1, 4]}, "
        "{time: 2, value: [2, 1, 4]}]}\n" +
        plane_object("    animate:\n      spin: {axis: [0, 1, 0], speed: 60}\n"
                     "      position: {interpolation: step, keys: [{time: 0, value: [0, 0, 0]}, "
                     "{time: 1.5, value: [0, 1, 0]}]}\n"
                     "      scale: {keys: [{time: 0, value: 1}, {time: 1, value: [1, 2, 1]}]}\n");
    Scene scene = dir.load(yaml);
    CHECK(scene.animated());
    CHECK(scene.timeline.end == Approx(6.0));  // the spin's turn outlasts every key
    CHECK(scene.timeline.first_frame() == 0);
    CHECK(scene.timeline.end_frame() == 60);
    CHECK(scene.time == 0.0);

    scene.pose(1.75);
    const Object& o = scene.objects[0];
    CHECK(scene.time == 1.75);
    CHECK(o.transform.translation == glm::vec3(0, 1, 0));  // step: the key at 1.5
    CHECK(o.transform.scale == glm::vec3(1, 2, 1));          // held after its last key
    CHECK(wrap(yaw_degrees(o.transform.rotation)) == Approx(30.0 + 105.0).margin(1e-3));
    CHECK(scene.camera.position.x == Approx(1.75));

    // Posed elsewhere first, or freshly loaded: the same scene, bit for bit.
    const glm::mat4 at_175 = o.transform.matrix();
    const glm::vec3 camera_175 = scene.camera.position;
    scene.pose(0.3);
    CHECK_FALSE(same_matrix(o.transform.matrix(), at_175));
    scene.pose(1.75);
    CHECK(same_matrix(o.transform.matrix(), at_175));
    Scene fresh = dir.load(yaml);
    fresh.pose(1.75);
    CHECK(same_matrix(fresh.objects[0].transform.matrix(), at_175));
    CHECK(fresh.camera.position == camera_175);

    // A camera put by hand stays where it is put, whatever the time.
    Camera still;
    still.position = {5, 5, 5};
    fresh.set_camera(still);
    fresh.pose(0.5);
    CHECK(fresh.camera.position == still.position);
}

TEST_CASE("bad animation input names the file, line and problem", "[animation][errors]") {
    SceneDir dir;
    CHECK_THAT(dir.error(plane_object("    animate:\n      position: {keys: [{time: 1, value: [0, 0, 0]}, "
                                      "{time: 1, value: [1, 0, 0]}]}\n")),
               Contains("scene.yaml:7:") && Contains("each later than the one before"));
    CHECK_THAT(dir.error(plane_object("    animate: {spin: 0}\n")),
               Contains("scene.yaml:6:") && Contains("does not move"));
    CHECK_THAT(dir.error(plane_object("    animate: {spin: {speed: 10, axis: [0, 0, 0]}}\n")),
               Contains("spin axis must not be zero"));
    CHECK_THAT(dir.error(plane_object("    animate: {position: {keys: [], interpolation: linear}}\n")),
               Contains("a track needs a key"));
    CHECK_THAT(dir.error(plane_object("    animate: {position: {keys: [{time: 0, value: [0, 0, 0]}], "
                                      "interpolation: cubic}}\n")),
               Contains("'cubic' (expected one of: linear, step)"));
    CHECK_THAT(dir.error(plane_object("    animate: {wobble: 3}\n")), Contains("wobble"));
    CHECK_THAT(dir.error(plane_object("    animate: {position: {keys: [{time: -1, value: [0, 0, 0]}]}}\n")),
               Contains("0..1e9 seconds"));
    CHECK_THAT(dir.error("camera:\n  position: [0, 0, 3]\n  animate:\n    target: {keys: [{time: 2, "
                         "value: [0, 0, 3]}]}\n"),
               Contains("at 2 s") && Contains("target is at its position"));
    // Between keys too: this path runs through the target half way.
    CHECK_THAT(dir.error("camera:\n  position: [0, 0, 3]\n  animate:\n    position: {keys: [{time: 0, "
                         "value: [0, 0, -1]}, {time: 2, value: [0, 0, 1]}]}\n"),
               Contains("at 1 s") && Contains("target is at its position"));
    CHECK_THAT(dir.error("animation: {fps: 0}\n"), Contains("fps must be 0.001..1000"));
    CHECK_THAT(dir.error("animation: {start: 2, end: 1}\n"), Contains("end must be after start"));
    CHECK_THAT(dir.error("animation: {start: 2}\n" + plane_object("    animate: {position: {keys: "
                                                                    "[{time: 1, value: [0, 0, 0]}]}}\n")),
               Contains("at or after the animation's end (1 s)"));
    Scene still = dir.load(plane_object(""));
    CHECK_THROWS_WITH(still.pose(std::nan("")), Contains("finite time"));
}

TEST_CASE("every draw and screen pass sees the scene's time", "[animation]") {
    SceneDir dir;
    dir.registry.add_scene_path(FACET_TEST_PLUGIN_DIR);
    Scene scene = dir.load(
        "render: {size: [16, 8], color_format: rgba32f, cull: none}\n"
        "camera: {position: [0, 0, 2]}\n" +
        plane_object("") );
    scene.objects[0].transform = {};
    scene.objects[0].transform.rotation = euler_degrees({90, 0, 0});  // the plane faces the camera
    scene.objects[0].transform.scale = glm::vec3(4.0f);
    scene.objects[0].use_material(std::make_shared<Material>(*scene.objects[0].material));
    scene.objects[0].material->plugin = dir.registry.get("time_and_row");
    scene.objects[0].material->block = nullptr;
    Renderer renderer(1);
    Framebuffer target;
    for (double t : {0.0, 0.25, 1.5}) {
        scene.pose(t);
        renderer.render(scene, target);
        CHECK(target.pixel(8, 4).g == float(t));
    }
}

TEST_CASE("a glTF file's node animation moves its parts through the same tracks", "[animation][model]") {
    SceneDir dir;
    // One triangle on a child node (rest translation (0, 1, 0)) under a
    // root turned 90 degrees about +Y; the child moves along its parent's
    // +X by 2 in one second.
    test::write(dir.dir / "mover.gltf", R"({
 "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"name": "root", "rotation": [0, 0.70710678, 0, 0.70710678], "children": [1]},
           {"name": "mover", "mesh": 0, "translation": [0, 1, 0]}],
 "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}}]}],
 "animations": [{"channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
                 "samplers": [{"input": 1, "output": 2, "interpolation": "LINEAR"}]}],
 "buffers": [{"byteLength": 68, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAAAAAACAPwAAAAAAAABAAACAPwAAAAA="}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                 {"buffer": 0, "byteOffset": 36, "byteLength": 8},
                 {"buffer": 0, "byteOffset": 44, "byteLength": 24}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0]},
               {"bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
               {"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"}]
})");
    Scene scene = dir.load("objects:\n  - {mesh: mover.gltf, material: {shader: unlit}}\n");
    const Object& o = scene.objects[0];
    REQUIRE(o.mesh->nodes.size() == 2);
    REQUIRE(o.mesh->parts.size() == 1);
    CHECK(o.mesh->nodes[size_t(o.mesh->parts[0].node)].name == "mover");
    CHECK(scene.timeline.end == Approx(1.0));
    // At rest (t = 0) the part is where the file puts it.
    REQUIRE(o.part_poses.size() == 1);
    const glm::vec4 rest_vertex = o.part_matrix(0) * glm::vec4(o.mesh->positions[0], 1.0f);
    CHECK(glm::length(glm::vec3(rest_vertex) - o.mesh->positions[0]) < 1e-6f);
    // Half way, 1 along the parent's +X, which the root turned to world -Z.
    scene.pose(0.5);
    const glm::vec3 moved = glm::vec3(o.part_matrix(0) * glm::vec4(o.mesh->positions[0], 1.0f));
    const glm::vec3 expected = o.mesh->positions[0] + glm::vec3(0, 0, -1);
    CHECK(glm::length(moved - expected) < 1e-5f);
    // The renderer draws it there: a view straight down the motion sees the
    // triangle's image move.
    scene.settings.width = 32;
    scene.settings.height = 32;
    scene.settings.color_format = ColorFormat::rgba32f;
    scene.settings.cull = CullMode::none;
    scene.camera.position = {5, 1.5f, -0.5f};  // the triangle lies in the plane x = 0
    scene.camera.target = {0, 1.0f, -0.5f};
    Renderer renderer(1);
    Framebuffer a, b;
    scene.pose(0.0);
    renderer.render(scene, a);
    scene.pose(1.0);
    renderer.render(scene, b);
    CHECK_FALSE(test::same_image(a, b));
}

TEST_CASE("a band of rows renders bit for bit as those rows of the whole image", "[animation][bands]") {
    PluginRegistry registry;
    for (const char* name : {"scenes/shadow.yaml", "scenes/gallery.yaml", "scenes/cutout.yaml",
                             "scenes/turntable.yaml"}) {
        Scene scene = test::small_demo_scene(registry, name);
        scene.settings.ao = false;
        scene.settings.post = false;
        for (int msaa : {1, 4}) {
            scene.settings.msaa = msaa;
            scene.settings.wireframe = msaa == 4;
            CAPTURE(name, msaa);
            Renderer renderer(2);
            Framebuffer whole, band;
            renderer.render(scene, whole);
            std::vector<uint8_t> all, rows;
            renderer.pipeline().resolve_srgb8(whole, all);
            const size_t row_bytes = size_t(scene.settings.width) * 4;
            for (auto [first, count] : {std::pair{0, 16}, {16, 64}, {80, 27}, {108, 3}}) {
                renderer.render_rows(scene, first, count, band);
                REQUIRE(band.height() == count);
                renderer.pipeline().resolve_srgb8(band, rows);
                CHECK(std::memcmp(rows.data(), all.data() + size_t(first) * row_bytes,
                                  rows.size()) == 0);
            }
        }
    }
    // A fragment's window y is the whole image's.
    SceneDir dir;
    dir.registry.add_scene_path(FACET_TEST_PLUGIN_DIR);
    Scene scene = dir.load("render: {size: [8, 64], color_format: rgba32f, cull: none}\n"
                           "camera: {position: [0, 0, 2]}\n" + plane_object(""));
    scene.objects[0].transform = {};
    scene.objects[0].transform.rotation = euler_degrees({90, 0, 0});
    scene.objects[0].transform.scale = glm::vec3(8.0f);
    scene.objects[0].material->plugin = dir.registry.get("time_and_row");
    Renderer renderer(1);
    Framebuffer band;
    renderer.render_rows(scene, 40, 8, band);
    CHECK(band.pixel(3, 2).b == Approx((42 + 0.5) / 1024.0));
}

TEST_CASE("bands refuse screen-space passes and rows outside the image", "[animation][bands][errors]") {
    PluginRegistry registry;
    Scene ao = test::small_demo_scene(registry, "scenes/ao.yaml");
    Renderer renderer(1);
    Framebuffer band;
    CHECK_THROWS_WITH(renderer.render_rows(ao, 0, 16, band), Contains("ambient occlusion"));
    ao.settings.ao = false;
    CHECK_NOTHROW(renderer.render_rows(ao, 0, 16, band));
    Scene post = test::small_demo_scene(registry, "scenes/post.yaml");
    CHECK_THROWS_WITH(renderer.render_rows(post, 64, 16, band), Contains("post chain"));
    CHECK_THROWS_WITH(renderer.render_rows(ao, 100, 12, band), Contains("rows 100..111 of a 197x111"));
    CHECK_THROWS_WITH(renderer.render_rows(ao, -1, 12, band), Contains("rows -1..10"));
    CHECK_THROWS_WITH(renderer.render_rows(ao, 18, 12, band), Contains("not on a multiple of 4"));
}

TEST_CASE("PNGs written in segments decode to their pixels, the same bytes however split",
          "[animation][png]") {
    test::TempDir dir("png");
    const int width = 37, height = 3 * kPngSegmentRows + 5;
    std::vector<uint8_t> rgba(size_t(width) * height * 4);
    uint32_t state = 12345;
    for (size_t i = 0; i < rgba.size(); ++i) {
        state = state * 1664525u + 1013904223u;  // noise, and smooth runs for the filters
        rgba[i] = (i / 4) % 7 == 0 ? uint8_t(state >> 24) : uint8_t((i / 4 / width) * 3 + (i % 4) * 40);
    }
    const fs::path whole = dir.path / "whole.png";
    write_png_rows(whole, rgba.data(), size_t(width) * 4, width, height, 3);
    int w = 0, h = 0, channels = 0;
    stbi_uc* decoded = stbi_load(whole.c_str(), &w, &h, &channels, 4);
    REQUIRE(decoded);
    CHECK(w == width);
    CHECK(h == height);
    CHECK(std::memcmp(decoded, rgba.data(), rgba.size()) == 0);
    stbi_image_free(decoded);

    // Bands of two segments each, encoded one at a time, in one writer.
    const fs::path banded = dir.path / "banded.png";
    {
        PngWriter png(banded, width, height);
        for (int y = 0; y < height; y += 2 * kPngSegmentRows)
            for (const PngSegment& s : encode_png_rows(rgba.data() + size_t(y) * width * 4,
                                                       size_t(width) * 4, width, y,
                                                       std::min(2 * kPngSegmentRows, height - y),
                                                       height, 1))
                png.add(s);
        png.finish();
    }
    std::ifstream a(whole, std::ios::binary), b(banded, std::ios::binary);
    const std::string bytes_a{std::istreambuf_iterator<char>(a), {}};
    const std::string bytes_b{std::istreambuf_iterator<char>(b), {}};
    CHECK(bytes_a == bytes_b);
    const std::vector<std::string> chunks = checked_chunks(bytes_a);
    REQUIRE(chunks.size() >= 3);
    CHECK(chunks.front() == "IHDR");
    CHECK(chunks.back() == "IEND");

    // A writer that does not finish leaves nothing where the image goes.
    const fs::path cut = dir.path / "cut.png";
    {
        PngWriter png(cut, width, height);
        png.add(encode_png_segment(rgba.data(), size_t(width) * 4, width, kPngSegmentRows, false));
        CHECK_THROWS_WITH(png.finish(), Contains("ends after 64 of its 197 rows"));
    }
    CHECK_FALSE(fs::exists(cut));
    CHECK_FALSE(fs::exists(dir.path / "cut.png.part"));
    CHECK_THROWS_WITH(PngWriter(dir.path / "no-such-folder" / "x.png", 4, 4),
                      Contains("no-such-folder/x.png"));
}

TEST_CASE("frame ranges and output patterns parse strictly", "[animation][cli]") {
    Timeline timeline;
    timeline.fps = 24;
    timeline.end = 2.0;
    std::string error;
    CHECK(parse_frames("3..7", timeline, error)->count() == 5);
    CHECK(parse_frames("4", timeline, error)->first == 4);
    const auto all = parse_frames("all", timeline, error);
    REQUIRE(all);
    CHECK(all->first == 0);
    CHECK(all->last == 47);
    for (const char* bad : {"", "7..3", "1..", "..4", "-1..2", "a..b", "1...3", "1..2..3"}) {
        CAPTURE(bad);
        CHECK_FALSE(parse_frames(bad, timeline, error));
    }
    CHECK_FALSE(parse_frames("all", Timeline{}, error));
    CHECK_THAT(error, Contains("does not move"));
    // "all" at another fps counts the frames at that fps.
    const auto [at_12, fps] = frames_to_render("all", 12, timeline);
    CHECK(fps == 12);
    CHECK(at_12.last == 23);
    CHECK(frames_to_render("all", 0, timeline).first.last == 47);
    CHECK_THROWS_WITH(frames_to_render("9..3", 0, timeline), Contains("--frames"));
    // Times that are whole frames up to rounding are those frames.
    Timeline tenth;
    tenth.fps = 30;
    tenth.start = 0.1;
    tenth.end = 1.1;
    CHECK(tenth.first_frame() == 3);
    CHECK(tenth.end_frame() == 33);
    CHECK(tenth.frame_at(0.1) == 3);
    // Read from a file in double: in float, 1000.7 s at 10 fps would start
    // at frame 10008.
    SceneDir dir;
    const Scene late = dir.load("animation: {fps: 10, start: 1000.7, end: 1001}\n");
    CHECK(late.timeline.first_frame() == 10007);
    CHECK(late.timeline.end_frame() == 10010);
    // A band wider than one target holds is refused, saying how many rows fit.
    CHECK_NOTHROW(check_band(32768, 8192));
    CHECK_THROWS_WITH(check_band(32768, 8256), Contains("at most 8192 rows"));
    CHECK(check_finite_times(std::nan(""), 24).find("--time") != std::string::npos);
    CHECK(check_finite_times(1.0, std::nan("")).find("--fps") != std::string::npos);
    CHECK(check_finite_times(std::nullopt, 24).empty());

    CHECK(check_frame_pattern("out_%04d.png").empty());
    CHECK(check_frame_pattern("100%%_%d.png").empty());
    CHECK_THAT(check_frame_pattern("out.png"), Contains("no %d"));
    CHECK_THAT(check_frame_pattern("%d_%d.png"), Contains("more than one"));
    CHECK_THAT(check_frame_pattern("%s.png"), Contains("other than %d"));
    CHECK(frame_path("out_%04d.png", 7) == "out_0007.png");
    CHECK(frame_path("f%d.png", 12345) == "f12345.png");
    CHECK(frame_path("100%%_%3d.png", 5) == "100%_  5.png");
}
