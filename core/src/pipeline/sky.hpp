// The sky pass: the scene's environment drawn behind everything, after the
// opaque draws and before the blended ones, only where nothing was drawn
// (the depth still at the far value the frame was cleared to), so pixels
// that geometry covers cost nothing. With MSAA, each sample on its own.
//
// Takes: a target, the environment's record, and the world direction
// through each pixel centre, which for a perspective camera is affine in
// the pixel's position. Gives: the environment's radiance there (level 0,
// or at the background's blur), in the target's format, alpha 1.
#pragma once

#include "facet/framebuffer.hpp"

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

namespace facet {

struct SkyRows {
    Framebuffer* target = nullptr;
    const facet_environment* environment = nullptr;
    float blur = 0.0f;  // perceptual roughness of the background; 0: level 0
    // World direction through image point (x, y), in pixels from the
    // image's top-left corner: origin + x dx + y dy.
    glm::vec3 origin{0.0f}, dx{0.0f}, dy{0.0f};
    int first_row = 0;       // the target's first row in the image
    float far_depth = 1.0f;  // what the target was cleared to
};

// The directions of a camera's pixels for a width x height image, from
// its view and projection and its position (perspective), or along its
// view (orthographic: every pixel looks the same way).
void sky_directions(SkyRows& sky, const glm::mat4& view, const glm::mat4& projection,
                    const glm::vec3& camera, bool orthographic, int width, int height);

}  // namespace facet
