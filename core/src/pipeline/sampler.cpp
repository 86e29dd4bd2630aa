// The per-path texture sampler (sampler.hpp): a vector of lanes at a time.
#include "pipeline/sampler.hpp"

#include "pipeline/texel_filters.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

namespace facet::FACET_KERNEL_NS {

namespace {

using namespace texel_filters;

// Every part with a lane in `mask` of a nearest, bilinear or trilinear
// binding, with its levels of detail from `lod` or, where that is null,
// from the quads.
template <TexelFormat F, Wrap W>
void sample_parts(const TexelLevels& t, Filter filter, const float* u, const float* v,
                  const float* lod, uint32_t mask, float* rgba) {
    const Quad lods =
        filter == Filter::trilinear && !lod ? block_lods(t, block_derivatives(u, v)) : Quad{};
    for (int p = 0; p < kParts; ++p) {
        const uint32_t lanes = simd::part_mask(mask, p);
        if (!lanes) {
            store(rgba, p, Texels{}, Int{});
            continue;
        }
        const Int active = active_lanes(lanes);
        const Float fu = fold<W>(simd::load<Float>(u + p * kWidth));
        const Float fv = fold<W>(simd::load<Float>(v + p * kWidth));
        switch (filter) {
            case Filter::nearest:
                store(rgba, p, nearest<F, W>(t, level_at(t, 0), fu, fv, active), active);
                break;
            case Filter::bilinear:
                store(rgba, p, unfixed<F>(bilinear<F, W>(t, level_at(t, 0), fu, fv, active)),
                      active);
                break;
            default: {  // trilinear
                const Float l = lod ? simd::load<Float>(lod + p * kWidth) : per_lane(lods, p);
                store(rgba, p, trilinear<F, W>(t, l, fu, fv, active), active);
                break;
            }
        }
    }
}

// A cube's lanes: directions x, y, z, levels of detail lod (null: 0).
template <TexelFormat F>
void sample_cube_parts(const TexelLevels& t, Filter filter, const float* x, const float* y,
                       const float* z, const float* lod, uint32_t mask, float* rgba) {
    for (int p = 0; p < kParts; ++p) {
        const uint32_t lanes = simd::part_mask(mask, p);
        if (!lanes) {
            store(rgba, p, Texels{}, Int{});
            continue;
        }
        const Int active = active_lanes(lanes);
        const auto at = [&](const float* a) { return simd::load<Float>(a + p * kWidth); };
        Float u, v;
        const Int face = cube_faces(at(x), at(y), at(z), t.levels, u, v);
        constexpr Wrap W = Wrap::clamp;  // each face filtered on its own
        if (filter == Filter::nearest)
            store(rgba, p, nearest<F, W>(t, level_at(t, face), u, v, active), active);
        else if (filter == Filter::bilinear)
            store(rgba, p, unfixed<F>(bilinear<F, W>(t, level_at(t, face), u, v, active)), active);
        else  // trilinear, and anisotropic, which a cube map filters as trilinear
            store(rgba, p, trilinear<F, W>(t, lod ? at(lod) : Float{}, u, v, active, face), active);
    }
}

template <TexelFormat F>
FACET_INLINE void sample_format(const TexelLevels& t, const TextureBinding& b, const Lanes& in,
                                uint32_t mask, float* rgba) {
    switch (b.wrap) {
        case Wrap::repeat:
            return sample_parts<F, Wrap::repeat>(t, b.filter, in.u, in.v, in.lod, mask, rgba);
        case Wrap::clamp:
            return sample_parts<F, Wrap::clamp>(t, b.filter, in.u, in.v, in.lod, mask, rgba);
        case Wrap::mirror:
            return sample_parts<F, Wrap::mirror>(t, b.filter, in.u, in.v, in.lod, mask, rgba);
    }
}

// 16 lanes: coordinates x, y (u, v) or, for a cube, x, y, z (a direction),
// levels of detail `lod` and a 2D texture's derivatives `grads` ([4][16]:
// du/dx, dv/dx, du/dy, dv/dy; both null: from the quads; a cube's level
// null: 0). A cube with no z (sample_block: a slot at a UV varying, which
// descriptors refuse for cubes) reads as nothing bound.
void sample(const TextureBinding& b, const float* x, const float* y, const float* z,
            const float* lod, const float* grads, uint32_t mask, float* rgba) {
    const TexelLevels* t = b.texture ? &b.texture->sampled() : nullptr;
    if (!t || t->levels == 0 || (t->faces == 6 && !z)) {  // nothing bound reads as white
        for (int k = 0; k < 4; ++k)
            for (int i = 0; i < N; ++i) rgba[k * N + i] = mask >> i & 1u ? 1.0f : 0.0f;
        return;
    }
    const bool wide = t->format == TexelFormat::rgba16;
    if (t->faces == 6) {
        if (wide)
            sample_cube_parts<TexelFormat::rgba16>(*t, b.filter, x, y, z, lod, mask, rgba);
        else
            sample_cube_parts<TexelFormat::rgba8>(*t, b.filter, x, y, z, lod, mask, rgba);
    } else if (b.filter == Filter::anisotropic) {
        sample_anisotropic(*t, b, {x, y, lod, grads}, mask, rgba);
    } else if (wide) {
        sample_format<TexelFormat::rgba16>(*t, b, {x, y, lod, grads}, mask, rgba);
    } else {
        sample_format<TexelFormat::rgba8>(*t, b, {x, y, lod, grads}, mask, rgba);
    }
}

}  // namespace

void sample_block(const TextureBinding& binding, const float* u, const float* v, uint32_t mask,
                  float* rgba) {
    sample(binding, u, v, nullptr, nullptr, nullptr, mask, rgba);
}

void sample_lanes(const TextureBinding& binding, const float* coords, const float* lod,
                  const float* grads, uint32_t count, uint32_t mask, float* rgba) {
    count = std::min(count, uint32_t(N));
    mask &= (1u << count) - 1u;
    const bool cube = binding.texture && binding.texture->faces == 6;
    const int components = cube ? 3 : 2;
    float c[3 * N] = {}, l[N] = {}, d[4 * N] = {}, out[4 * N];
    for (int k = 0; k < components; ++k) std::memcpy(c + k * N, coords + k * count, sizeof(float) * count);
    if (lod) std::memcpy(l, lod, sizeof(float) * count);
    if (grads && !cube)
        for (int k = 0; k < 4; ++k) std::memcpy(d + k * N, grads + k * count, sizeof(float) * count);
    sample(binding, c, c + N, c + 2 * N, l, grads && !cube ? d : nullptr, mask, out);
    for (int k = 0; k < 4; ++k) std::memcpy(rgba + k * count, out + k * N, sizeof(float) * count);
}

}  // namespace facet::FACET_KERNEL_NS
