// The post-processing chain: the scene's screen passes (Scene::post), run in
// order on the finished frame.
//
// Takes: the frame drawn into a float target (rgba32f, one sample: the MSAA
// resolve comes first), the chain, and the target the frame goes to.
// Gives: each pass's result in place in the float target, one after the
// other, then the result encoded into the output target in its format,
// with the frame's depth; the time of each pass in FrameStats.
//
// A pass is called once, on the rendering thread; it shares its work out
// to the pipeline's threads through the host's parallel_for
// (pipeline/host.cpp), and keeps its intermediate images in scratch memory
// this chain owns: FACET_PASS_SCRATCH_SLOTS buffers per position in the
// chain, kept between frames, so that a steady frame allocates nothing.
#pragma once

#include "pipeline/draw_context.hpp"

#include "facet/framebuffer.hpp"
#include "facet/pipeline.hpp"
#include "facet/scene.hpp"

#include <array>
#include <vector>

namespace facet {

class PostChain {
public:
    // Runs `passes` over `frame` (rgba32f, one sample) and writes the result
    // into `target` (the frame's size, one sample, any colour format).
    // Stops between passes when the pipeline is stopped. `time` is the
    // scene's (facet_pass_frame.time).
    void run(const std::vector<PostPass>& passes, Framebuffer& frame, Framebuffer& target,
             const RenderSettings& settings, float time, Pipeline& pipeline, FrameStats& stats);

private:
    std::vector<std::array<PostScratch, FACET_PASS_SCRATCH_SLOTS>> scratch_;  // per position
};

}  // namespace facet
