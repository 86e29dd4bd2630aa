// The probe frame of a plugin on its first load (facet-sandbox's `probe`
// job; PluginRegistry::get runs it before the host loads the plugin): the
// plugin, loaded from its file, draws a small frame that needs nothing but
// itself.
//   A shader: a sphere with every vertex attribute a shader may ask for
//   (normals, UVs, colours, tangents), in its material's default
//   parameters, lit by a directional, a point and a spot light.
//   A screen pass: run over a cleared frame, in its default parameters.
// Whatever the plugin does wrong there (a crash, exit(), a loop, an
// allocation without bound) ends the sandbox, not the host.
#include "probe_frame.hpp"

#include <facet/framebuffer.hpp>
#include <facet/material.hpp>
#include <facet/mesh.hpp>
#include <facet/plugin.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/texture.hpp>

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

namespace facet {

namespace {

std::shared_ptr<const Mesh> probe_sphere() {
    constexpr int kRings = 8, kSegments = 16;
    auto m = std::make_shared<Mesh>();
    m->source = "the probe frame's sphere";
    for (int r = 0; r <= kRings; ++r)
        for (int s = 0; s <= kSegments; ++s) {
            const float theta = glm::pi<float>() * float(r) / float(kRings);
            const float phi = glm::two_pi<float>() * float(s) / float(kSegments);
            const glm::vec3 unit(std::sin(theta) * std::cos(phi), std::cos(theta),
                                 std::sin(theta) * std::sin(phi));
            m->positions.push_back(unit);
            m->normals.push_back(unit);
            m->uvs.push_back({float(s) / float(kSegments), 1.0f - float(r) / float(kRings)});
            m->colors.push_back({0.8f, 0.6f, 0.4f, 1.0f});
            m->tangents.push_back({-std::sin(phi), 0.0f, std::cos(phi), 1.0f});
        }
    for (int r = 0; r < kRings; ++r)
        for (int s = 0; s < kSegments; ++s) {
            const uint32_t a = uint32_t(r * (kSegments + 1) + s), b = a + 1,
                           c = a + uint32_t(kSegments + 1), d = c + 1;
            m->indices.insert(m->indices.end(), {a, b, c, b, d, c});
        }
    m->bounds = compute_bounds(m->positions);
    return m;
}

std::vector<Light> probe_lights() {
    Light sun;
    sun.direction = glm::normalize(glm::vec3(-1.0f, -2.0f, -1.0f));
    Light point;
    point.type = LightType::point;
    point.position = {2.0f, 2.0f, 2.0f};
    point.attenuation = {1.0f, 0.1f, 0.01f};
    Light spot;
    spot.type = LightType::spot;
    spot.position = {0.0f, 3.0f, 0.0f};
    return {sun, point, spot};
}

}  // namespace

void probe_frame(const std::filesystem::path& plugin_file, int width) {
    const std::shared_ptr<ShaderPlugin> plugin = ShaderPlugin::load(plugin_file);
    TextureCache textures;
    Scene scene;
    scene.source = plugin_file;
    RenderSettings& s = scene.settings;
    s.width = width;
    s.height = std::max(1, width * 3 / 4);
    s.msaa = 1;
    s.shadow_map_size = 64;
    if (plugin->is_post()) {
        PostPass pass;
        pass.name = plugin->name();
        pass.file = plugin_file.string();
        pass.block = bind_params({}, *plugin, pass.file, textures).block;
        pass.plugin = plugin;
        scene.post.push_back(std::move(pass));
    } else {
        auto material = std::make_shared<Material>();
        material->shader = plugin->name();
        material->source = "the probe frame";
        bind(*material, plugin, textures);
        Object sphere;
        sphere.name = "probe";
        sphere.mesh = probe_sphere();
        sphere.material = material;
        scene.objects.push_back(std::move(sphere));
        scene.lights = probe_lights();
    }
    Renderer renderer(1);
    Framebuffer target;
    renderer.render(scene, target);
}

}  // namespace facet
