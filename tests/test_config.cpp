// Materials and scenes from YAML: every error names its id, file, line and
// column; good files load into the values they say.
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/material.hpp>
#include <facet/plugin.hpp>
#include <facet/scene.hpp>
#include <facet/shader.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using facet::ErrorCode;

namespace {

using namespace facet::sdk;

// A shader compiled into the test, to validate materials against.
struct TestShader {
    static constexpr const char* name = "test";
    static constexpr const char* version = "1";
    static constexpr uint32_t needs = FACET_NEED_UVS | FACET_NEED_TEXTURES;
    FACET_VARYINGS((Vec2, uv))
    FACET_PARAMS((color4, tint, {1, 0.5f, 0.25f, 1}),
                 (float1, gloss, 0.5f, 0.0f, 1.0f),
                 (int1, steps, 4, 1, 16),
                 (boolean, mirror, true),
                 (texture, albedo, "uv", srgb))

    static Varyings vertex(const VertexIn& in, const Draw& d, const Params&, Vec4& clip) {
        clip = d.model_view_projection() * Vec4(in.position, 1.0f);
        return {in.uv};
    }
    static Vec4 fragment(const Varyings&, Fragment& f, const Draw&, const Params& p) {
        return p.tint * f.texture(p.albedo);
    }
};

// A temp folder with a registry that knows the test shader, and files in it.
struct Env {
    facet::test::TempDir folder{"config"};
    const fs::path& dir = folder.path;
    facet::PluginRegistry registry{std::vector<fs::path>{}};
    facet::TextureCache cache;

    Env() {
        registry.add(
            facet::ShaderPlugin::from_descriptor(facet::sdk::describe<TestShader>(), "test"));
        write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
        // A 1x1 TGA: header, then one BGRA texel.
        write("px.tga",
              std::string("\0\0\2\0\0\0\0\0\0\0\0\0\1\0\1\0\x20\x28", 18) + "\x10\x20\x30\xff");
    }
    fs::path write(const std::string& name, const std::string& text) const {
        return folder.write(name, text);
    }
    std::shared_ptr<facet::Material> material(const std::string& yaml) {
        return facet::load_material(write("m.yaml", yaml), registry, cache);
    }
    facet::Scene scene(const std::string& yaml) {
        return facet::load_scene(write("scene.yaml", yaml), registry);
    }
};

// The Error `run` throws; fails the test if it throws none.
facet::Error error_of(const std::function<void()>& run) {
    try {
        run();
    } catch (const facet::Error& e) {
        return e;
    }
    throw std::runtime_error("expected a facet::Error, got none");
}

void require_at(const facet::Error& e, ErrorCode code, const fs::path& file, int line, int column) {
    INFO(e.what());
    REQUIRE(facet::error_name(e.code()) == facet::error_name(code));
    REQUIRE(e.file() == file.string());
    REQUIRE(e.line() == line);
    REQUIRE(e.column() == column);
}

TestShader::Params params_of(const facet::Material& m) {
    TestShader::Params p;
    std::memcpy(&p, m.block->bytes, sizeof p);
    return p;
}

const char* kObject = "objects:\n  - {mesh: tri.obj, material: {shader: test}}\n";

}  // namespace

// ---- YAML errors -------------------------------------------------------------------

TEST_CASE("malformed YAML names file, line and column", "[config]") {
    Env env;
    const auto e =
        error_of([&] { env.material("shader: test\nparams:\n  gloss: [0.5\nblend: alpha\n"); });
    REQUIRE(e.code() == ErrorCode::yaml_syntax);
    REQUIRE(e.file() == (env.dir / "m.yaml").string());
    REQUIRE(e.line() == 4);  // where yaml-cpp sees the unclosed sequence end
    REQUIRE(e.column() > 0);
}

TEST_CASE("render settings given as text replace only the keys they name", "[config]") {
    facet::RenderSettings s;
    s.msaa = 2;
    s.shadow_map_size = 1024;
    facet::apply_render_settings(s, "{shadows: false, ao_resolution: half, depth: standard}", "--render");
    CHECK_FALSE(s.shadows);
    CHECK(s.ao_half_resolution);
    CHECK_FALSE(s.reversed_z);
    CHECK(s.depth_compare == facet::DepthCompare::less_equal);  // follows the depth range
    CHECK(s.msaa == 2);                                   // not named: kept
    CHECK(s.shadow_map_size == 1024);
    const facet::RenderSettings before = s;
    const auto e = error_of([&] { facet::apply_render_settings(s, "{msaa: 3}", "--render"); });
    CHECK(e.code() == ErrorCode::out_of_range);
    CHECK(e.file() == "--render");
    CHECK(e.column() > 0);
    CHECK(error_of([&] { facet::apply_render_settings(s, "{shadow: false}", "--render"); }).code() ==
          ErrorCode::unknown_key);
    CHECK(error_of([&] { facet::apply_render_settings(s, "{msaa: [", "--render"); }).code() ==
          ErrorCode::yaml_syntax);
    CHECK(s.msaa == before.msaa);  // a bad map changes nothing
    CHECK(s.shadows == before.shadows);
}

TEST_CASE("unknown keys are errors at the key, listing the keys expected", "[config]") {
    Env env;
    const auto e = error_of([&] { env.material("shader: test\nblennd: alpha\n"); });
    require_at(e, ErrorCode::unknown_key, env.dir / "m.yaml", 2, 1);
    REQUIRE_THAT(e.what(), Contains("'blennd'") && Contains("shader, blend, cull"));

    const auto s = error_of([&] { env.scene("camera:\n  position: [0, 0, 3]\n  fovy: 40\n"); });
    require_at(s, ErrorCode::unknown_key, env.dir / "scene.yaml", 3, 3);
}

TEST_CASE("missing keys and wrong shapes are errors at the right place", "[config]") {
    Env env;
    require_at(error_of([&] { env.material("blend: alpha\n"); }), ErrorCode::missing_key,
               env.dir / "m.yaml", 1, 1);
    require_at(error_of([&] { env.material("shader: test\ndepth_write: maybe\n"); }),
               ErrorCode::wrong_type, env.dir / "m.yaml", 2, 14);
    require_at(error_of([&] { env.material("shader: test\nblend: glass\n"); }),
               ErrorCode::config_invalid, env.dir / "m.yaml", 2, 8);
    require_at(error_of([&] { env.material("shader: test\nparams:\n  gloss:\n"); }),
               ErrorCode::wrong_type, env.dir / "m.yaml", 3, 3);
    require_at(error_of([&] { env.scene("camera: {position: [0, 1]}\n"); }), ErrorCode::wrong_type,
               env.dir / "scene.yaml", 1, 20);
}

TEST_CASE("a missing scene file is reported as such", "[config]") {
    Env env;
    facet::PluginRegistry registry;
    const auto e = error_of([&] { facet::load_scene(env.dir / "nope.yaml", registry); });
    REQUIRE(e.code() == ErrorCode::file_not_found);
    REQUIRE(e.file() == (env.dir / "nope.yaml").string());
}

// ---- materials -----------------------------------------------------------------------

TEST_CASE("a material binds defaults, values and textures", "[material]") {
    Env env;
    const auto m = env.material(
        "shader: test\nblend: alpha\ncull: none\nparams:\n"
        "  tint: [0.1, 0.2, 0.3]\n  steps: 8\n  mirror: false\n"
        "  albedo: {file: px.tga, filter: nearest, wrap: clamp}\n");
    REQUIRE(m->blend == facet::BlendMode::alpha);
    REQUIRE(m->cull == facet::CullMode::none);
    REQUIRE_FALSE(m->writes_depth());
    const TestShader::Params p = params_of(*m);
    REQUIRE(p.tint == glm::vec4(0.1f, 0.2f, 0.3f, 1.0f));  // a color4 given 3 numbers is opaque
    REQUIRE(p.gloss == 0.5f);                              // the schema's default
    REQUIRE(p.steps == 8);
    REQUIRE(p.mirror == 0);
    REQUIRE(p.albedo.bound == 1);
    REQUIRE(m->textures.size() == 1);
    REQUIRE(m->textures[0].texture->srgb);  // the schema marks albedo as sRGB
    REQUIRE(m->textures[0].filter == facet::Filter::nearest);
    REQUIRE(m->textures[0].wrap == facet::Wrap::clamp);
    REQUIRE(m->textures[0].texture->source == (env.dir / "px.tga").string());
}

TEST_CASE("a texture's transform places it on its UVs, and bad ones are refused", "[material]") {
    Env env;
    const auto m = env.material(
        "shader: test\nparams:\n"
        "  albedo: {file: px.tga, transform: {offset: [0.5, -1], rotation: 0.25, scale: [2, 3]}}\n");
    const facet::UvTransform& t = m->textures.at(0).transform;
    REQUIRE(t.offset == glm::vec2(0.5f, -1.0f));
    REQUIRE(t.rotation == 0.25f);
    REQUIRE(t.scale == glm::vec2(2.0f, 3.0f));
    // Each part is optional.
    REQUIRE(env.material("shader: test\nparams:\n  albedo: {file: px.tga, transform: {rotation: 1}}\n")
                ->textures.at(0).transform.scale == glm::vec2(1.0f));
    struct Bad {
        const char* transform;
        int column;
        const char* says;
    };
    for (const Bad& b : {Bad{"{offset: [1e7, 0]}", 47, "offset 1e7 is past 1e6"},
                         Bad{"{scale: [1, 2, 3]}", 45, "2 numbers"},
                         Bad{"{rotation: -2e6}", 48, "rotation -2e6 is past 1e6"},
                         Bad{"{shear: 1}", 38, "'shear'"}}) {
        INFO(b.transform);
        const auto e = error_of([&] {
            env.material(std::string("shader: test\nparams:\n  albedo: {file: px.tga, transform: ") +
                         b.transform + "}\n");
        });
        REQUIRE(e.line() == 3);
        CHECK(e.column() == b.column);
        CHECK_THAT(e.what(), Contains(b.says));
    }
}

TEST_CASE("a cube map takes no transform and no UV set, whether faces or one file", "[material]") {
    Env env;
    facet::PluginRegistry shipped;  // the built shaders: mirror's environment is a cube map
    const std::pair<const char*, const char*> cases[] = {
        {"{file: sky.hdr, transform: {scale: [2, 2]}}", "'environment' is a cube map, read by direction"},
        {"{file: sky.hdr, uv_set: 1}", "'environment' reads the second set of texture coordinates"}};
    for (const auto& [value, says] : cases) {
        INFO(value);
        const auto e = error_of([&] {
            facet::load_material(
                env.write("m.yaml", std::string("shader: mirror\nparams:\n  environment: ") + value + "\n"),
                shipped, env.cache);
        });
        CHECK(e.line() == 3);
        CHECK_THAT(e.what(), Contains(says));
    }
}

TEST_CASE("a texture's UV set is 0 or 1, and 1 only where the shader has a second", "[material]") {
    Env env;
    REQUIRE(env.material("shader: test\nparams:\n  albedo: {file: px.tga, uv_set: 0}\n")
                ->textures.at(0).uv_set == 0);
    auto e = error_of([&] { env.material("shader: test\nparams:\n  albedo: {file: px.tga, uv_set: 1}\n"); });
    require_at(e, ErrorCode::config_invalid, env.dir / "m.yaml", 3, 11);
    CHECK_THAT(e.what(), Contains("'albedo' reads the second set of texture coordinates") &&
                             Contains("shader 'test' has no second set"));
    e = error_of([&] { env.material("shader: test\nparams:\n  albedo: {file: px.tga, uv_set: 2}\n"); });
    CHECK(e.code() == ErrorCode::out_of_range);
    CHECK_THAT(e.what(), Contains("uv_set is 0"));
}

TEST_CASE("anisotropic filtering takes its most samples, 2 to 16, and only with that filter",
          "[material][anisotropic]") {
    Env env;
    const auto m = env.material(
        "shader: test\nparams:\n  albedo: {file: px.tga, filter: anisotropic, anisotropy: 8}\n");
    CHECK(m->textures.at(0).filter == facet::Filter::anisotropic);
    CHECK(m->textures.at(0).anisotropy == 8);
    CHECK(env.material("shader: test\nparams:\n  albedo: {file: px.tga, filter: anisotropic}\n")
              ->textures.at(0).anisotropy == 16);  // GL's and D3D's most
    auto e = error_of([&] {
        env.material("shader: test\nparams:\n  albedo: {file: px.tga, anisotropy: 4}\n");
    });
    require_at(e, ErrorCode::config_invalid, env.dir / "m.yaml", 3, 38);
    CHECK_THAT(e.what(), Contains("filter: anisotropic"));
    for (const char* most : {"1", "17", "-3"}) {
        e = error_of([&] {
            env.material(std::string("shader: test\nparams:\n  albedo: {file: px.tga, filter: "
                                     "anisotropic, anisotropy: ") + most + "}\n");
        });
        CHECK(e.code() == ErrorCode::out_of_range);
        CHECK_THAT(e.what(), Contains("2 to 16"));
    }
}

TEST_CASE("a material without params gets the schema defaults", "[material]") {
    Env env;
    const auto m = env.material("shader: test\n");
    const TestShader::Params p = params_of(*m);
    REQUIRE(p.tint == glm::vec4(1, 0.5f, 0.25f, 1));
    REQUIRE(p.steps == 4);
    REQUIRE(p.mirror == 1);
    REQUIRE(p.albedo.bound == 0);
    REQUIRE(m->textures.size() == 1);
    REQUIRE_FALSE(m->textures[0].texture);
}

TEST_CASE("unknown parameters list what the shader expects", "[material]") {
    Env env;
    const auto e = error_of([&] { env.material("shader: test\nparams:\n  shinyness: 3\n"); });
    require_at(e, ErrorCode::param_unknown, env.dir / "m.yaml", 3, 14);
    REQUIRE_THAT(e.what(), Contains("'shinyness'") && Contains("shader 'test'") &&
                               Contains("tint (color4), gloss (float), steps (int)"));
}

TEST_CASE("parameters of the wrong type are errors at the value", "[material]") {
    Env env;
    const fs::path file = env.dir / "m.yaml";
    auto code_at = [&](const std::string& param, int column) {
        require_at(error_of([&] { env.material("shader: test\nparams:\n  " + param + "\n"); }),
                   ErrorCode::param_type, file, 3, column);
    };
    code_at("gloss: [0.5, 0.5]", 10);
    code_at("steps: 2.5", 10);
    code_at("mirror: 1", 11);
    code_at("tint: [1, 1]", 9);
    code_at("tint: true", 9);
    code_at("albedo: 3", 11);
    code_at("gloss: px.tga", 10);
}

TEST_CASE("parameters out of range are errors at the value", "[material]") {
    Env env;
    const fs::path file = env.dir / "m.yaml";
    auto range_at = [&](const std::string& param, int column) {
        const auto e = error_of([&] { env.material("shader: test\nparams:\n  " + param + "\n"); });
        require_at(e, ErrorCode::param_range, file, 3, column);
        return std::string(e.what());
    };
    REQUIRE_THAT(range_at("gloss: 1.5", 10), Contains("1.5"));
    range_at("steps: 0", 10);
    REQUIRE_THAT(range_at("tint: [1, -0.5, 0]", 9), Contains("component 1"));
}

TEST_CASE("an unknown shader is reported at the shader value", "[material]") {
    Env env;
    const auto e = error_of([&] { env.material("blend: opaque\nshader: phong\n"); });
    require_at(e, ErrorCode::unknown_shader, env.dir / "m.yaml", 2, 9);
    REQUIRE_THAT(e.what(), Contains("phong.so"));
}

TEST_CASE("a missing texture is reported at the parameter", "[material]") {
    Env env;
    const auto e = error_of([&] { env.material("shader: test\nparams:\n  albedo: nope.png\n"); });
    require_at(e, ErrorCode::file_not_found, env.dir / "m.yaml", 3, 11);
    REQUIRE_THAT(e.what(), Contains("nope.png"));
}

TEST_CASE("bind leaves the material unchanged when it throws", "[material]") {
    Env env;
    const auto m = env.material("shader: test\nparams:\n  gloss: 0.25\n");
    const auto block = m->block;
    facet::Material copy = *m;
    copy.params.push_back(copy.params[0]);
    copy.params.back().numbers = {7.0};
    REQUIRE_THROWS_AS(facet::bind(copy, m->plugin, env.cache), facet::Error);
    REQUIRE(copy.block == block);
    REQUIRE(params_of(copy).gloss == 0.25f);
}

// ---- scenes ----------------------------------------------------------------------------

TEST_CASE("a scene loads camera, settings, lights and objects", "[scene]") {
    Env env;
    env.write("materials/shared.yaml", "shader: test\nparams:\n  albedo: ../px.tga\n");
    const facet::Scene s = env.scene(R"(
camera: {position: [0, 1, 4], target: [0, 1, 0], projection: orthographic, height: 3, near: 0.5, far: 50}
render: {size: [320, 200], clear_color: [0.1, 0.2, 0.3], depth: standard, cull: front, front_face: cw,
         msaa: 8, subpixel_bits: 4, wireframe: true, shadows: false, ao: false}
lights:
  - {type: spot, position: [0, 3, 0], direction: [0, -2, 0], spot_inner: 10, spot_outer: 15, casts_shadow: true}
objects:
  - {name: a, mesh: tri.obj, material: materials/shared.yaml, position: [1, 2, 3], scale: 2}
  - {name: b, mesh: ./tri.obj, material: materials/shared.yaml, rotation: {axis: [0, 1, 0], angle: 90}, visible: false}
  - {mesh: tri.obj, material: {shader: test, params: {gloss: 0.75}}, rotation: [0, 90, 0], scale: [1, 2, 3]}
)");
    REQUIRE(s.camera.orthographic);
    REQUIRE(s.camera.ortho_height == 3.0f);
    REQUIRE(s.settings.width == 320);
    REQUIRE(s.settings.clear_color == glm::vec4(0.1f, 0.2f, 0.3f, 1.0f));
    REQUIRE_FALSE(s.settings.reversed_z);
    REQUIRE(s.settings.depth_compare == facet::DepthCompare::less_equal);
    REQUIRE(s.settings.cull == facet::CullMode::front);
    REQUIRE_FALSE(s.settings.front_ccw);
    REQUIRE(s.settings.msaa == 8);
    REQUIRE(s.settings.subpixel_bits == 4);
    REQUIRE(s.settings.wireframe);
    REQUIRE_FALSE(s.settings.shadows);
    REQUIRE_FALSE(s.settings.ao);
    REQUIRE(s.lights.size() == 1);
    REQUIRE(s.lights[0].type == facet::LightType::spot);
    REQUIRE(s.lights[0].direction == glm::vec3(0, -1, 0));
    REQUIRE(s.lights[0].casts_shadow);
    REQUIRE(s.objects.size() == 3);
    REQUIRE(s.objects[0].mesh == s.objects[1].mesh);  // one load per file
    REQUIRE(s.objects[0].material == s.objects[1].material);
    REQUIRE(s.objects[0].transform.scale == glm::vec3(2.0f));
    REQUIRE(s.objects[0].transform.translation == glm::vec3(1, 2, 3));
    REQUIRE_FALSE(s.objects[1].visible);
    const glm::quat q1 = s.objects[1].transform.rotation, q2 = s.objects[2].transform.rotation;
    REQUIRE(std::abs(glm::dot(q1, q2)) == Approx(1.0f));  // the two spellings agree
    REQUIRE(s.objects[2].name == "object 2");
}

TEST_CASE("an inline material is labelled by scene and line", "[scene]") {
    Env env;
    const facet::Scene s = env.scene(std::string("# comment\n") + kObject);
    const facet::Material& m = *s.objects[0].material;
    REQUIRE(m.source == (env.dir / "scene.yaml").string() + ":3");
    REQUIRE(params_of(m).gloss == 0.5f);

    const auto e = error_of([&] {
        env.scene(
            "objects:\n  - mesh: tri.obj\n    material:\n      shader: test\n"
            "      params: {gloss: -1}\n");
    });
    require_at(e, ErrorCode::param_range, env.dir / "scene.yaml", 5, 23);
}

TEST_CASE("mesh and material errors are reported where the scene names them", "[scene]") {
    Env env;
    env.write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    const auto mesh =
        error_of([&] { env.scene("objects:\n  - {mesh: bad.obj, material: {shader: test}}\n"); });
    require_at(mesh, ErrorCode::mesh_load_failed, env.dir / "scene.yaml", 2, 12);
    REQUIRE_THAT(mesh.what(), Contains((env.dir / "bad.obj").string() + ": OBJ: vertex index"));

    const auto missing =
        error_of([&] { env.scene("objects:\n  - {mesh: gone.obj, material: {shader: test}}\n"); });
    require_at(missing, ErrorCode::file_not_found, env.dir / "scene.yaml", 2, 12);

    env.write("bad.yaml", "shader: test\nparams:\n  gloss: yes please\n");
    const auto material =
        error_of([&] { env.scene("objects:\n  - {mesh: tri.obj, material: bad.yaml}\n"); });
    require_at(material, ErrorCode::param_type, env.dir / "scene.yaml", 2, 31);
    REQUIRE_THAT(material.what(), Contains((env.dir / "bad.yaml").string() + ":3:10"));
}

TEST_CASE("scene values are checked for sense", "[scene]") {
    Env env;
    const fs::path file = env.dir / "scene.yaml";
    auto check = [&](const std::string& yaml, ErrorCode code, int line, int column) {
        require_at(error_of([&] { env.scene(yaml); }), code, file, line, column);
    };
    check("camera: {near: 0}\n", ErrorCode::out_of_range, 1, 16);
    check("camera: {near: 2, far: 1}\n", ErrorCode::out_of_range, 1, 24);
    check("camera: {fov_y: 180}\n", ErrorCode::out_of_range, 1, 17);
    check("camera: {position: [0, 0, 0], target: [0, 0, 0]}\n", ErrorCode::config_invalid, 1, 39);
    check("render: {size: [0, 100]}\n", ErrorCode::out_of_range, 1, 17);
    check("render: {size: [100, 40000]}\n", ErrorCode::out_of_range, 1, 22);
    check("render: {depth_compare: lesser}\n", ErrorCode::config_invalid, 1, 25);
    check("render: {msaa: 3}\n", ErrorCode::out_of_range, 1, 16);
    check("render: {subpixel_bits: 9}\n", ErrorCode::out_of_range, 1, 25);
    check("render: {subpixel_bits: 0}\n", ErrorCode::out_of_range, 1, 25);
    check("render: {wireframe: maybe}\n", ErrorCode::wrong_type, 1, 21);
    check("render: {ao_radius: 0}\n", ErrorCode::out_of_range, 1, 21);
    check("render: {ao_radius: -1}\n", ErrorCode::out_of_range, 1, 21);
    check("render: {ao_samples: 257}\n", ErrorCode::out_of_range, 1, 22);
    check("lights:\n  - {direction: [0, 0, 0]}\n", ErrorCode::config_invalid, 2, 17);
    check("lights:\n  - {type: spot, spot_inner: 40, spot_outer: 30}\n", ErrorCode::out_of_range, 2,
          30);
    // (A mesh with no material anywhere is drawn grey, with a warning:
    // test_models.cpp.)
    check("objects:\n  - {mesh: tri.obj, material: {shader: test}, scale: 0}\n",
          ErrorCode::out_of_range, 2, 54);
    // Subnormal: it flattens every triangle to nothing.
    check("objects:\n  - {mesh: tri.obj, material: {shader: test}, scale: 1e-45}\n",
          ErrorCode::out_of_range, 2, 54);
    // Beyond float: at the component.
    check("objects:\n  - {mesh: tri.obj, material: {shader: test}, scale: [1, 1e300, 1]}\n",
          ErrorCode::out_of_range, 2, 58);
    check("camera: {position: [0, 0, 1e39]}\n", ErrorCode::out_of_range, 1, 27);
    // Within float, but past what a transform or the lighting keeps finite.
    check("camera: {far: 1e16}\n", ErrorCode::out_of_range, 1, 15);
    check("camera: {fov_y: 1e-4}\n", ErrorCode::out_of_range, 1, 17);
    check("render: {clear_color: [0, 0, 0, 2]}\n", ErrorCode::out_of_range, 1, 23);
    check("lights:\n  - {intensity: 1e10}\n", ErrorCode::out_of_range, 2, 17);
    check("lights:\n  - {attenuation: [1e-9, 0, 0]}\n", ErrorCode::out_of_range, 2, 19);
    check("lights:\n  - {type: spot, spot_inner: 0, spot_outer: 0}\n", ErrorCode::out_of_range, 2,
          45);
    check("objects:\n  - {mesh: tri.obj, material: {shader: test}, scale: 1e10}\n",
          ErrorCode::out_of_range, 2, 54);
    check("objects:\n  - {mesh: tri.obj, material: {shader: test}, position: [0, 0, 1e16]}\n",
          ErrorCode::out_of_range, 2, 57);
    check("plugin_paths: [no-such-folder]\n", ErrorCode::file_not_found, 1, 16);
    check("objects: {mesh: tri.obj}\n", ErrorCode::wrong_type, 1, 10);
}

TEST_CASE("scenes that would draw nothing without a word get a warning or work", "[scene]") {
    Env env;
    {
        // Each triangle overflows a float once scaled: a warning at the object.
        const facet::test::LogCapture log;
        env.write("huge.obj", "v 0 0 0\nv 1e30 0 0\nv 0 1e30 0\nf 1 2 3\n");
        env.scene("objects:\n  - {name: giant, mesh: huge.obj, material: {shader: test}, scale: 1e9}\n");
        CHECK_THAT(log.text(), Contains((env.dir / "scene.yaml").string() +
                                        ":2:5: object 'giant': none of its 1 triangles survives "
                                        "its transform"));
    }
    {
        const facet::test::LogCapture log;
        env.scene("objects:\n  - {mesh: tri.obj, material: {shader: test}, scale: 2}\n");
        CHECK_THAT(log.text(), !Contains("survives"));
    }
    // A tiny up vector is still a direction; a far camera is far, not at
    // its target.
    const facet::Scene tiny_up = env.scene("camera: {up: [0, 1e-30, 0]}\n");
    CHECK(tiny_up.camera.up == glm::vec3(0, 1, 0));
    auto finite = [](const glm::mat4& m) {
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(m[c][r])) return false;
        return true;
    };
    CHECK(finite(tiny_up.camera.view()));
    const facet::Scene far = env.scene("camera: {position: [1e20, 0, 0], target: [0, 0, 0]}\n");
    CHECK(far.camera.position.x == 1e20f);
    const glm::mat4 view = far.camera.view();  // float's squares overflow; double's do not
    REQUIRE(finite(view));
    const glm::vec4 origin = view * glm::vec4(0, 0, 0, 1);
    CHECK(origin.z == Approx(-1e20f));  // straight ahead, 1e20 away
    CHECK(std::abs(origin.x) < 1e13f);
}

TEST_CASE("plugin_paths reach the registry before materials load", "[scene]") {
    Env env;
    fs::create_directories(env.dir / "shaders");
    const facet::Scene s = env.scene(std::string("plugin_paths: [shaders]\n") + kObject);
    REQUIRE(s.plugin_paths == std::vector<fs::path>{env.dir / "shaders"});
    const std::vector<fs::path> search = env.registry.search_path();
    REQUIRE(std::find(search.begin(), search.end(), env.dir / "shaders") != search.end());
}

TEST_CASE("the default scene loads with the built unlit plugin", "[scene]") {
    facet::PluginRegistry registry;
    const facet::Scene s = facet::load_scene(facet::default_scene_path(), registry);
    REQUIRE(s.settings.width == 960);
    REQUIRE(s.settings.height == 540);
    REQUIRE(s.objects.size() == 1);
    const facet::Object& spot = s.objects[0];
    REQUIRE(spot.mesh->triangle_count() > 0);
    REQUIRE(spot.material->plugin->name() == "unlit");
    REQUIRE(spot.material->textures.size() == 1);
    REQUIRE(spot.material->textures[0].texture->srgb);
}
