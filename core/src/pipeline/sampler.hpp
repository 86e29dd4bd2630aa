// The texture sampler, once per instruction-set path (kernels.hpp).
//
// Takes a texture bound with a filter and a wrap, and texture coordinates
// for the 16 lanes of a fragment batch with a mask of the lanes to sample;
// gives linear RGBA, rgba[c * 16 + i], 0 at the other lanes (white at every
// lane of the mask where nothing is bound). It works a vector of lanes at a
// time: coordinates, wrap, level of detail, the gathers of the texels from
// the texture's tiled levels (facet/texture.hpp, TexelLevels), their decode
// and the filter weights. Nothing is read for a lane outside the mask.
//
// It computes what the scalar reference sampler of facet/texture.hpp
// (sample, sample_block) computes, in the same steps but filtering in
// 16-bit fixed point, and every path computes the same floats: tests
// (test_sampler.cpp) hold it to the reference within one 8-bit code, and
// every path to the same bits.
//   - nearest: the texel holding (u w, v h); bilinear: the four texels
//     around (u w - 1/2, v h - 1/2), weighted by the fractions; both on
//     level 0. A coordinate is pinned to +-2^23 texels, NaN to 0.
//   - trilinear: level of detail l from the lane's 2x2 quad (the ABI's
//     quads) as log2 of its longer footprint axis in level-0 texels, or
//     given per lane (sample_lod); the bilinear samples of levels floor(l)
//     and floor(l) + 1 mixed by the fraction, l within [0, levels - 1].
//   - anisotropic: the mean of up to the binding's anisotropy trilinear
//     samples along the longer axis of the lane's footprint, from the
//     quad's differences or given derivatives (anisotropic_footprint in
//     facet/texture.hpp); a part loops to its largest count.
//   - wraps: repeat, clamp to edge, mirrored repeat, each folding a
//     coordinate once.
//   - cube maps: the face of a direction's largest component, filtered as
//     a 2D texture clamped to its edges (texture.hpp, cube_face);
//     anisotropic as trilinear.
#pragma once

#ifndef FACET_KERNEL_NS
#error "sampler.hpp belongs to the per-ISA kernel sources (core/CMakeLists.txt)"
#endif

#include <cstdint>

#include "facet/texture.hpp"

namespace facet::FACET_KERNEL_NS {

// Level of detail from each 2x2 quad's differences of u and v (all 16
// lanes must hold coordinates).
void sample_block(const TextureBinding& binding, const float* u, const float* v, uint32_t mask,
                  float* rgba);

// `count` lanes (1 to 16) of `mask`, as facet_textures_service.sample
// and sample_grad take them: coords[k * count + i] (u, v; a cube map's
// direction x, y, z), a level of detail per lane (null: 0; nearest and
// bilinear read level 0 whatever it says), a 2D texture's derivatives
// grads[k * count + i] (du/dx, dv/dx, du/dy, dv/dy; null: none, and an
// anisotropic binding is then trilinear at `lod`), rgba[c * count + i].
void sample_lanes(const TextureBinding& binding, const float* coords, const float* lod,
                  const float* grads, uint32_t count, uint32_t mask, float* rgba);

}  // namespace facet::FACET_KERNEL_NS
