// The sky pass (sky.hpp), once per instruction-set path: kWidth pixels of
// a row at a time, each looked up in the environment by the SDK's own
// lookup (<facet/environment.hpp>), so the background and a mirror show the
// same texels.
#include "pipeline/framebuffer_access.hpp"
#include "pipeline/kernels.hpp"
#include "pipeline/pixels.hpp"
#include "pipeline/sky.hpp"

#include <facet/environment.hpp>

#include <cstring>

namespace facet::FACET_KERNEL_NS {

namespace {

// Bit i: the pixel `first` + i has its sample s (of `samples`) still at the
// far depth; with one sample, a vector compare.
uint32_t far_lanes(const float* depth, size_t first, int samples, int s, float far) {
    if (samples == 1) return simd::bits(simd::load<Float>(depth + first) == far);
    uint32_t bits = 0;
    for (int i = 0; i < kWidth; ++i)
        bits |= uint32_t(depth[(first + size_t(i)) * size_t(samples) + size_t(s)] == far) << i;
    return bits;
}

}  // namespace

void sky_rows(const SkyRows& sky, int first, int count) {
    namespace sdk = facet::sdk;
    static_assert(sdk::kLanes == kWidth);
    const sdk::Environment env(sky.environment);
    Framebuffer& fb = *sky.target;
    const int samples = fb.samples();
    const size_t bpp = bytes_per_pixel(fb.format());
    const float* depth =
        samples > 1 ? FramebufferAccess::sample_depth(fb) : FramebufferAccess::depth(fb);
    uint8_t* color =
        samples > 1 ? FramebufferAccess::sample_color(fb) : FramebufferAccess::color(fb);
    Float lane;
    for (int i = 0; i < kWidth; ++i) lane[i] = float(i) + 0.5f;
    for (int y = first; y < first + count; ++y) {
        const glm::vec3 row = sky.origin + sky.dy * (float(sky.first_row + y) + 0.5f);
        for (int x = 0; x < fb.width(); x += kWidth) {
            const size_t pixel = size_t(y) * size_t(fb.stride()) + size_t(x);
            uint32_t far[Framebuffer::kMaxSamples], any = 0;
            for (int s = 0; s < samples; ++s) any |= far[s] = far_lanes(depth, pixel, samples, s, sky.far_depth);
            if (!any) continue;
            const Float px = lane + float(x);
            const sdk::Vec3 d(row.x + px * sky.dx.x, row.y + px * sky.dx.y, row.z + px * sky.dx.z);
            const sdk::Vec3 c =
                sky.blur > 0.0f ? env.specular(d, sdk::splat(sky.blur)) : env.radiance(d, 0);
            if (samples == 1 && far[0] == (1u << kWidth) - 1u) {  // all sky: stored as packed
                pack(fb.format(), {c.x, c.y, c.z, Float{} + 1.0f}, color + pixel * bpp);
                continue;
            }
            Packed packed;
            pack(fb.format(), {c.x, c.y, c.z, Float{} + 1.0f}, packed.bytes);
            for (int s = 0; s < samples; ++s)
                for (uint32_t bits = far[s]; bits; bits &= bits - 1) {
                    const int i = __builtin_ctz(bits);
                    std::memcpy(color + ((pixel + size_t(i)) * size_t(samples) + size_t(s)) * bpp,
                                packed.bytes + size_t(i) * bpp, bpp);
                }
        }
    }
}

}  // namespace facet::FACET_KERNEL_NS
