// Screen-space ambient occlusion.
//
// Takes: the visible opaque objects, the camera's view and projection, the
// target size, and the AO radius and sample count.
// Gives: a target-sized buffer of ambient visibility, 1 where nothing
// occludes. A pre-pass renders depth and view-space normals. For each pixel,
// `samples` cosine-weighted directions in the hemisphere around its normal
// (rotated per pixel in a 4x4 pattern) are marched in screen space up to
// `radius` world units; a direction is occluded where it passes behind the
// pre-pass surface by less than `radius`. This estimates the same quantity a
// ray tracer does (cosine-weighted visibility within the radius) from what
// the screen shows. A depth-aware 4x4 blur then removes the pattern's noise
// without bleeding across depth edges.
#pragma once

#include "thread_pool.hpp"

#include "facet/framebuffer.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"

#include <vector>

namespace facet {

struct AoSettings {
    float radius = 0.5f;  // world units
    int samples = 12;     // directions per pixel
};

// AO radius and sample count from the material's `ao_radius` (float) and
// `ao_samples` (int) parameters, where its shader declares them; clamped.
AoSettings ao_settings(const Material& material);

class AoPass {
public:
    // Runs the pre-pass (timed into stats.ms_prepass) and the AO and blur
    // (stats.ms_ao). `reversed_z` and `clear_depth` describe the depth range.
    void run(const std::vector<const Object*>& objects, const glm::mat4& view,
             const glm::mat4& proj, bool reversed_z, int width, int height,
             const AoSettings& settings, Renderer& renderer, ThreadPool& pool,
             FrameStats& stats);

    // Ambient visibility per pixel of the last run, row-major.
    const float* visibility() const { return blurred_.data(); }

private:
    void linearize(const glm::mat4& proj, bool reversed_z, int y);
    void occlusion(const glm::mat4& proj, const AoSettings& settings, int y);
    void blur(int y);
    bool blocked(const glm::vec3& p, const glm::vec3& dir, const glm::mat4& proj,
                 float radius) const;

    Framebuffer prepass_;
    std::vector<float> view_z_;  // view-space z per pixel; 0 where nothing was drawn
    std::vector<float> raw_;
    std::vector<float> blurred_;
};

}  // namespace facet
