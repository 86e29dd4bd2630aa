// GL's stencil test and operations on one stored value (glStencilFunc,
// glStencilOp, glStencilMask): the rules the fragment stage applies sample
// by sample (stencil.cpp), and tests check.
#pragma once

#include "facet/render_state.hpp"

#include <cstdint>

namespace facet {

// Whether (reference & read_mask) compares so with (stored & read_mask).
inline bool stencil_passes(StencilCompare compare, uint8_t reference, uint8_t stored,
                           uint8_t read_mask) {
    const int r = reference & read_mask, s = stored & read_mask;
    switch (compare) {
        case StencilCompare::never: return false;
        case StencilCompare::less: return r < s;
        case StencilCompare::less_equal: return r <= s;
        case StencilCompare::greater: return r > s;
        case StencilCompare::greater_equal: return r >= s;
        case StencilCompare::equal: return r == s;
        case StencilCompare::not_equal: return r != s;
        case StencilCompare::always: return true;
    }
    return false;
}

// `stored` after operation `op`, only the bits of `write_mask` changed.
inline uint8_t stencil_after(StencilOp op, uint8_t stored, uint8_t reference,
                             uint8_t write_mask) {
    uint8_t v = stored;
    switch (op) {
        case StencilOp::keep: return stored;
        case StencilOp::zero: v = 0; break;
        case StencilOp::replace: v = reference; break;
        case StencilOp::increment: v = stored == 0xFF ? stored : uint8_t(stored + 1); break;
        case StencilOp::increment_wrap: v = uint8_t(stored + 1); break;
        case StencilOp::decrement: v = stored == 0 ? stored : uint8_t(stored - 1); break;
        case StencilOp::decrement_wrap: v = uint8_t(stored - 1); break;
        case StencilOp::invert: v = uint8_t(~stored); break;
    }
    return uint8_t((stored & ~write_mask) | (v & write_mask));
}

}  // namespace facet
