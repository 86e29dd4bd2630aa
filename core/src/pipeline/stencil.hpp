// The stencil test and its operations (one of the per-ISA kernels,
// kernels.hpp), for a draw whose PipelineState::stencil is on and whose
// target has a stencil buffer (DrawContext::stencil).
//
// GL's per-fragment order, sample by sample: the stencil test of the
// facing's state, (reference & read_mask) against (stored & read_mask);
// where it fails, the `fail` operation and nothing more; where it passes,
// the depth test, then `depth_fail` or `pass`. Each operation changes only
// the bits of the write mask. A fragment that passes both goes on to be
// written (its depth where the draw writes depth, its colour). The rules
// for one value are stencil_ops.hpp's.
//
// The fragment stage tests before shading, or after it where the shader
// may discard or its alpha picks samples: then only what the shader kept
// is tested, and so changes the stencil (fragment.cpp).
#pragma once

#include "pipeline/fragment.hpp"

namespace facet::FACET_KERNEL_NS {

// For each lane i of `lanes` of block b of triangle t: its samples in
// sd.passed[i] (with one sample a pixel, bit 0) tested and the stencil
// written; sd.passed[i] then holds those that passed both tests, and
// sd.z their depths. Gives the lanes with a sample that passed.
uint32_t stencil_depth_test(const DrawContext& dc, const TriangleSetup& t, const Block& b,
                            uint32_t lanes, SampleDepth& sd);

}  // namespace facet::FACET_KERNEL_NS
