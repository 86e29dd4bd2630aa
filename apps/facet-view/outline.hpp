// The editor's selection outline: the selected object's silhouette, drawn
// alone in white by the unlit shader into a mask the size of the frame,
// becomes a band of colour just outside its edge in the shown image. The
// frame itself (and so a screenshot) never has it.
#pragma once

#include <facet/framebuffer.hpp>
#include <facet/material.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace facet::view {

class Outline {
public:
    // `threads` as the viewer's renderer has them.
    explicit Outline(int threads);

    // Draws `object`'s outline (`width` pixels) over `rgba`, an sRGB8 image
    // of `settings`' size seen through `camera`. Throws Error if the unlit
    // shader cannot be found.
    void draw(const Object& object, const Camera& camera, const RenderSettings& settings,
              PluginRegistry& registry, TextureCache& textures, std::vector<uint8_t>& rgba,
              int width);

private:
    Renderer renderer_;
    Framebuffer mask_;
    std::vector<uint8_t> inside_;  // 1 where the object covers the pixel
    std::shared_ptr<Material> white_;
};

}  // namespace facet::view
