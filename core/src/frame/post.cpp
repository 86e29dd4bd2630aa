// The post-processing chain (post.hpp): each screen pass in place on the
// float frame, then the result in the target's format.
#include "frame/post.hpp"

#include "base/timing.hpp"
#include "pipeline/framebuffer_access.hpp"
#include "pipeline/kernels.hpp"
#include "plugin/plugin_calls.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace facet {

void PostChain::run(const std::vector<PostPass>& passes, Framebuffer& frame, Framebuffer& target,
                    const RenderSettings& settings, float time, Pipeline& pipeline,
                    FrameStats& stats) {
    if (scratch_.size() < passes.size()) scratch_.resize(passes.size());
    FramebufferAccess::forget_cleared(frame);  // the passes write it in place
    for (size_t i = 0; i < passes.size() && !pipeline.stopped(); ++i) {
        const PostPass& pass = passes[i];
        const auto start = std::chrono::steady_clock::now();
        PostContext context{pass.plugin.get(), &pipeline.pool(), scratch_[i].data()};
        facet_pass_frame f{};
        f.host = host_services();
        f.params = pass.block->bytes;
        f.host_data = &context;
        f.width = uint32_t(frame.width());
        f.height = uint32_t(frame.height());
        f.stride = uint32_t(frame.stride());
        f.threads = uint32_t(pipeline.threads());
        f.color = reinterpret_cast<float*>(FramebufferAccess::color(frame));
        f.depth = FramebufferAccess::depth(frame);
        f.reversed_z = settings.reversed_z ? 1u : 0u;
        f.time = time;
        call_plugin(pass.plugin.get(), PluginEntry::post, pass.plugin->pass(), &f);
        if (i < size_t(FrameStats::kPostTimings)) stats.ms_post_pass[i] = elapsed_ms(start);
        ++stats.post_passes;
    }
    // The result in the target's format (a copy for rgba32f), and the depth.
    const Kernels& k = pipeline.kernels();
    const size_t row_bytes = size_t(target.stride()) * size_t(bytes_per_pixel(target.format()));
    FramebufferAccess::forget_cleared(target);
    uint8_t* const color = FramebufferAccess::color(target);
    float* const depth = FramebufferAccess::depth(target);
    const Framebuffer& drawn = frame;
    pipeline.pool().parallel_for(frame.height(), [&](int y, int) {
        const auto* from = reinterpret_cast<const glm::vec4*>(drawn.color_data()) +
                           size_t(y) * size_t(frame.stride());
        k.encode_pixels(target.format(), from, size_t(frame.width()), color + size_t(y) * row_bytes);
        std::memcpy(depth + size_t(y) * size_t(target.stride()),
                    drawn.depth() + size_t(y) * size_t(frame.stride()),
                    sizeof(float) * size_t(frame.width()));
    });
}

}  // namespace facet
