// The shadow pass's kernel (kernels.hpp): a shadow map's window depths as
// 16-bit distances from the light (facet_shadow_distances), kWidth texels
// at a time; one of the per-ISA kernel sources.
#include "pipeline/kernels.hpp"
#include "base/simd.hpp"

namespace facet::FACET_KERNEL_NS {

using simd::Float;
using simd::Int;
using simd::kWidth;

// Distance along the light's axis, as (distance - near) / (far - near) *
// 65535 rounded up, so that a receiver at a caster's own distance reads as
// lit; 65535 where nothing was drawn (depth 1). An orthographic map's window
// depth is that fraction already. A perspective depth z is distance
// n f / (f (1 - z) + n z): 1 - z is exact where z is near 1, so the
// distance stays within a few units in the last place, below the 16-bit
// step. Every path does the same IEEE operations: the same texels.
void shadow_distance_rows(const ShadowDistanceRows& r, int first, int count) {
    using U16 = uint16_t __attribute__((vector_size(2 * kWidth)));
    const float n = r.near_plane, f = r.far_plane, scale = 65535.0f / (f - n);
    for (int y = first; y < first + count; ++y) {
        const float* depth = r.depth + size_t(y) * size_t(r.depth_stride);
        uint16_t* out = r.distances + size_t(y) * size_t(r.distance_stride);
        for (int x = 0; x < r.width; x += kWidth) {
            const Float z = simd::load<Float>(depth + x);
            Float q = r.orthographic ? z * 65535.0f : (n * f / (f * (1.0f - z) + n * z) - n) * scale;
            q = q < 0.0f ? 0.0f : q > 65535.0f ? 65535.0f : q;
            const Int whole = __builtin_convertvector(q, Int);  // q >= 0: the floor
            const Int up = whole - (simd::to_float(whole) < q);  // a comparison is 0 or -1
            simd::store(out + x, __builtin_convertvector(up, U16));
        }
    }
}

}  // namespace facet::FACET_KERNEL_NS
