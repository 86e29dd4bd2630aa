// Screen-space ambient occlusion.
//
// Takes: the visible opaque parts (DrawItem), the camera's view and projection, the
// target size, and the AO radius, sample count and resolution.
// Gives: ambient visibility, 1 where nothing occludes: a target-sized
// buffer, or at half size the AO grid, which the main pass upsamples a
// tile at a time as it shades (fragment.hpp's TileAo).
//
// It reads a depth-only pre-pass at the target's size: the frame's own, which
// the main pass then shades against (Renderer), or, where the frame cannot
// use one (MSAA, or a part that cannot take part), one it draws itself. The
// AO grid is that size, or half of it per side (settings.half_resolution),
// each of its texels standing for one target pixel (i * scale, j * scale).
// Each texel's view-space position comes from the pre-pass depth (only z is
// stored: x and y follow from it on the pixel's ray), and its normal
// from its neighbours' positions (on each axis, the side nearer in depth, so
// that no normal straddles an edge): the geometric normal, as a ray tracer
// sees the surface. From each texel `samples` cosine-weighted directions in
// the hemisphere around its normal (rotated per texel in a 4x4 pattern) are
// marched in screen space up to `radius` world units, in AoFrame::kSteps
// steps; a direction is occluded where it passes behind the pre-pass
// surface by less than `radius`, a surface that stands above the texel's
// tangent plane. This estimates the same quantity a ray tracer does
// (cosine-weighted visibility within the radius) from what the screen
// shows. The most grazing direction goes first: a group of 16 texels of
// 4 rows where it is open everywhere is taken as open (a nearby occluder
// blocks the grazing directions first; only an overhang within reach could
// block a steeper one alone; the group's texels turn the direction set all
// 16 ways, so between them they look all round). That spares the open
// floor of a typical scene most of its marches, at little cost in accuracy
// against the ray caster (within 0.001 RMSE, facet-bench-shadow-ao). A depth-aware 4x4 blur removes the pattern's
// noise without bleeding across depth edges, and at half resolution a
// depth-aware bilinear upsample gives each target pixel the visibility of
// the texels around it that lie at its depth. Where everything they would
// weigh is open, both give open without weighing (the blur away from a
// row's ends, the upsample where a vector's texels are in whole loads).
//
// The occlusion, blur and upsample are per-ISA kernels
// (pipeline/ao_kernels.cpp, with the other kernels of the path), kWidth
// texels at a time, and every stage runs on the pipeline's threads; the
// upsample runs in the main pass, a tile at a time, where the tile's
// buffer stays in the cache (a main pass cut into several flushes, by
// more than 32k triangles or 256 draws, upsamples a tile again in each).
#pragma once

#include "pipeline/ao_frame.hpp"
#include "base/thread_pool.hpp"

#include "facet/framebuffer.hpp"
#include "facet/pipeline.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"

#include <vector>

namespace facet {

class AoPass {
public:
    // Runs the AO, blur and upsample (timed into stats.ms_ao) for a target
    // of the settings' size and depth range, with their ao_radius,
    // ao_samples and ao_resolution, from `depth`: a single-sampled target
    // whose depth holds every item's nearest surface (the frame's own depth
    // pre-pass), cleared to settings.far_depth(), which
    // means nothing was drawn. Without one, it first draws its own pre-pass of `items`
    // (timed into stats.ms_prepass), in which a cutout's shader sees `time`.
    void run(const std::vector<DrawItem>& items, const glm::mat4& view,
             const glm::mat4& proj, const RenderSettings& settings, float time,
             const Framebuffer* depth, Pipeline& pipeline, FrameStats& stats);

    // The last run's ambient visibility, for the main pass (DrawCall::ao,
    // ao_grid): per target pixel, row-major, at full size; at half size
    // its grid, which the fragment stage upsamples a tile at a time (null
    // otherwise).
    const float* visibility() const { return scale_ == 1 ? blurred_.data() : nullptr; }
    const AoFrame* grid() const { return scale_ == 2 ? &frame_ : nullptr; }

private:
    void make_directions(int samples);
    void draw_prepass(const std::vector<DrawItem>& items, const glm::mat4& view,
                      const glm::mat4& proj, const RenderSettings& settings, float time,
                      Pipeline& pipeline, FrameStats& stats);

    Framebuffer depth_;  // its own pre-pass, at the target's size
    int scale_ = 1;
    AoFrame frame_;
    // Per AO texel; z with a row and a vector of padding on either side,
    // which the normals' neighbour loads may read.
    std::vector<float> z_, key_;
    // The grid z's padding and the key's border were zeroed for:
    // the passes write only inside the grid, so they stay zero until it
    // changes.
    int zeroed_width_ = -1, zeroed_height_ = -1;  // -1: never
    std::vector<float> directions_;
    int direction_samples_ = 0;  // what directions_ holds
    std::vector<float> raw_, blurred_;
};

}  // namespace facet
