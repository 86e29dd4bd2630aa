// Shadow maps.
//
// Takes: the scene, and the objects that cast shadows.
// Gives: one depth map per shadow-casting directional or spot light, seen
// from the light, with the facet_shadow_map that describes it to shaders.
// A directional light's map is orthographic, fitted around the camera's view
// frustum (up to render.shadow_distance) and deep enough to hold every
// caster; a spot light's is perspective, over its cone. Point lights cast no
// shadow map (that would take a cube map).
#pragma once

#include "facet/framebuffer.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"

#include <facet/shader_abi.h>

#include <vector>

namespace facet {

// The maps of one frame: `abi` is the contiguous array shaders receive, and
// abi[i].depth points into depth[i]. Storage is reused from frame to frame.
struct ShadowMaps {
    std::vector<facet_shadow_map> abi;
    std::vector<Framebuffer> depth;
    std::vector<glm::vec3> corners;  // scratch for fitting
};

// Renders one map per light with casts_shadow that is directional or spot;
// afterwards maps.abi holds exactly those.
void render_shadow_maps(const Scene& scene, const std::vector<const Object*>& casters,
                        Renderer& renderer, ShadowMaps& maps);

}  // namespace facet
