// The reference renderer: a scene's image as facet should approach it, for
// measuring facet's error (tests and benchmarks only).
//
// Each pixel is the mean of grid x grid samples at the centres of a regular
// grid over the pixel (16 x 16 by default). For each sample:
//   - visibility is exact: a camera ray between the near and far planes,
//     traced in double precision (RayCaster), with the scene's culling;
//   - varyings are the shader's own vertex outputs, interpolated with the
//     hit's exact barycentric weights (perspective-correct by construction;
//     `linear` ones with the window-space weights, `flat` ones from the
//     triangle's first vertex);
//   - textures are read at level 0 with bilinear filtering (the mean over
//     the pixel's samples is then the texture filtered by the pixel's box);
//   - a shadow-casting directional or spot light (the ones facet shadows)
//     is blocked or not by a ray to it: hard shadows, no bias;
//   - ambient visibility, for a shader that asks for AO, is ray-traced with
//     the scene's `render: ao_radius`, over cosine-weighted directions spread
//     across the pixel's samples;
//   - the shading is the plugin's own fragment function, in float, as facet
//     calls it: only what the rasterizer approximates is replaced.
// Samples that hit nothing take the clear colour.
//
// Limits: the geometry is each mesh under its object's transform, which is
// where every built-in shader's vertex function puts it; materials must be
// opaque, without discard, derivatives or the stencil, and write colour (else it throws
// std::runtime_error). Shadowed lighting is taken to be ambient plus a sum
// over lights, as the SDK's lighting helpers compute it: the reference
// removes a blocked light's share, the difference between shading with that
// light alone and with none.
#pragma once

#include <facet/scene.hpp>

#include <glm/glm.hpp>

#include <vector>

namespace facet::reference {

struct RenderOptions {
    int grid = 16;        // samples per pixel side
    int ao_rays = 1;      // AO rays per sample (shaders that need AO)
    int threads = 0;      // 0: one per hardware thread
};

// Linear RGBA per pixel, settings.width x settings.height, top row first.
std::vector<glm::dvec4> render(const Scene& scene, const RenderOptions& options = {});

}  // namespace facet::reference
