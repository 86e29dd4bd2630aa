// Models as artists make them: a mesh file's parts, each drawn with its own
// material (the file's, mapped to facet's, or the scene's), tangents for
// normal maps, and the errors of each new path, which name the file.
#include "reference/metrics.hpp"
#include "reference/render.hpp"
#include "support.hpp"

#include <facet/error.hpp>
#include <facet/png.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <catch2/catch.hpp>

#include <cstring>
#include <fstream>

using namespace facet;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kAssets = fs::path(FACET_SOURCE_DIR) / "assets";

using test::SceneDir;

const char* kCameraAndLight =
    "camera: {position: [2.6, 1.9, 3.2], target: [0, 0.25, 0], fov_y: 38}\n"
    "render: {size: [96, 64], color_format: rgba32f, shadows: false}\n"
    "lights: [{type: directional, direction: [-0.5, -1, -0.35], intensity: 2}]\n";

// A glTF 2.0 file of one quad (z = 0, facing +Z, UVs 0..1 with V down) in
// two primitives, one triangle each, with `materials` (JSON) and each
// primitive's material index; the buffer beside it. `bad_index` puts a
// vertex index past the end into the second triangle. `second_uvs` adds
// a TEXCOORD_1 turned half a turn from the first (1 - u, 1 - v).
void write_gltf(const fs::path& file, const std::string& materials, int first, int second,
                bool bad_index = false, const std::string& images = "[]",
                const std::string& textures = "[]", bool second_uvs = false) {
    const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const float normals[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float uvs[] = {0, 1, 1, 1, 1, 0, 0, 0};
    const float uvs1[] = {1, 0, 0, 0, 0, 1, 1, 1};
    const uint16_t indices[] = {0, 1, 2, 0, 2, uint16_t(bad_index ? 9 : 3), 0, 0};  // and padding
    std::string bin;
    for (const auto& [data, size] : {std::pair<const void*, size_t>{positions, sizeof positions},
                                     {normals, sizeof normals},
                                     {uvs, sizeof uvs},
                                     {indices, sizeof indices},
                                     {uvs1, sizeof uvs1}})
        bin.append(static_cast<const char*>(data), size);
    std::ofstream(fs::path(file).replace_extension(".bin"), std::ios::binary) << bin;
    const std::string bin_name = fs::path(file).replace_extension(".bin").filename().string();
    auto primitive = [second_uvs](int index_accessor, int material) {
        return "{\"attributes\": {\"POSITION\": 0, \"NORMAL\": 1, \"TEXCOORD_0\": 2" +
               std::string(second_uvs ? ", \"TEXCOORD_1\": 5" : "") + "}, "
               "\"indices\": " + std::to_string(index_accessor) +
               (material >= 0 ? ", \"material\": " + std::to_string(material) : "") + "}";
    };
    test::write(file,
                "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],\n"
                " \"nodes\": [{\"name\": \"quad\", \"mesh\": 0}],\n"
                " \"meshes\": [{\"name\": \"quad\", \"primitives\": [" + primitive(3, first) + ", " +
                    primitive(4, second) + "]}],\n"
                " \"materials\": " + materials + ",\n"
                " \"images\": " + images + ", \"textures\": " + textures + ",\n"
                " \"buffers\": [{\"uri\": \"" + bin_name + "\", \"byteLength\": " +
                    std::to_string(bin.size()) + "}],\n"
                " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 48},\n"
                "   {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 48},\n"
                "   {\"buffer\": 0, \"byteOffset\": 96, \"byteLength\": 32},\n"
                "   {\"buffer\": 0, \"byteOffset\": 128, \"byteLength\": 12},\n"
                "   {\"buffer\": 0, \"byteOffset\": 144, \"byteLength\": 32}],\n"
                " \"accessors\": [\n"
                "   {\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\", "
                "\"min\": [-1, -1, 0], \"max\": [1, 1, 0]},\n"
                "   {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"},\n"
                "   {\"bufferView\": 2, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},\n"
                "   {\"bufferView\": 3, \"byteOffset\": 0, \"componentType\": 5123, \"count\": 3, "
                "\"type\": \"SCALAR\"},\n"
                "   {\"bufferView\": 3, \"byteOffset\": 6, \"componentType\": 5123, \"count\": 3, "
                "\"type\": \"SCALAR\"},\n"
                "   {\"bufferView\": 4, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"}]}\n");
}

const char* kTwoMaterials =
    "[{\"name\": \"matte_red\", \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.8, 0.1, 0.1, 1],"
    " \"metallicFactor\": 0, \"roughnessFactor\": 0.9}},"
    " {\"name\": \"blue_metal\", \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.1, 0.2, 0.9, 1],"
    " \"metallicFactor\": 1, \"roughnessFactor\": 0.3}, \"doubleSided\": true,"
    " \"alphaMode\": \"MASK\", \"alphaCutoff\": 0.25}]";

// The value of float parameter `name` in a bound material.
float param(const Material& m, const char* name) {
    const facet_param_desc* d = m.plugin->find_param(name);
    REQUIRE(d);
    float v;
    std::memcpy(&v, m.block->bytes + d->offset, sizeof v);
    return v;
}

glm::vec4 pixel_at(const Framebuffer& fb, const Scene& s, glm::vec3 world) {
    const glm::vec4 c = s.camera.projection(float(s.settings.width) / float(s.settings.height),
                                            s.settings.reversed_z) *
                        s.camera.view() * glm::vec4(world, 1.0f);
    const int x = int((c.x / c.w + 1.0f) * 0.5f * float(s.settings.width));
    const int y = int((1.0f - c.y / c.w) * 0.5f * float(s.settings.height));
    return fb.pixel(x, y);
}

// `s` drawn by facet into `fb`, and its error against the reference
// renderer (8x8 samples a pixel, 2 threads).
reference::ImageError render_against_reference(const Scene& s, Framebuffer& fb) {
    Renderer(1).render(s, fb);
    const std::vector<glm::dvec4> truth = reference::render(s, {8, 1, 2});
    return reference::compare(reference::linear_image(fb), truth, s.settings.width,
                              s.settings.height);
}

}  // namespace

TEST_CASE("a glTF file's primitives are parts, each with its own material mapped to pbr",
          "[model]") {
    SceneDir sd;
    write_gltf(sd.dir / "quad.gltf", kTwoMaterials, 0, 1);
    const Scene s = sd.load(
        "camera: {position: [0, 0, 3], target: [0, 0, 0], fov_y: 50}\n"
        "render: {size: [64, 64], color_format: rgba32f}\n"
        "lights: [{type: directional, direction: [0, 0, -1], intensity: 1}]\n"
        "objects: [{name: quad, mesh: quad.gltf}]\n");
    const Object& o = s.objects.at(0);
    REQUIRE(o.mesh->part_count() == 2);
    CHECK(o.mesh->parts[0].name != o.mesh->parts[1].name);
    const Material& red = *o.material_of(0);
    const Material& blue = *o.material_of(1);
    CHECK(red.shader == "pbr");
    CHECK(blue.shader == "pbr");
    CHECK(param(red, "metallic") == 0.0f);
    CHECK(param(red, "roughness") == Approx(0.9f));
    CHECK(param(blue, "metallic") == 1.0f);
    CHECK(param(blue, "roughness") == Approx(0.3f));
    CHECK(param(blue, "alpha_cutoff") == Approx(0.25f));
    CHECK(blue.cull == CullMode::none);  // doubleSided
    CHECK_FALSE(red.cull.has_value());
    CHECK(red.source == (sd.dir / "quad.gltf").string() + ": material 'matte_red'");
    // Generated tangents: along +u, the bitangent towards the texture's top.
    REQUIRE(o.mesh->tangents.size() == o.mesh->vertex_count());
    for (size_t i = 0; i < o.mesh->vertex_count(); ++i) {
        const glm::vec4 t = o.mesh->tangents[i];
        CHECK(glm::vec3(t) == glm::vec3(1, 0, 0));
        const glm::vec3 bitangent = glm::cross(o.mesh->normals[i], glm::vec3(t)) * t.w;
        CHECK(bitangent.y == Approx(1.0f));  // V runs down the quad: its top is +Y
    }
    // Each triangle is drawn in its own colour: red below the diagonal, blue above.
    Framebuffer fb;
    Renderer(1).render(s, fb);
    const glm::vec4 lower_right = fb.pixel(44, 44), upper_left = fb.pixel(20, 20);
    CHECK(lower_right.r > 3.0f * lower_right.b);
    CHECK(upper_left.b > 2.0f * upper_left.r);
}

TEST_CASE("a glTF primitive without a material gets the format's default material", "[model]") {
    SceneDir sd;
    write_gltf(sd.dir / "quad.gltf", kTwoMaterials, -1, 1);
    const Scene s = sd.load("objects: [{mesh: quad.gltf}]\n");
    const Material& m = *s.objects[0].material_of(0);
    CHECK(m.shader == "pbr");
    CHECK(param(m, "metallic") == 1.0f);
    CHECK(param(m, "roughness") == 1.0f);
    CHECK(s.objects[0].material_of(1)->source.find("blue_metal") != std::string::npos);
}

TEST_CASE("glTF alpha modes, extensions and out-of-range factors map as docs/MATERIALS.md says",
          "[model]") {
    SceneDir sd;
    write_gltf(sd.dir / "modes.gltf",
               "[{\"name\": \"see_through\", \"pbrMetallicRoughness\": {\"baseColorFactor\": "
               "[1, 1, 1, 0.4]}, \"alphaMode\": \"BLEND\"},"
               " {\"name\": \"solid\", \"pbrMetallicRoughness\": {\"baseColorFactor\": "
               "[1, 1, 1, 0.4]}, \"emissiveFactor\": [0.5, 0.25, 0],"
               " \"normalTexture\": {\"index\": 0, \"scale\": 40}},"
               " {\"name\": \"flat\", \"extensions\": {\"KHR_materials_unlit\": {}}}]",
               0, 1, false, "[{\"uri\": \"" + (kAssets / "gallery" / "tiles_normal.png").string() + "\"}]",
               "[{\"source\": 0}]");
    const Scene s = sd.load("camera: {position: [0, 0, 3], target: [0, 0, 0], fov_y: 50}\n"
                            "render: {size: [64, 64], color_format: rgba32f}\n"
                            "objects: [{mesh: modes.gltf}]\n");
    const Object& o = s.objects[0];
    const Material& blend = *o.material_of(0);
    const Material& solid = *o.material_of(1);
    CHECK(blend.blend == BlendMode::alpha);
    CHECK(param(blend, "opaque_alpha") == 0.0f);  // an int32 0 reads as float 0
    CHECK(solid.blend == BlendMode::opaque);
    CHECK(param(solid, "normal_scale") == 16.0f);  // 40, clamped
    const facet_param_desc* emissive = solid.plugin->find_param("emissive");
    float e[3];
    std::memcpy(e, solid.block->bytes + emissive->offset, sizeof e);
    CHECK(e[0] == Approx(0.5f));
    CHECK(e[1] == Approx(0.25f));
    // OPAQUE ignores alpha: the image's alpha is 1 where the solid triangle is.
    Framebuffer fb;
    Renderer(1).render(s, fb);
    CHECK(fb.pixel(44, 44).a == 1.0f);
    // KHR_materials_unlit, on a quad of its own.
    write_gltf(sd.dir / "flat.gltf",
               "[{\"name\": \"flat\", \"pbrMetallicRoughness\": {\"baseColorFactor\": "
               "[0.2, 0.4, 0.6, 1]}, \"extensions\": {\"KHR_materials_unlit\": {}}}]",
               0, 0);
    const Scene flat = sd.load("objects: [{mesh: flat.gltf}]\n");
    CHECK(flat.objects[0].material_of(0)->shader == "unlit");
}

// An 8x8 PNG of four quadrants: red at the top left, green at the top
// right, blue at the bottom left, white at the bottom right.
fs::path quadrant_png(const fs::path& dir) {
    std::vector<uint8_t> rgba(8 * 8 * 4);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const bool right = x >= 4, bottom = y >= 4;
            const uint8_t c[4] = {uint8_t(!bottom || right ? 255 : 0), uint8_t(right ? 255 : 0),
                                  uint8_t(bottom ? 255 : 0), 255};
            std::memcpy(&rgba[size_t(y * 8 + x) * 4], c, 4);
        }
    const fs::path file = dir / "quadrants.png";
    write_png_rows(file, rgba.data(), 8 * 4, 8, 8, 1);
    return file;
}

TEST_CASE("glTF texture transforms, emissive strength, ior, specular and clear coat are drawn",
          "[model][extensions]") {
    SceneDir sd;
    // KHR_texture_transform's own example: the lower left quadrant alone,
    // turned 90 degrees.
    const std::string placed =
        "{\"index\": 0, \"extensions\": {\"KHR_texture_transform\": {\"offset\": [0, 1], "
        "\"rotation\": 1.57079632679, \"scale\": [0.5, 0.5]}}}";
    write_gltf(sd.dir / "layers.gltf",
               "[{\"name\": \"coated\", \"pbrMetallicRoughness\": {\"baseColorTexture\": " + placed +
                   ", \"metallicFactor\": 0, \"roughnessFactor\": 0.5}, \"emissiveFactor\": [0.1, 0.2, 0.3],"
                   " \"extensions\": {\"KHR_materials_emissive_strength\": {\"emissiveStrength\": 4},"
                   " \"KHR_materials_ior\": {\"ior\": 1.8},"
                   " \"KHR_materials_specular\": {\"specularFactor\": 0.5, \"specularColorFactor\": [1, 0.5, 0.25],"
                   " \"specularTexture\": {\"index\": 0}},"
                   " \"KHR_materials_clearcoat\": {\"clearcoatFactor\": 0.75, \"clearcoatRoughnessFactor\": 0.2,"
                   " \"clearcoatNormalTexture\": {\"index\": 0}}}},"
                   " {\"name\": \"flat\", \"pbrMetallicRoughness\": {\"baseColorTexture\": " + placed + "},"
                   " \"extensions\": {\"KHR_materials_unlit\": {}}}],"
                   " \"extensionsUsed\": [\"KHR_texture_transform\", \"KHR_materials_emissive_strength\","
                   " \"KHR_materials_ior\", \"KHR_materials_specular\", \"KHR_materials_clearcoat\","
                   " \"KHR_materials_unlit\"]",
               0, 1, false, "[{\"uri\": \"" + quadrant_png(sd.dir).string() + "\"}]",
               "[{\"source\": 0, \"sampler\": 0}], \"samplers\": [{\"magFilter\": 9729, \"minFilter\": 9729,"
               " \"wrapS\": 33071, \"wrapT\": 33071}]");  // bilinear, as the reference reads, and clamped
    test::LogCapture log;
    const Scene s = sd.load(std::string(kCameraAndLight) + "objects: [{mesh: layers.gltf}]\n");
    const Material& coated = *s.objects[0].material_of(0);
    CHECK(param(coated, "ior") == Approx(1.8f));
    CHECK(param(coated, "specular") == Approx(0.5f));
    CHECK(param(coated, "clearcoat") == Approx(0.75f));
    CHECK(param(coated, "clearcoat_roughness") == Approx(0.2f));
    float v[3];
    std::memcpy(v, coated.block->bytes + coated.plugin->find_param("emissive")->offset, sizeof v);
    CHECK(glm::vec3(v[0], v[1], v[2]) == glm::vec3(0.4f, 0.8f, 1.2f));  // times the strength
    std::memcpy(v, coated.block->bytes + coated.plugin->find_param("specular_color")->offset, sizeof v);
    CHECK(glm::vec3(v[0], v[1], v[2]) == glm::vec3(1.0f, 0.5f, 0.25f));
    const UvTransform& t = coated.textures.at(0).transform;
    CHECK(t.offset == glm::vec2(0.0f, 1.0f));
    CHECK(t.rotation == Approx(1.5707963f));
    CHECK(t.scale == glm::vec2(0.5f));
    // What is left out is said.
    CHECK_THAT(log.text(), Contains("clear coat normal texture") && Contains("specularTexture"));
    // The unlit triangle (top left) shows the lower left quadrant only: blue.
    Scene front = s;
    front.camera.position = {0.0f, 0.0f, 3.0f};
    front.camera.target = {0.0f, 0.0f, 0.0f};
    Framebuffer fb;
    Renderer(1).render(front, fb);
    for (const glm::vec3 at : {glm::vec3(-0.8f, 0.6f, 0.0f), glm::vec3(-0.2f, 0.8f, 0.0f),
                               glm::vec3(-0.7f, -0.5f, 0.0f), glm::vec3(0.5f, 0.8f, 0.0f)}) {
        INFO("at " << at.x << ", " << at.y);
        const glm::vec4 c = pixel_at(fb, front, at);
        CHECK(c.r < 0.01f);
        CHECK(c.g < 0.01f);
        CHECK(c.b > 0.99f);
    }
    // The transformed textures, the coat and all, match the reference
    // renderer (four samples a pixel: the quad's edges, blue on black, are
    // most of the error).
    Scene sampled = s;
    sampled.settings.msaa = 4;
    Framebuffer lit;
    const reference::ImageError e = render_against_reference(sampled, lit);
    CAPTURE(e.rmse, e.max, e.dssim);
    CHECK(e.rmse < 0.05);
}

TEST_CASE("glTF extensions reach the material assimp reads, in assimp's order", "[model][extensions]") {
    // The first primitive uses the file's second material: assimp reads the
    // materials in the order it meets them, so its material 0 is the file's
    // 1. Each must keep its own emissive strength.
    SceneDir sd;
    write_gltf(sd.dir / "order.gltf",
               "[{\"name\": \"two\", \"emissiveFactor\": [0.1, 0.1, 0.1],"
               " \"extensions\": {\"KHR_materials_emissive_strength\": {\"emissiveStrength\": 2}}},"
               " {\"name\": \"five\", \"emissiveFactor\": [0.1, 0.1, 0.1],"
               " \"extensions\": {\"KHR_materials_emissive_strength\": {\"emissiveStrength\": 5}}}],"
               " \"extensionsUsed\": [\"KHR_materials_emissive_strength\"]",
               1, 0);
    const Scene s = sd.load("objects: [{mesh: order.gltf}]\n");
    for (size_t part = 0; part < 2; ++part) {
        const Material& m = *s.objects[0].material_of(part);
        INFO(m.source);
        float e[3];
        std::memcpy(e, m.block->bytes + m.plugin->find_param("emissive")->offset, sizeof e);
        const bool five = m.source.find("'five'") != std::string::npos;
        CHECK(five == (part == 0));
        CHECK(e[0] == Approx(five ? 0.5f : 0.2f));
    }
}

TEST_CASE("a glTF texture of the second UV set is drawn at TEXCOORD_1", "[model][extensions]") {
    SceneDir sd;
    // The base colour on set 1, which is set 0 turned half a turn; the
    // occlusion on set 0. The unlit triangle's base is on set 1 too, which
    // unlit does not have: left out, and said.
    write_gltf(sd.dir / "two_sets.gltf",
               "[{\"name\": \"turned\", \"pbrMetallicRoughness\": {\"baseColorTexture\": "
               "{\"index\": 0, \"texCoord\": 1}, \"metallicFactor\": 0, \"roughnessFactor\": 0.6},"
               " \"occlusionTexture\": {\"index\": 0}},"
               " {\"name\": \"flat\", \"pbrMetallicRoughness\": {\"baseColorTexture\": "
               "{\"index\": 0, \"texCoord\": 1}}, \"extensions\": {\"KHR_materials_unlit\": {}}}],"
               " \"extensionsUsed\": [\"KHR_materials_unlit\"]",
               0, 1, false, "[{\"uri\": \"" + quadrant_png(sd.dir).string() + "\"}]",
               "[{\"source\": 0, \"sampler\": 0}], \"samplers\": [{\"magFilter\": 9729, \"minFilter\": 9729,"
               " \"wrapS\": 33071, \"wrapT\": 33071}]",
               true);
    test::LogCapture log;
    Scene s = sd.load(std::string(kCameraAndLight) + "objects: [{mesh: two_sets.gltf}]\n");
    CHECK_THAT(log.text(), Contains("material 'flat': base colour texture reads texture coordinates "
                                    "set 1, and this material's shader reads only the first"));
    const Object& o = s.objects[0];
    REQUIRE(o.mesh->uvs1.size() == o.mesh->vertex_count());
    const Material& turned = *o.material_of(0);
    const int base = turned.plugin->texture_slot(*turned.plugin->find_param("base_texture"));
    const int occlusion = turned.plugin->texture_slot(*turned.plugin->find_param("occlusion_texture"));
    CHECK(turned.textures.at(size_t(base)).uv_set == 1);
    CHECK(turned.textures.at(size_t(occlusion)).uv_set == 0);
    // It matches the reference renderer, which samples each texture at its own set.
    s.settings.msaa = 4;
    Framebuffer fb;
    const reference::ImageError e = render_against_reference(s, fb);
    CAPTURE(e.rmse, e.max, e.dssim);
    CHECK(e.rmse < 0.05);
    // Near the quad's corner at the bottom right (u, v = 0.9), set 0 reads
    // white and set 1 red: the base is red, darkened by the occlusion's white (1).
    const glm::vec4 c = pixel_at(fb, s, {0.8f, -0.8f, 0.0f});
    CHECK(c.r > 0.05f);
    CHECK(c.g < 0.2f * c.r);
    CHECK(c.b < 0.2f * c.r);
}

TEST_CASE("an OBJ whose material library is missing, or lacks its usemtl, is an error",
          "[model][errors]") {
    SceneDir sd;
    const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shiny\nf 1 2 3\n";
    test::write(sd.dir / "lost.obj", "mtllib missing.mtl\n" + triangle);
    std::string e = sd.error("objects: [{mesh: lost.obj}]\n");
    CHECK_THAT(e, Contains("lost.obj: material 'shiny'"));
    CHECK_THAT(e, Contains("material library 'missing.mtl' was not found"));
    test::write(sd.dir / "other.mtl", "newmtl dull\nKd 1 0 0\n");
    test::write(sd.dir / "undefined.obj", "mtllib other.mtl\n" + triangle);
    e = sd.error("objects: [{mesh: undefined.obj}]\n");
    CHECK_THAT(e, Contains("undefined.obj: material 'shiny'"));
    CHECK_THAT(e, Contains("no material library (mtllib) of the file defines it"));
    // Naming a material in the scene needs none of the file's.
    CHECK_NOTHROW(sd.load("objects: [{mesh: lost.obj, material: {shader: lit}}]\n"));
}

TEST_CASE("a scene names materials for a whole object, a part or a file's material", "[model]") {
    SceneDir sd;
    write_gltf(sd.dir / "quad.gltf", kTwoMaterials, 0, 1);
    test::write(sd.dir / "green.yaml", "shader: unlit\nparams: {base_color: [0, 1, 0, 1]}\n");
    const std::string head = "objects:\n  - name: quad\n    mesh: quad.gltf\n";
    {
        const Scene s = sd.load(head + "    material: green.yaml\n");
        const Object& o = s.objects[0];
        CHECK(o.material_of(0)->shader == "unlit");
        CHECK(o.material_of(1)->shader == "unlit");
    }
    {
        const Scene s = sd.load(head + "    materials: {blue_metal: green.yaml}\n");
        const Object& o = s.objects[0];
        CHECK(o.material_of(0)->shader == "pbr");
        CHECK(o.material_of(1)->shader == "unlit");
        CHECK(o.materials().size() == 2);
    }
    {
        // By part name, over a material for the whole object.
        const Scene s0 = sd.load(head);
        const std::string part = s0.objects[0].mesh->parts[0].name;
        const Scene s = sd.load(head + "    material: {shader: lit}\n    materials: {'" + part +
                                "': green.yaml}\n");
        CHECK(s.objects[0].material_of(0)->shader == "unlit");
        CHECK(s.objects[0].material_of(1)->shader == "lit");
    }
}

TEST_CASE("an OBJ with an .mtl renders with its diffuse textures, as the reference does",
          "[model][reference]") {
    SceneDir sd;
    const fs::path crate = kAssets / "crate_obj" / "crate.obj";
    const Scene s = sd.load(std::string(kCameraAndLight) +
                            "objects: [{name: crate, mesh: " + crate.string() +
                            ", position: [0, 0, 0], rotation: [0, 20, 0], scale: 0.8}]\n");
    const Object& o = s.objects.at(0);
    REQUIRE(o.mesh->part_count() >= 3);
    int textured = 0;
    for (size_t i = 0; i < o.mesh->part_count(); ++i) {
        const Material& m = *o.material_of(i);
        CHECK(m.shader == "phong");
        if (!m.textures.empty() && m.textures[0].texture) {
            ++textured;
            CHECK_THAT(m.textures[0].texture->source, Contains("crate_obj"));
        }
    }
    CHECK(textured >= 2);  // wood and label
    Framebuffer fb;
    const reference::ImageError e = render_against_reference(s, fb);
    CAPTURE(e.rmse, e.max, e.dssim);
    CHECK(e.rmse < 0.05);
    // Without its textures the crate looks different.
    Scene plain = s;
    for (PartMaterial& p : plain.objects[0].part_materials) {
        if (!p.material) continue;
        auto m = std::make_shared<Material>(*p.material);
        for (TextureBinding& t : m->textures) t.texture.reset();
        p.material = m;
    }
    Framebuffer untextured;
    Renderer(1).render(plain, untextured);
    const reference::ImageError d = reference::compare(reference::linear_image(untextured),
                                                       reference::linear_image(fb),
                                                       s.settings.width, s.settings.height);
    CHECK(d.rmse > 0.02);
}

TEST_CASE("the gallery glTF, normal maps and all, matches the reference renderer",
          "[model][reference]") {
    SceneDir sd;
    const fs::path gallery = kAssets / "gallery" / "gallery.gltf";
    // The reference draws no cutouts: the leaves are drawn opaque here.
    // Four samples a pixel, as the edges of so small an image are most of its error.
    Scene s = sd.load(std::string(kCameraAndLight) +
                      "objects:\n  - name: gallery\n    mesh: " + gallery.string() +
                      "\n    materials: {leaves_cutout: {shader: pbr}}\n");
    s.settings.msaa = 4;
    const Object& o = s.objects.at(0);
    CHECK(o.mesh->part_count() == 6);
    int normal_mapped = 0;
    for (size_t i = 0; i < o.mesh->part_count(); ++i) {
        const Material& m = *o.material_of(i);
        const int slot = m.plugin->texture_slot(*m.plugin->find_param("normal_texture"));
        normal_mapped += m.textures[size_t(slot)].texture != nullptr;
    }
    CHECK(normal_mapped == 2);  // the tiles and the bricks
    Framebuffer fb;
    const reference::ImageError e = render_against_reference(s, fb);
    CAPTURE(e.rmse, e.max, e.dssim);
    CHECK(e.rmse < 0.05);  // with one sample, 0.074: mostly edges
    // Each part shows its material: the gold sphere is gold, the plastic one red.
    const glm::vec4 gold = pixel_at(fb, s, {-0.75f, 0.5f, 0.45f});
    const glm::vec4 red = pixel_at(fb, s, {0.15f, 0.5f, 0.85f});
    CHECK(gold.r > gold.b);
    CHECK(gold.g > gold.b);
    CHECK(red.r > 2.0f * red.g);
    CHECK(red.r > 2.0f * red.b);
}

TEST_CASE("tangents split where UVs are mirrored, so each side keeps its frame", "[model]") {
    SceneDir sd;
    // Two quads side by side sharing an edge; the right one's texture is
    // mirrored in u, so the shared vertices meet both handednesses.
    test::write(sd.dir / "mirror.obj",
                "v -1 0 0\nv 0 0 0\nv 0 1 0\nv -1 1 0\nv 1 0 0\nv 1 1 0\n"
                "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                "vn 0 0 1\n"
                "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n"
                "f 5/1/1 6/4/1 3/3/1\nf 5/1/1 3/3/1 2/2/1\n");
    const Scene s = sd.load("objects: [{mesh: mirror.obj, material: {shader: lit}}]\n");
    const Mesh& m = *s.objects[0].mesh;
    REQUIRE(m.tangents.size() == m.vertex_count());
    int left = 0, right = 0;
    for (size_t t = 0; t < m.triangle_count(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = m.indices[3 * t + k];
            const glm::vec4 tangent = m.tangents[i];
            // The right quad's +u runs to -X.
            const bool right_quad = t >= 2;
            CHECK(tangent.x == Approx(right_quad ? -1.0f : 1.0f));
            CHECK(std::abs(tangent.y) < 1e-6f);
            // OBJ's V runs up; either way the bitangent points up the texture: +Y.
            CHECK((glm::cross(m.normals[i], glm::vec3(tangent)) * tangent.w).y == Approx(1.0f));
            (right_quad ? right : left) += 1;
        }
    }
    CHECK(left == 6);
    CHECK(right == 6);
    CHECK(m.vertex_count() == 8);  // the two shared vertices, split
}

TEST_CASE("model errors name the file: missing textures, bad indices, names that match nothing",
          "[model][errors]") {
    SceneDir sd;
    const std::string images = "[{\"uri\": \"missing.png\"}]";
    const std::string textures = "[{\"source\": 0}]";
    {
        write_gltf(sd.dir / "untextured.gltf",
                   "[{\"name\": \"painted\", \"pbrMetallicRoughness\": {\"baseColorTexture\": "
                   "{\"index\": 0}}}]",
                   0, 0, false, images, textures);
        const std::string e = sd.error("objects: [{mesh: untextured.gltf}]\n");
        CHECK_THAT(e, Contains("scene.yaml:1:"));
        CHECK_THAT(e, Contains("untextured.gltf: material 'painted'"));
        CHECK_THAT(e, Contains("missing.png"));
    }
    {
        test::write(sd.dir / "box.obj",
                    "mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                    "usemtl painted\nf 1/1 2/2 3/3\n");
        test::write(sd.dir / "box.mtl", "newmtl painted\nKd 1 1 1\nmap_Kd nowhere.png\n");
        const std::string e = sd.error("objects: [{mesh: box.obj}]\n");
        CHECK_THAT(e, Contains("box.obj: material 'painted'"));
        CHECK_THAT(e, Contains("nowhere.png"));
    }
    {
        write_gltf(sd.dir / "bad.gltf", kTwoMaterials, 0, 1, true);
        const std::string e = sd.error("objects: [{mesh: bad.gltf}]\n");
        CHECK_THAT(e, Contains("bad.gltf"));
        CHECK_THAT(e, Contains("mesh failed to load") || Contains("invalid mesh"));
    }
    {
        write_gltf(sd.dir / "quad.gltf", kTwoMaterials, 0, 1);
        const std::string e =
            sd.error("objects:\n  - mesh: quad.gltf\n    materials: {chrome: {shader: lit}}\n");
        CHECK_THAT(e, Contains("scene.yaml:3:17"));
        CHECK_THAT(e, Contains("'chrome' names no part and no material of"));
        CHECK_THAT(e, Contains("'matte_red', 'blue_metal'"));
        const std::string key = sd.error(
            "objects:\n  - mesh: quad.gltf\n    materials: {[a, b]: {shader: lit}}\n");
        CHECK_THAT(key, Contains("scene.yaml:3:17"));
        CHECK_THAT(key, Contains("expected a key of materials"));
    }
    {
        // An OBJ without materials, and no material in the scene: drawn
        // grey, with a warning that says how to name one.
        test::write(sd.dir / "bare.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        test::LogCapture log;
        const Scene bare = sd.load("objects: [{name: bare, mesh: bare.obj}]\n");
        CHECK_THAT(log.text(), Contains("object 'bare'"));
        CHECK_THAT(log.text(), Contains("has no material in its file; it is drawn grey"));
        REQUIRE(bare.objects[0].material_of(0) != nullptr);
        CHECK(bare.objects[0].material_of(0)->shader == "phong");
    }
    {
        // An embedded image that is no image is an error naming it.
        write_gltf(sd.dir / "garbled.gltf",
                   "[{\"name\": \"inside\", \"pbrMetallicRoughness\": {\"baseColorTexture\": "
                   "{\"index\": 0}}}]",
                   0, 0, false, "[{\"uri\": \"data:image/png;base64,bm90IGFuIGltYWdl\"}]",
                   textures);
        const std::string e = sd.error("objects: [{mesh: garbled.gltf}]\n");
        CHECK_THAT(e, Contains("garbled.gltf: material 'inside'"));
        CHECK_THAT(e, Contains("garbled.gltf#0"));
        // A scene that names its own material for it needs none of it.
        CHECK_NOTHROW(sd.load("objects: [{mesh: garbled.gltf, material: {shader: lit}}]\n"));
    }
}

namespace {

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 2]));
        out += digits[n >> 18 & 63];
        out += digits[n >> 12 & 63];
        out += i + 1 < bytes.size() ? digits[n >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? digits[n & 63] : '=';
    }
    return out;
}

}  // namespace

TEST_CASE("textures embedded in a glTF file are read from it", "[model]") {
    SceneDir sd;
    const fs::path png = kAssets / "gallery" / "leaves_basecolor.png";
    std::ifstream in(png, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    write_gltf(sd.dir / "embedded.gltf",
               "[{\"name\": \"inside\", \"pbrMetallicRoughness\": {\"baseColorTexture\": "
               "{\"index\": 0}}}]",
               0, 0, false, "[{\"uri\": \"data:image/png;base64," + base64(bytes) + "\"}]",
               "[{\"source\": 0}]");
    const Scene s = sd.load("objects: [{mesh: embedded.gltf}]\n");
    const Material& m = *s.objects[0].material_of(0);
    REQUIRE(m.textures.at(0).texture);
    const Texture& t = *m.textures[0].texture;
    CHECK_THAT(t.source, Contains("embedded.gltf#0"));
    CHECK(t.srgb);
    // The same texels as the file the image came from.
    const std::shared_ptr<const Texture> file = load_texture(png, true);
    CHECK(t.width == file->width);
    CHECK(t.height == file->height);
    CHECK(t.texels == file->texels);
}
