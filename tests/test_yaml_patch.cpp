// The editor's save: values set in a YAML file's text, everything else kept
// byte for byte (apps/support/yaml_patch.hpp).
#include <facet/error.hpp>
#include <facet/yaml_patch.hpp>

#include <catch2/catch.hpp>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>

using facet::yaml_set;

namespace {

const std::string kScene = R"(# A scene, commented.
camera:
  position: [0, 1.6, 4.4]   # eye
  fov_y: 32
lights:
  - {type: directional, direction: [-0.4, -1.0, -0.7], color: [1.0, 0.95, 0.85], intensity: 0.9}
  - {type: point, position: [0.2, 1.0, 1.6], intensity: 1.6,
     attenuation: [1, 0, 0.5], range: 6}
objects:
  - name: 'ground'
    scale:
      - 8
      - 8
      - 8
    material: ../materials/phong_ground.yaml

  # the teapot
  - name: "phong teapot"
    position: [-0.95, 0, 0]
render:
)";

}  // namespace

TEST_CASE("yaml_set replaces a value and keeps every other byte", "[yaml_patch]") {
    const std::string out = yaml_set(kScene, {"lights", size_t(1), "intensity"}, "2.5");
    std::string expected = kScene;
    expected.replace(expected.find("intensity: 1.6"), 14, "intensity: 2.5");
    CHECK(out == expected);

    // A flow sequence with a comment after it; a scalar at the end of a flow map.
    const std::string eye = yaml_set(kScene, {"camera", "position"}, "[1, 2, 3]");
    CHECK(eye.find("  position: [1, 2, 3]   # eye\n") != std::string::npos);
    const std::string last = yaml_set(kScene, {"lights", size_t(0), "intensity"}, "3");
    CHECK(last.find("[1.0, 0.95, 0.85], intensity: 3}\n") != std::string::npos);
    // A value inside a flow mapping that spans lines.
    const std::string range = yaml_set(kScene, {"lights", size_t(1), "range"}, "12");
    CHECK(range.find("attenuation: [1, 0, 0.5], range: 12}\n") != std::string::npos);
    // A quoted scalar, and a sequence item.
    const std::string name = yaml_set(kScene, {"objects", size_t(1), "name"}, "teapot");
    CHECK(name.find("  - name: teapot\n") != std::string::npos);
    const std::string fov = yaml_set(kScene, {"camera", "fov_y"}, "40");
    CHECK(fov.size() == kScene.size());
    CHECK(YAML::Load(fov)["camera"]["fov_y"].as<float>() == 40.0f);
}

TEST_CASE("yaml_set replaces a block sequence by a flow one", "[yaml_patch]") {
    const std::string out = yaml_set(kScene, {"objects", size_t(0), "scale"}, "[2, 2, 2]");
    const YAML::Node doc = YAML::Load(out);
    CHECK(doc["objects"][0]["scale"][2].as<float>() == 2.0f);
    CHECK(doc["objects"][0]["material"].as<std::string>() == "../materials/phong_ground.yaml");
    CHECK(out.find("  # the teapot\n") != std::string::npos);
}

TEST_CASE("yaml_set adds missing keys where their siblings are", "[yaml_patch]") {
    // In a block mapping: after its last key, at its indentation.
    const std::string out = yaml_set(kScene, {"objects", size_t(1), "scale"}, "0.3");
    CHECK(out.find("    position: [-0.95, 0, 0]\n    scale: 0.3\n") != std::string::npos);
    // In a flow mapping: inside its braces.
    const std::string shadow = yaml_set(kScene, {"lights", size_t(0), "casts_shadow"}, "true");
    CHECK(shadow.find("intensity: 0.9, casts_shadow: true}") != std::string::npos);
    // Under a key with nothing yet, and a whole missing mapping.
    const std::string msaa = yaml_set(kScene, {"render", "msaa"}, "4");
    CHECK(YAML::Load(msaa)["render"]["msaa"].as<int>() == 4);
    const std::string material = "shader: phong\n# no params yet\n";
    const std::string params = yaml_set(material, {"params", "shininess"}, "20");
    CHECK(params == "shader: phong\nparams:\n  shininess: 20\n# no params yet\n");
    const std::string twice = yaml_set(params, {"params", "diffuse"}, "[1, 0, 0]");
    CHECK(twice == "shader: phong\nparams:\n  shininess: 20\n  diffuse: [1, 0, 0]\n# no params yet\n");
    // Every result still parses, to the values set.
    for (const std::string& text : {out, shadow, msaa, params, twice}) CHECK_NOTHROW(YAML::Load(text));
}

TEST_CASE("yaml_set refuses paths the file cannot take", "[yaml_patch]") {
    CHECK_THROWS_AS(yaml_set(kScene, {"lights", size_t(5), "intensity"}, "1"), facet::Error);
    CHECK_THROWS_AS(yaml_set(kScene, {"camera", "fov_y", "x"}, "1"), facet::Error);
    CHECK_THROWS_WITH(yaml_set("a: [1, 2\n", {"a"}, "1", "bad.yaml"),
                      Catch::Contains("bad.yaml"));
}

TEST_CASE("yaml_number writes the shortest text that reads back the same float", "[yaml_patch]") {
    for (float v : {0.1f, 1.0f, 3.0f, -0.95f, 1e-7f, 123456.789f, 0.85f}) {
        const std::string text = facet::yaml_number(v);
        CHECK(std::stof(text) == v);
        CHECK(text.size() <= 12);
    }
    CHECK(facet::yaml_number(0.5f) == "0.5");
    const float c[3] = {1.0f, 0.25f, 0.0f};
    CHECK(facet::yaml_sequence(c, 3) == "[1, 0.25, 0]");
}

TEST_CASE("yaml_set keeps a byte-order mark and CRLF line ends, and reads quotes in plain text",
          "[yaml_patch]") {
    const std::string bom = "\xEF\xBB\xBF";
    CHECK(yaml_set(bom + "a: 1\nb: 2\n", {"b"}, "3") == bom + "a: 1\nb: 3\n");
    CHECK(yaml_set("a: 1\r\nb:\r\n  c: 2\r\n", {"b", "d"}, "4") == "a: 1\r\nb:\r\n  c: 2\r\n  d: 4\r\n");
    // An apostrophe inside a plain scalar does not open a quoted one.
    const std::string pot = "objects:\n  - {name: Bob's pot, mesh: q.obj}\n  - {name: b, mesh: r.obj}\n";
    const std::string out = yaml_set(pot, {"objects", size_t(0), "position"}, "[1, 2, 3]");
    CHECK(out == "objects:\n  - {name: Bob's pot, mesh: q.obj, position: [1, 2, 3]}\n"
                 "  - {name: b, mesh: r.obj}\n");
    // A comment at the start of a line inside a flow sequence, with a bracket in it.
    const std::string list = "a: [1,\n# not ] here\n  2]\nb: 0\n";
    CHECK(yaml_set(list, {"a"}, "[3]") == "a: [3]\nb: 0\n");
}

TEST_CASE("yaml_set refuses what it cannot edit in place, and leaves the text alone",
          "[yaml_patch]") {
    // Anchors and aliases: yaml-cpp places an alias at its anchor's text.
    const std::string anchored = "objects:\n  - {name: a, material: &red {shader: lit}}\n"
                                 "  - {name: b, material: *red}\n";
    CHECK_THROWS_WITH(yaml_set(anchored, {"objects", size_t(1), "position"}, "[3, 0, 0]", "s.yaml"),
                      Catch::Contains("anchors or aliases"));
    CHECK_THROWS_WITH(yaml_set("a: |\n  text\nb: 1\n", {"a"}, "x"), Catch::Contains("block scalar"));
    // A path into a sequence that does not exist yet, under a new key.
    CHECK_THROWS_AS(yaml_set("a: 1\n", {"b", "c", size_t(0)}, "1"), facet::Error);
    CHECK_THROWS_AS(yaml_set("a:\nb: 1\n", {"a", size_t(0)}, "1"), facet::Error);
    CHECK_THROWS_AS(facet::yaml_number(std::numeric_limits<float>::infinity()), facet::Error);
    CHECK_THROWS_AS(facet::yaml_number(std::nanf("")), facet::Error);
}

TEST_CASE("yaml_string quotes what would not read back as the same string", "[yaml_patch]") {
    using facet::yaml_string;
    CHECK(yaml_string("materials/red.yaml") == "materials/red.yaml");
    CHECK(yaml_string("wood, dark.png") == "\"wood, dark.png\"");
    CHECK(yaml_string("a: b") == "\"a: b\"");
    CHECK(yaml_string("true") == "\"true\"");
    CHECK(yaml_string("say \"hi\"") == "\"say \\\"hi\\\"\"");
    for (const std::string s : {"wood, dark.png", "a: b", "#1", "true", "x'y", "[a]", " lead"})
        CHECK(YAML::Load("k: " + yaml_string(s))["k"].as<std::string>() == s);
}
