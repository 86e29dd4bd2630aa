// Cube maps from files (facet/texture.hpp, load_cube): six faces, or one
// equirectangular image, each direction read from the face and the place
// the definitions give; and cube map parameters in material files.
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/material.hpp>
#include <facet/plugin.hpp>
#include <facet/texture.hpp>

#include <catch2/catch.hpp>

#include <stb/stb_image_write.h>

#include <cmath>
#include <string>
#include <vector>

using namespace facet;
using facet::test::TempDir;

namespace {

// A w x h PNG whose every texel is colour(x, y), in the folder.
template <class Colour>
std::filesystem::path png(const TempDir& dir, const std::string& name, int w, int h,
                          Colour colour) {
    std::vector<uint8_t> rgba;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::ivec3 c = colour(x, y);
            rgba.insert(rgba.end(), {uint8_t(c.r), uint8_t(c.g), uint8_t(c.b), 255});
        }
    const std::filesystem::path file = dir.path / name;
    REQUIRE(stbi_write_png(file.string().c_str(), w, h, 4, rgba.data(), w * 4));
    return file;
}

const glm::ivec3 kFaceColour[6] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255},
                                   {255, 255, 0}, {0, 255, 255}, {255, 0, 255}};

std::vector<std::filesystem::path> six_faces(const TempDir& dir, int n) {
    std::vector<std::filesystem::path> faces;
    for (int f = 0; f < 6; ++f)
        faces.push_back(png(dir, "face" + std::to_string(f) + ".png", n, n,
                            [&](int, int) { return kFaceColour[f]; }));
    return faces;
}

glm::ivec3 codes(const glm::vec4& linear) {
    return {int(std::lround(linear.r * 255)), int(std::lround(linear.g * 255)),
            int(std::lround(linear.b * 255))};
}

}  // namespace

TEST_CASE("a cube map from six faces reads each direction from its face", "[texture][cube]") {
    const TempDir dir("cube");
    const auto cube = load_cube(six_faces(dir, 8), false);
    REQUIRE(cube->faces == 6);
    CHECK(cube->levels() == 4);
    const TextureBinding b{cube, Filter::trilinear, Wrap::repeat};
    const glm::vec3 towards[6] = {{1, 0.2f, 0.1f}, {-1, 0.1f, -0.3f}, {0.2f, 1, 0.1f},
                                  {0.1f, -1, 0.2f}, {0.3f, 0.1f, 1},  {-0.2f, 0.1f, -1}};
    for (int f = 0; f < 6; ++f)
        for (const float lod : {0.0f, 2.5f, 9.0f}) {
            INFO("face " << f << ", level of detail " << lod);
            CHECK(codes(sample_cube(b, towards[f], lod)) == kFaceColour[f]);
        }
}

TEST_CASE("a cube map from an equirectangular image: longitude across, latitude down",
          "[texture][cube]") {
    // Four quarters of longitude in four colours, white near the top (+Y)
    // and black near the bottom (-Y).
    const TempDir dir("equirect");
    const glm::ivec3 quarter[4] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 0}};
    const auto file = png(dir, "sky.png", 64, 32, [&](int x, int y) {
        if (y < 4) return glm::ivec3(255);
        if (y >= 28) return glm::ivec3(0);
        return quarter[x / 16];
    });
    const auto cube = load_cube({file}, false);
    CHECK(cube->width == 16);  // half the image's height
    const TextureBinding b{cube, Filter::bilinear, Wrap::repeat};
    CHECK(codes(sample_cube(b, {0, 1, 0}, 0)) == glm::ivec3(255));
    CHECK(codes(sample_cube(b, {0, -1, 0}, 0)) == glm::ivec3(0));
    // The middle of each quarter: longitude -135, -45, 45 and 135 degrees,
    // 0 being -Z, 90 +X.
    const float s = std::sqrt(0.5f);
    CHECK(codes(sample_cube(b, {-s, 0, s}, 0)) == quarter[0]);
    CHECK(codes(sample_cube(b, {-s, 0, -s}, 0)) == quarter[1]);
    CHECK(codes(sample_cube(b, {s, 0, -s}, 0)) == quarter[2]);
    CHECK(codes(sample_cube(b, {s, 0, s}, 0)) == quarter[3]);
}

TEST_CASE("cube maps refuse faces that are not square or not one size", "[texture][cube]") {
    const TempDir dir("cube_bad");
    std::vector<std::filesystem::path> faces = six_faces(dir, 8);
    faces[3] = png(dir, "odd.png", 8, 4, [](int, int) { return glm::ivec3(9); });
    CHECK_THROWS_MATCHES(load_cube(faces, true), Error,
                         Catch::Predicate<Error>([](const Error& e) {
                             return e.code() == ErrorCode::texture_load_failed &&
                                    e.file().find("odd.png") != std::string::npos;
                         }));
    faces[3] = png(dir, "big.png", 16, 16, [](int, int) { return glm::ivec3(9); });
    CHECK_THROWS_AS(load_cube(faces, true), Error);
    faces.pop_back();
    CHECK_THROWS_AS(load_cube(faces, true), Error);  // five files
}

TEST_CASE("a material gives a cube map parameter six faces or one file, and a 2D one no faces",
          "[texture][cube][material]") {
    const TempDir dir("cube_material");
    six_faces(dir, 8);
    png(dir, "sky.png", 16, 8, [](int x, int) { return glm::ivec3(x * 16, 0, 0); });
    PluginRegistry registry;
    TextureCache cache;
    const auto load = [&](const std::string& yaml) {
        return load_material(dir.write("m.yaml", yaml), registry, cache);
    };
    const auto faces = load(
        "shader: mirror\nparams:\n  environment: {faces: [face0.png, face1.png, face2.png, "
        "face3.png, face4.png, face5.png]}\n");
    REQUIRE(faces->textures.size() == 1);
    CHECK(faces->textures[0].texture->faces == 6);
    CHECK(load("shader: mirror\nparams:\n  environment: sky.png\n")->textures[0].texture->faces ==
          6);
    const auto error_of = [&](const std::string& yaml) {
        try {
            load(yaml);
        } catch (const Error& e) {
            return std::make_pair(e.code(), e.line());
        }
        return std::make_pair(ErrorCode::interrupted, 0);  // no error
    };
    CHECK(error_of("shader: mirror\nparams:\n  environment: {faces: [face0.png]}\n") ==
          std::make_pair(ErrorCode::wrong_type, 3));
    CHECK(error_of("shader: unlit\nparams:\n  base_texture: {faces: [face0.png, face1.png, "
                   "face2.png, face3.png, face4.png, face5.png]}\n") ==
          std::make_pair(ErrorCode::param_type, 3));
}
