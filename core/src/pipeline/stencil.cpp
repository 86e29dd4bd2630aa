// The stencil test and its operations (stencil.hpp).
#include "pipeline/stencil.hpp"

#include "pipeline/framebuffer_access.hpp"
#include "pipeline/stencil_ops.hpp"

#include <bit>

namespace facet::FACET_KERNEL_NS {

uint32_t stencil_depth_test(const DrawContext& dc, const TriangleSetup& t, const Block& b,
                            uint32_t lanes, SampleDepth& sd) {
    Framebuffer& fb = *dc.target;
    const int n = fb.samples();
    const StencilFace& f = t.front_facing ? dc.state.stencil.front : dc.state.stencil.back;
    uint8_t* stencil =
        n > 1 ? FramebufferAccess::sample_stencil(fb) : FramebufferAccess::stencil(fb);
    const float* depth = n > 1 ? FramebufferAccess::sample_depth(fb) : FramebufferAccess::depth(fb);
    const glm::vec2 dz = n > 1 ? depth_gradient(t) : glm::vec2(0.0f);
    uint32_t out = 0;
    for (uint32_t m = lanes; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        const float centre = centre_depth(t, b, i);
        const size_t at = pixel_index(fb, b.x + i % 4, b.y + i / 4) * size_t(n);
        uint8_t passed = 0;
        for (uint32_t bits = sd.passed[i]; bits; bits &= bits - 1) {
            const int s = std::countr_zero(bits);
            const float z = sample_depth(centre, dz, n, s);
            sd.z[s][i] = z;
            uint8_t& stored = stencil[at + size_t(s)];
            StencilOp op = f.pass;
            if (!stencil_passes(f.compare, f.reference, stored, f.read_mask))
                op = f.fail;
            else if (!depth_test_passes(dc.state.depth_compare, z, depth[at + size_t(s)]))
                op = f.depth_fail;
            else
                passed |= uint8_t(1u << s);
            stored = stencil_after(op, stored, f.reference, f.write_mask);
        }
        sd.passed[i] = passed;
        out |= uint32_t(passed != 0) << i;
    }
    return out & lanes;
}

}  // namespace facet::FACET_KERNEL_NS
