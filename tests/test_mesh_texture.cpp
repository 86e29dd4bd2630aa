// Mesh loading (OBJ, PLY, glTF through assimp), mesh validation, texture
// decoding (PNG, JPEG), sampling and mipmaps, checked against hand-computed
// values; trilinear filtering against the analytic level of detail.
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/math.hpp>
#include <facet/mesh.hpp>
#include <facet/plugin.hpp>
#include <facet/texture.hpp>

#include <catch2/catch.hpp>

#include <stb/stb_image_write.h>

#include <algorithm>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace fs = std::filesystem;
using namespace facet;
using Catch::Matchers::Contains;

namespace {

using facet::test::TempDir;
using facet::test::clip_space_call;
using facet::test::make_mesh;

// An uncompressed 32-bit TGA, top row first; `rgba` holds 4 bytes per texel.
std::string tga(int width, int height, const std::vector<uint8_t>& rgba) {
    std::string out(18, '\0');
    out[2] = 2;  // uncompressed true-colour
    out[12] = char(width & 0xff);
    out[13] = char(width >> 8);
    out[14] = char(height & 0xff);
    out[15] = char(height >> 8);
    out[16] = 32;
    out[17] = 0x28;  // 8 alpha bits, origin top-left
    for (size_t i = 0; i < rgba.size(); i += 4)
        out += {char(rgba[i + 2]), char(rgba[i + 1]), char(rgba[i]), char(rgba[i + 3])};
    return out;
}

// A grey texture whose red channel holds `codes` (one row, linear data).
facet::TextureBinding row_texture(const TempDir& dir, const std::vector<uint8_t>& codes,
                                  facet::Filter filter, facet::Wrap wrap) {
    std::vector<uint8_t> rgba;
    for (uint8_t c : codes) rgba.insert(rgba.end(), {c, 0, 0, 255});
    const fs::path file = dir.write("row.tga", tga(int(codes.size()), 1, rgba));
    return {facet::load_texture(file, false), filter, wrap};
}

float red_at(const facet::TextureBinding& binding, float u) {
    return facet::sample(binding, {u, 0.5f}).r;
}

const char* kQuadObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3 4/4\n";

const char* kQuadPly =
    "ply\nformat ascii 1.0\nelement vertex 4\n"
    "property float x\nproperty float y\nproperty float z\n"
    "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 255 255 255\n"
    "4 0 1 2 3\n";

// One triangle in the XY plane (normal +Z) under a node turned 90 degrees
// about +Y and moved 2 along +Z. Buffer: 3 float3 positions, 3 uint16 indices.
const char* kTriangleGltf = R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "rotation": [0, 0.70710678, 0, 0.70710678], "translation": [0, 0, 2]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"byteLength": 42,
    "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA"}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 6, "target": 34963}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]
})";

void require_vec(const glm::vec3& got, const glm::vec3& want) {
    for (int i = 0; i < 3; ++i) REQUIRE(got[i] == Approx(want[i]).margin(1e-5));
}

facet::Mesh triangle_mesh() {
    facet::Mesh mesh;
    mesh.source = "inline";
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2};
    return mesh;
}

facet::ErrorCode error_code_of(const facet::Mesh& mesh) {
    try {
        facet::validate_mesh(mesh);
    } catch (const facet::Error& e) {
        return e.code();
    }
    throw std::runtime_error("validate_mesh accepted an invalid mesh");
}

}  // namespace

// ---- meshes -----------------------------------------------------------------------

TEST_CASE("OBJ quad is triangulated, joined, given normals and flipped UVs", "[mesh]") {
    TempDir dir("mesh");
    const auto mesh = facet::load_mesh(dir.write("quad.obj", kQuadObj));
    REQUIRE(mesh->triangle_count() == 2);
    REQUIRE(mesh->vertex_count() == 4);
    REQUIRE(mesh->normals.size() == 4);
    REQUIRE(mesh->uvs.size() == 4);
    REQUIRE(mesh->colors.empty());
    for (const glm::vec3& n : mesh->normals) require_vec(n, {0, 0, 1});
    for (size_t i = 0; i < 4; ++i)  // FlipUVs: v = 1 - v, so row 0 is at the top
        REQUIRE(mesh->uvs[i].y == Approx(1.0f - mesh->positions[i].y));
    require_vec(mesh->bounds.min, {0, 0, 0});
    require_vec(mesh->bounds.max, {1, 1, 0});
}

TEST_CASE("PLY quad keeps its vertex colours", "[mesh]") {
    TempDir dir("mesh");
    const auto mesh = facet::load_mesh(dir.write("quad.ply", kQuadPly));
    REQUIRE(mesh->triangle_count() == 2);
    REQUIRE(mesh->colors.size() == mesh->vertex_count());
    for (const glm::vec3& n : mesh->normals) require_vec(n, {0, 0, 1});
    for (size_t i = 0; i < mesh->vertex_count(); ++i) {
        const glm::vec3 p = mesh->positions[i];
        const glm::vec4 want = p.x == 0 && p.y == 0   ? glm::vec4(1, 0, 0, 1)
                               : p.x == 1 && p.y == 0 ? glm::vec4(0, 1, 0, 1)
                               : p.x == 1             ? glm::vec4(0, 0, 1, 1)
                                                      : glm::vec4(1, 1, 1, 1);
        for (int c = 0; c < 4; ++c) REQUIRE(mesh->colors[i][c] == Approx(want[c]));
    }
}

TEST_CASE("glTF node transforms apply to positions and normals", "[mesh]") {
    TempDir dir("mesh");
    const auto mesh = facet::load_mesh(dir.write("triangle.gltf", kTriangleGltf));
    REQUIRE(mesh->triangle_count() == 1);
    // (x, y, z) turns to (z, y, -x), then moves +2 in z.
    require_vec(mesh->positions[0], {0, 0, 2});
    require_vec(mesh->positions[1], {0, 0, 1});
    require_vec(mesh->positions[2], {0, 1, 2});
    for (const glm::vec3& n : mesh->normals) require_vec(n, {1, 0, 0});
}

TEST_CASE("Spot loads with UVs and unit normals", "[mesh]") {
    const auto mesh = facet::load_mesh(fs::path(FACET_SOURCE_DIR) / "assets/spot/spot.obj");
    REQUIRE(mesh->triangle_count() == 5856);
    REQUIRE(mesh->uvs.size() == mesh->vertex_count());
    for (const glm::vec3& n : mesh->normals) REQUIRE(glm::length(n) == Approx(1.0f));
}

TEST_CASE("mesh files that cannot be read are refused", "[mesh]") {
    TempDir dir("mesh");
    try {
        facet::load_mesh(dir.path / "missing.obj");
        FAIL("no error");
    } catch (const facet::Error& e) {
        REQUIRE(e.code() == facet::ErrorCode::file_not_found);
        REQUIRE(e.file() == (dir.path / "missing.obj").string());
    }
    try {
        facet::load_mesh(dir.write("broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"));
        FAIL("no error");
    } catch (const facet::Error& e) {
        REQUIRE(e.code() == facet::ErrorCode::mesh_load_failed);
        REQUIRE_FALSE(e.detail().empty());
    }
}

namespace {

// A one-triangle binary PLY, little- or big-endian, optionally cut short.
std::string binary_ply(bool big_endian, size_t drop_bytes = 0) {
    std::string out = std::string("ply\nformat ") +
                      (big_endian ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n";
    auto put = [&](const void* p, size_t n) {
        std::string bytes(static_cast<const char*>(p), n);
        if (big_endian) std::reverse(bytes.begin(), bytes.end());
        out += bytes;
    };
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(&f, 4);
    out += char(3);
    for (int32_t i : {0, 1, 2}) put(&i, 4);
    out.resize(out.size() - drop_bytes);
    return out;
}

facet::ErrorCode mesh_error(const fs::path& file) {
    try {
        facet::load_mesh(file);
    } catch (const facet::Error& e) {
        return e.code();
    }
    return facet::ErrorCode::config_invalid;  // loaded: not what these tests expect
}

}  // namespace

TEST_CASE("broken PLY files are refused, never hang or crash", "[mesh][ply]") {
    // assimp 5.2 alone loops forever on the first and crashes on the second.
    TempDir dir("mesh");
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                               "property float y\nproperty float z\nelement face 1\n"
                               "property list uchar int vertex_indices\nend_header\n";
    CHECK(mesh_error(dir.write("count.ply", "ply\nformat ascii 1.0\nelement vertex x\n")) ==
          facet::ErrorCode::mesh_load_failed);
    CHECK(mesh_error(dir.write("cut.ply", binary_ply(false, 7))) ==
          facet::ErrorCode::mesh_load_failed);
    CHECK(mesh_error(dir.write("cut_ascii.ply", header + "0 0 0\n1 0 0\n")) ==
          facet::ErrorCode::mesh_load_failed);
    CHECK(mesh_error(dir.write("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 3\n")) ==
          facet::ErrorCode::mesh_load_failed);
    CHECK(mesh_error(dir.write("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"
                                           "property quaternion x\nend_header\n1\n")) ==
          facet::ErrorCode::mesh_load_failed);
    try {
        facet::load_mesh(dir.write("count2.ply", "ply\nformat ascii 1.0\nelement vertex x\n"));
    } catch (const facet::Error& e) {
        CHECK(e.line() == 3);
        CHECK_THAT(e.what(), Contains("element 'vertex' has no valid count"));
    }
    // The same files, whole, load.
    CHECK(facet::load_mesh(dir.write("le.ply", binary_ply(false)))->triangle_count() == 1);
    CHECK(facet::load_mesh(dir.write("be.ply", binary_ply(true)))->triangle_count() == 1);
    CHECK(facet::load_mesh(dir.write("ok.ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"))
              ->triangle_count() == 1);
}

TEST_CASE("GLB files whose lengths run past the file are refused at once, named",
          "[mesh][glb]") {
    // assimp 5.2 alone spends seconds and hundreds of megabytes on such a
    // file; the preflight names the length that does not fit.
    TempDir dir("glb");
    const auto u32 = [](uint32_t v) {
        return std::string{char(v), char(v >> 8), char(v >> 16), char(v >> 24)};
    };
    const std::string json = "{\"asset\":{\"version\":\"2.0\"}}  ";  // 4-byte aligned
    const auto glb = [&](uint32_t version, uint32_t length, uint32_t chunk,
                         const std::string& type) {
        return "glTF" + u32(version) + u32(length) + u32(chunk) + type + json;
    };
    const uint32_t whole = uint32_t(20 + json.size());
    struct Case {
        std::string bytes;
        const char* says;
    };
    for (const Case& c : {Case{glb(2, whole + 1000, uint32_t(json.size()), "JSON"),
                               "the header says the file has"},
                          Case{glb(2, whole, 964, "JSON"), "says it holds 964 bytes, but only"},
                          Case{glb(3, whole, uint32_t(json.size()), "JSON"), "version 3"},
                          Case{glb(2, whole, uint32_t(json.size()), std::string("BIN\0", 4)),
                               "is not the JSON"},
                          Case{"glTF" + u32(2), "ends inside its 12-byte header"}}) {
        // Named .gltf: assimp would read it by its content all the same.
        const std::filesystem::path file = dir.write("bad.gltf", c.bytes);
        try {
            facet::load_mesh(file);
            FAIL("loaded");
        } catch (const facet::Error& e) {
            CHECK(e.code() == facet::ErrorCode::mesh_load_failed);
            CHECK_THAT(e.what(), Contains(c.says));
        }
    }
}

TEST_CASE("validate_mesh names the first problem", "[mesh]") {
    REQUIRE_NOTHROW(facet::validate_mesh(triangle_mesh()));

    facet::Mesh out_of_range = triangle_mesh();
    out_of_range.indices[2] = 3;
    REQUIRE(error_code_of(out_of_range) == facet::ErrorCode::mesh_invalid);
    REQUIRE_THROWS_WITH(facet::validate_mesh(out_of_range), Contains("uses vertex 3 of 3"));

    facet::Mesh not_finite = triangle_mesh();
    not_finite.positions[1].y = std::nanf("");
    REQUIRE_THROWS_WITH(facet::validate_mesh(not_finite),
                        Contains("vertex 1 has a non-finite position"));

    facet::Mesh short_normals = triangle_mesh();
    short_normals.normals = {{0, 0, 1}};
    REQUIRE(error_code_of(short_normals) == facet::ErrorCode::mesh_invalid);

    facet::Mesh empty;
    REQUIRE(error_code_of(empty) == facet::ErrorCode::mesh_invalid);
}

TEST_CASE("compute_bounds spans the positions", "[mesh]") {
    const facet::Bounds b = facet::compute_bounds({{1, -2, 3}, {-1, 4, 0}, {0, 0, 5}});
    require_vec(b.min, {-1, -2, 0});
    require_vec(b.max, {1, 4, 5});
}

// ---- textures -----------------------------------------------------------------------

TEST_CASE("sRGB textures are kept in 8 bits and decode colour to linear, alpha stays linear",
          "[texture]") {
    TempDir dir("mesh");
    const fs::path file = dir.write("px.tga", tga(2, 1, {0, 128, 255, 128, 188, 10, 0, 255}));
    const auto srgb = facet::load_texture(file, true);
    REQUIRE(srgb->width == 2);
    REQUIRE(srgb->height == 1);
    // Kept as the file has them, 8 bits a channel; decoded as they are read.
    REQUIRE(srgb->texels[0] == Texel8{0, 128, 255, 128});
    REQUIRE(srgb->texels[1] == Texel8{188, 10, 0, 255});
    REQUIRE(srgb->linear(0).r == Approx(0.0f));
    REQUIRE(srgb->linear(0).g == Approx(0.2158605f).epsilon(1e-4));  // sRGB 128
    REQUIRE(srgb->linear(0).b == Approx(1.0f));
    REQUIRE(srgb->linear(0).a == Approx(128.0f / 255.0f));
    REQUIRE(srgb->linear(1).r == Approx(0.5028865f).epsilon(1e-4));  // sRGB 188
    REQUIRE(srgb->linear(1).g == Approx(10.0f / 255.0f / 12.92f));   // the linear segment

    const auto data = facet::load_texture(file, false);
    REQUIRE(data->linear(0).g == Approx(128.0f / 255.0f));
}

TEST_CASE("bilinear filtering against hand-computed values", "[texture]") {
    TempDir dir("mesh");
    // 2x2, red = 0, 100 / 200, 255 (codes), linear data.
    const fs::path file = dir.write(
        "2x2.tga", tga(2, 2, {0, 0, 0, 255, 100, 0, 0, 255, 200, 0, 0, 255, 255, 0, 0, 255}));
    const facet::TextureBinding b{facet::load_texture(file, false), facet::Filter::bilinear,
                                  facet::Wrap::clamp};
    auto red = [&](float u, float v) { return facet::sample(b, {u, v}).r * 255.0f; };
    REQUIRE(red(0.25f, 0.25f) == Approx(0.0f).margin(1e-4));  // texel centres are exact
    REQUIRE(red(0.75f, 0.25f) == Approx(100.0f));
    REQUIRE(red(0.25f, 0.75f) == Approx(200.0f));
    REQUIRE(red(0.5f, 0.25f) == Approx(50.0f));   // halfway along row 0
    REQUIRE(red(0.5f, 0.5f) == Approx(138.75f));  // the mean of all four
    // x = 0.6 * 2 - 0.5 = 0.7, y = 0.4 * 2 - 0.5 = 0.3
    const float top = 0.3f * 0 + 0.7f * 100, bottom = 0.3f * 200 + 0.7f * 255;
    REQUIRE(red(0.6f, 0.4f) == Approx(0.7f * top + 0.3f * bottom));
}

TEST_CASE("nearest filtering and wrap modes", "[texture]") {
    TempDir dir("mesh");
    using facet::Filter;
    using facet::Wrap;
    const std::vector<uint8_t> codes = {0, 51, 102, 255};  // 0, 0.2, 0.4, 1
    const auto repeat = row_texture(dir, codes, Filter::nearest, Wrap::repeat);
    const auto clamp = row_texture(dir, codes, Filter::nearest, Wrap::clamp);
    const auto mirror = row_texture(dir, codes, Filter::nearest, Wrap::mirror);
    // u = -0.1 is texel -1; u = 1.1 is texel 4; u = 1.6 is texel 6.
    REQUIRE(red_at(repeat, -0.1f) == Approx(1.0f));
    REQUIRE(red_at(clamp, -0.1f) == Approx(0.0f));
    REQUIRE(red_at(mirror, -0.1f) == Approx(0.0f));
    REQUIRE(red_at(repeat, 1.1f) == Approx(0.0f));
    REQUIRE(red_at(clamp, 1.1f) == Approx(1.0f));
    REQUIRE(red_at(mirror, 1.1f) == Approx(1.0f));
    REQUIRE(red_at(repeat, 1.6f) == Approx(0.4f));
    REQUIRE(red_at(clamp, 1.6f) == Approx(1.0f));
    REQUIRE(red_at(mirror, 1.6f) == Approx(0.2f));
    REQUIRE(red_at(repeat, 0.3f) == Approx(0.2f));

    // Bilinear at u = 0 falls between texel -1 and texel 0.
    const auto b_repeat = row_texture(dir, codes, Filter::bilinear, Wrap::repeat);
    const auto b_clamp = row_texture(dir, codes, Filter::bilinear, Wrap::clamp);
    const auto b_mirror = row_texture(dir, codes, Filter::bilinear, Wrap::mirror);
    REQUIRE(red_at(b_repeat, 0.0f) == Approx(0.5f));
    REQUIRE(red_at(b_clamp, 0.0f) == Approx(0.0f));
    REQUIRE(red_at(b_mirror, 0.0f) == Approx(0.0f));
    REQUIRE(std::isfinite(red_at(b_repeat, std::nanf(""))));
    REQUIRE(std::isfinite(red_at(b_repeat, 1e30f)));
}

TEST_CASE("sample_many writes channel-major and matches sample", "[texture]") {
    TempDir dir("mesh");
    const auto b =
        row_texture(dir, {0, 51, 102, 255}, facet::Filter::bilinear, facet::Wrap::mirror);
    const float u[3] = {0.1f, 0.55f, 0.9f}, v[3] = {0.5f, 0.5f, 0.5f};
    float rgba[12];
    facet::sample_many(b, u, v, 3, rgba);
    for (int i = 0; i < 3; ++i) {
        const glm::vec4 one = facet::sample(b, {u[i], v[i]});
        for (int c = 0; c < 4; ++c) REQUIRE(rgba[c * 3 + i] == one[c]);
    }
}

TEST_CASE("the texture cache shares by file and colour space", "[texture]") {
    TempDir dir("mesh");
    dir.write("a.tga", tga(1, 1, {1, 2, 3, 4}));
    facet::TextureCache cache;
    const auto a = cache.get(dir.path / "a.tga", true);
    REQUIRE(cache.get(dir.path / "." / "a.tga", true) == a);
    REQUIRE(cache.get(dir.path / "a.tga", false) != a);
}

TEST_CASE("texture files that cannot be read are refused", "[texture]") {
    TempDir dir("mesh");
    try {
        facet::load_texture(dir.path / "missing.png", true);
        FAIL("no error");
    } catch (const facet::Error& e) {
        REQUIRE(e.code() == facet::ErrorCode::file_not_found);
    }
    try {
        facet::load_texture(dir.write("junk.png", "not an image"), true);
        FAIL("no error");
    } catch (const facet::Error& e) {
        REQUIRE(e.code() == facet::ErrorCode::texture_load_failed);
        REQUIRE_FALSE(e.detail().empty());
    }
}

TEST_CASE("mipmaps: generated by box filter, down to 1x1", "[texture][mipmap]") {
    Texture t;
    t.width = 5;
    t.height = 2;
    // Codes 20 i in a linear texture: the means are codes too.
    for (int i = 0; i < 10; ++i) t.texels.push_back({uint8_t(20 * i), 0, 0, 255});
    generate_mipmaps(t);
    REQUIRE(t.levels() == 3);  // 5x2, 2x1, 1x1
    CHECK((t.mips[0].width == 2 && t.mips[0].height == 1));
    CHECK(t.mips[0].texels[0].r == 20 * (0 + 1 + 5 + 6) / 4);
    CHECK(t.mips[0].texels[1].r == 20 * (2 + 3 + 7 + 8) / 4);
    CHECK(t.mips[1].texels[0].r == (60 + 100) / 2);
    CHECK(t.mips[1].texels[0].a == 255);
}

TEST_CASE("mipmaps of an sRGB texture average in linear light", "[texture][mipmap]") {
    // Black and white side by side: the mean is half the light, which sRGB
    // encodes as code 188, not 128.
    Texture t;
    t.width = 2;
    t.height = 1;
    t.srgb = true;
    t.texels = {{0, 0, 0, 0}, {255, 255, 255, 255}};
    generate_mipmaps(t);
    REQUIRE(t.levels() == 2);
    CHECK(t.mips[0].texels[0] == Texel8{188, 188, 188, 128});
    CHECK(decode_texel(t.mips[0].texels[0], true).r == Approx(0.5).margin(0.003));
}

TEST_CASE("trilinear filtering picks the analytic level of detail at a grazing angle",
          "[texture][mipmap]") {
    // A 256x256 texture whose level k holds the value k / 9 (code 28 k),
    // so what a pixel samples is the level of detail the sampler chose
    // (blended between levels). The reference is the analytic LOD, log2 of the longer axis of
    // the UV footprint from the exact Jacobian of the plane's UV mapping.
    auto tex = std::make_shared<Texture>();
    tex->width = tex->height = 256;
    tex->texels.assign(256 * 256, Texel8{});
    generate_mipmaps(*tex);
    for (int k = 1; k < tex->levels(); ++k)
        for (Texel8& t : tex->mips[size_t(k - 1)].texels) t = {uint8_t(28 * k), 0, 0, 255};
    const double per_level = 28.0 / 255.0;
    const TextureBinding binding{tex, Filter::trilinear, Wrap::repeat};

    // The plane y = 0, x in [-1, 1], z in [-40, 0], with uv = (x, -z / 2):
    // seen from just above, it recedes to a grazing angle.
    const int W = 128, H = 96;
    Mesh plane =
        make_mesh({{-1, 0, 0}, {1, 0, 0}, {1, 0, -40}, {-1, 0, -40}}, {0, 1, 2, 0, 2, 3});
    plane.uvs = {{-1, 0}, {1, 0}, {1, 20}, {-1, 20}};
    const glm::vec3 eye(0.0f, 0.25f, 1.0f);
    const glm::mat4 view = look_at(eye, {0.0f, 0.0f, -6.0f}, {0, 1, 0});
    const glm::mat4 proj = perspective(glm::radians(50.0f), float(W) / H, 0.05f, 100.0f, true);
    PluginRegistry registry;
    auto unlit = registry.get("unlit");
    const ParamBlock params =
        test::param_block(*unlit, {{"base_color", glm::vec4(1.0f)}, {"base_texture", glm::vec4(1.0f)}});
    Framebuffer fb(W, H);
    fb.clear(glm::vec4(-1.0f), 0.0f);
    DrawCall call = clip_space_call(plane, *unlit);
    call.view = view;
    call.projection = proj;
    call.params = params.bytes;
    call.textures = &binding;
    call.texture_count = 1;
    FrameStats stats;
    Pipeline().draw(call, fb, stats);

    // uv at window point p (pixels), from the ray through it.
    const glm::dmat4 inv = glm::inverse(glm::dmat4(proj) * glm::dmat4(view));
    auto uv_at = [&](glm::dvec2 p) {
        const glm::dvec2 ndc(p.x / W * 2 - 1, 1 - p.y / H * 2);
        const glm::dvec4 a = inv * glm::dvec4(ndc, 0.0, 1.0);
        const glm::dvec3 far = glm::dvec3(a) / a.w, o(eye);
        const glm::dvec3 hit = o + (far - o) * (o.y / (o.y - far.y));
        return glm::dvec2(hit.x, -hit.z / 2);
    };
    double max_err = 0, min_lod = 99, max_lod = 0;
    for (int qy = 0; qy < H; qy += 2)
        for (int qx = 0; qx < W; qx += 2) {
            const double got = fb.pixel(qx, qy).r / per_level;
            if (got < 0.0 || fb.pixel(qx + 1, qy + 1).r < 0.0f) continue;  // not on the plane
            const glm::dvec2 c(qx + 1.0, qy + 1.0);  // centre of the 2x2 quad
            const double h = 1e-3;
            const glm::dvec2 ex(h, 0), ey(0, h);
            const glm::dvec2 dx = (uv_at(c + ex) - uv_at(c - ex)) / (2 * h);
            const glm::dvec2 dy = (uv_at(c + ey) - uv_at(c - ey)) / (2 * h);
            const double lod = std::log2(256.0 * std::max(glm::length(dx), glm::length(dy)));
            if (lod < 0.05 || lod > tex->levels() - 1.05) continue;  // clamped at either end
            max_err = std::max(max_err, std::abs(got - lod));
            min_lod = std::min(min_lod, lod);
            max_lod = std::max(max_lod, lod);
        }
    INFO("LOD range " << min_lod << " .. " << max_lod);
    INFO("max LOD error " << max_err);
    CHECK(max_lod - min_lod > 3.0);  // the plane really spans several levels
    CHECK(max_err < 0.05);
}

TEST_CASE("JPEG textures load through stb_image, decoded from sRGB", "[texture]") {
    // A flat sRGB colour (188, 64, 32), written as a JPEG at full quality.
    const TempDir folder("jpeg");
    const std::filesystem::path& dir = folder.path;
    std::vector<unsigned char> pixels;
    for (int i = 0; i < 64; ++i) pixels.insert(pixels.end(), {188, 64, 32});
    REQUIRE(stbi_write_jpg((dir / "flat.jpg").c_str(), 8, 8, 3, pixels.data(), 100));
    const auto tex = load_texture(dir / "flat.jpg", true);
    REQUIRE((tex->width == 8 && tex->height == 8));
    const glm::vec4 texel = tex->linear(27);
    CHECK(texel.r == Approx(srgb_to_linear(188 / 255.0f)).margin(0.01));
    CHECK(texel.g == Approx(srgb_to_linear(64 / 255.0f)).margin(0.01));
    CHECK(texel.b == Approx(srgb_to_linear(32 / 255.0f)).margin(0.01));
    CHECK(tex->levels() == 4);  // 8x8 down to 1x1
}

TEST_CASE("every image layout in the decoder's seeds decodes to its pixels", "[texture]") {
    // fuzz/seeds/make_texture_seeds.py writes a 5x3 image in each layout,
    // after one flags byte; channel c of pixel (x, y) is the ramp below.
    // The lossless 8- and 16-bit RGB(A) ones must give it exactly (16 bits
    // keep their high byte), the others their size.
    const fs::path dir = fs::path(FACET_SOURCE_DIR) / "fuzz" / "seeds" / "texture_decode";
    int decoded = 0, exact = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        INFO(name);
        const std::string bytes = facet::test::read_file(entry.path());
        const auto texture = decode_texture(std::string_view(bytes).substr(1), false, name);
        REQUIRE((texture->width == 5 && texture->height == 3));
        ++decoded;
        const bool rgb = name == "png-rgb8.png" || name == "png-rgb8-interlaced.png" ||
                         name == "bmp-rgb24.bmp" || name == "pnm-rgb.ppm";
        const bool rgba = name == "png-rgba8.png" || name == "png-rgba16.png" ||
                          name == "tga-rgba.tga" || name == "tga-rgba-rle.tga";
        if (!rgb && !rgba) continue;
        ++exact;
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 5; ++x) {
                const Texel8 t = texture->texels[size_t(y * 5 + x)];
                const uint8_t got[4] = {t.r, t.g, t.b, t.a};
                for (int c = 0; c < (rgba ? 4 : 3); ++c)
                    CHECK(int(got[c]) == (x * 53 + y * 97 + c * 71) / 2 % 256);
            }
    }
    CHECK(decoded >= 15);
    CHECK(exact == 8);
}

TEST_CASE("damaged and cut-short PNGs are named as such", "[texture]") {
    const TempDir dir("png-check");
    std::vector<unsigned char> pixels(16 * 16 * 4);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = uint8_t(i * 7);
    REQUIRE(stbi_write_png((dir.path / "good.png").c_str(), 16, 16, 4, pixels.data(), 16 * 4));
    const std::string good = facet::test::read_file(dir.path / "good.png");
    CHECK(load_texture(dir.path / "good.png", true)->width == 16);
    const auto error_of = [&](const std::string& name, const std::string& bytes) {
        try {
            load_texture(dir.write(name, bytes), true);
        } catch (const Error& e) {
            CHECK(e.code() == ErrorCode::texture_load_failed);
            return std::string(e.what());
        }
        return std::string("loaded");
    };
    std::string damaged = good;
    damaged[good.find("IDAT") + 20] ^= 0x10;  // a bit of the image data
    CHECK_THAT(error_of("damaged.png", damaged),
               Contains("damaged.png: ") && Contains("chunk 'IDAT' at byte") &&
                   Contains("fails its CRC") && Contains("the file is damaged"));
    CHECK_THAT(error_of("cut.png", good.substr(0, good.find("IDAT") + 30)),
               Contains("chunk 'IDAT' at byte") && Contains("it is cut short"));
    CHECK_THAT(error_of("no-end.png", good.substr(0, good.size() - 12)),
               Contains("before its IEND chunk: it is cut short"));
}

TEST_CASE("a 16-bit PNM is refused, named, before the decoder reads past its buffer",
          "[texture][errors]") {
    // stb_image (libstb 2022-09-08) converts a 16-bit PNM's channels in a
    // buffer sized for 8 bits (tests/fuzz_regressions/texture_decode/).
    for (const std::string header :
         {"P6 2 2 65535\n", "P5\n# a comment\n2 2\n1000\n", "P5 1000000 1 65535\n"}) {
        INFO(header);
        const std::string bytes = header + std::string(24, '\x7f');
        try {
            decode_texture(bytes, false, "deep.ppm");
            FAIL("decoded");
        } catch (const Error& e) {
            CHECK(e.code() == ErrorCode::texture_load_failed);
            CHECK(e.file() == "deep.ppm");
            CHECK_THAT(e.what(), Catch::Contains("16 bits"));
        }
    }
    // 8 bits a sample still decode.
    const auto eight = decode_texture("P6 1 1 255\n\x10\x20\x30", false, "ok.ppm");
    CHECK(eight->texels[0] == Texel8{0x10, 0x20, 0x30, 255});
}

TEST_CASE("a JPEG Huffman table of more than 256 codes is refused, named", "[texture][errors]") {
    // stb_image writes a table's code lengths past its 257 entries
    // (tests/fuzz_regressions/texture_decode/, found once facet's own copy
    // of stb_image ran under the sanitizers).
    const std::string file = facet::test::read_file(
        fs::path(FACET_SOURCE_DIR) / "tests" / "fuzz_regressions" / "texture_decode" /
        "jpeg-huffman-table-over-256-codes.jpg");
    try {
        decode_texture(std::string_view(file).substr(1), false, "huff.jpg");  // past the flags byte
        FAIL("decoded");
    } catch (const Error& e) {
        CHECK(e.code() == ErrorCode::texture_load_failed);
        CHECK(e.file() == "huff.jpg");
        CHECK_THAT(e.what(), Catch::Contains("Huffman table"));
    }
    // The JPEG seeds (real files, their tables within bounds) still decode.
    const fs::path seeds = fs::path(FACET_SOURCE_DIR) / "fuzz" / "seeds" / "texture_decode";
    int jpegs = 0;
    for (const auto& entry : fs::directory_iterator(seeds))
        if (entry.path().filename().string().starts_with("jpeg")) {
            const std::string bytes = facet::test::read_file(entry.path());
            CHECK(decode_texture(std::string_view(bytes).substr(1), true, "seed")->width == 5);
            ++jpegs;
        }
    CHECK(jpegs >= 2);
}

namespace {
// A JPEG without its nth segment of a marker (its first byte, the fuzz
// seed's flags byte, dropped).
std::string jpeg_without(const std::string& seed, unsigned char marker, int nth) {
    std::string bytes = facet::test::read_file(fs::path(FACET_SOURCE_DIR) / "fuzz" / "seeds" /
                                               "texture_decode" / seed)
                            .substr(1);
    for (size_t at = 2; at + 4 <= bytes.size();) {
        const auto u = [&](size_t i) { return static_cast<unsigned char>(bytes[i]); };
        if (u(at) != 0xFF || u(at + 1) == 0 || u(at + 1) == 0xFF || (u(at + 1) & 0xF8) == 0xD0) {
            ++at;
            continue;
        }
        const size_t length = 2 + ((size_t(u(at + 2)) << 8) | u(at + 3));
        if (u(at + 1) == marker && nth-- == 0) return bytes.erase(at, length);
        at += length;
    }
    FAIL("no such segment");
    return {};
}
}  // namespace

TEST_CASE("a JPEG scan that uses a table never defined, or a component none codes, is refused",
          "[texture][errors]") {
    // stb_image allocates its tables without clearing them: a scan that
    // uses an undefined Huffman table read it at index -16,776,874
    // (tests/fuzz_regressions/texture_decode/, from `scripts/fuzz 60`).
    struct Case {
        const char* seed;
        unsigned char marker;
        int nth;
        const char* says;
    };
    for (const Case& c : {Case{"jpeg-progressive.jpg", 0xC4, 2, "AC Huffman table 0, which is not defined"},
                          Case{"jpeg-progressive.jpg", 0xC4, 0, "DC Huffman table 0, which is not defined"},
                          Case{"jpeg-baseline.jpg", 0xC4, 3, "AC Huffman table 1, which is not defined"},
                          Case{"jpeg-baseline.jpg", 0xDB, 1, "quantization table 1"},
                          Case{"jpeg-progressive.jpg", 0xDA, 0, "component 1 that no scan codes"},
                          Case{"jpeg-baseline.jpg", 0xDA, 0, "component 1 that no scan codes"}}) {
        INFO(c.seed << " without segment " << c.nth << " of marker " << int(c.marker));
        try {
            decode_texture(jpeg_without(c.seed, c.marker, c.nth), false, "tables.jpg");
            FAIL("decoded");
        } catch (const Error& e) {
            CHECK(e.code() == ErrorCode::texture_load_failed);
            CHECK(e.file() == "tables.jpg");
            CHECK_THAT(e.what(), Catch::Contains(c.says));
        }
    }
    // A frame whose second component takes the first's id: stb_image would
    // code the first twice and leave the second unwritten.
    std::string twin = jpeg_without("jpeg-baseline.jpg", 0xE0, 0);
    const size_t sof = twin.find("\xFF\xC0");
    REQUIRE(sof != std::string::npos);
    twin[sof + 4 + 6 + 3] = twin[sof + 4 + 6];  // component 2's id := component 1's
    try {
        decode_texture(twin, false, "twin.jpg");
        FAIL("decoded");
    } catch (const Error& e) {
        CHECK_THAT(e.what(), Catch::Contains("two components of id"));
    }
    // The control: without a segment no scan needs (JFIF's APP0), the
    // progressive seed, whose AC tables come between its scans, decodes.
    CHECK(decode_texture(jpeg_without("jpeg-progressive.jpg", 0xE0, 0), false, "ok.jpg")->width == 5);
}
