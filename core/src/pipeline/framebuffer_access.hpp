// The core's own access to a Framebuffer's storage (private to the core).
//
// The same pointers as Framebuffer's non-const accessors, without telling
// the framebuffer that its caller writes it (which would end what the
// pipeline knows of its contents, Framebuffer::ClearedTiles), and that
// knowledge itself. Whoever writes through these keeps it true: a tile's
// draw marks its tile (draw_tile), a clear records what it wrote
// (complete_clears in pipeline.cpp), and anything else that writes a
// target (the sky, an MSAA resolve, the post chain) calls forget_cleared()
// first, on the calling thread, before its rows are shared out.
#pragma once

#include "facet/framebuffer.hpp"

#include <cstdint>

namespace facet {

struct FramebufferAccess {
    using ClearedTiles = Framebuffer::ClearedTiles;

    static uint8_t* color(Framebuffer& fb) { return fb.color_.data(); }
    static uint8_t* sample_color(Framebuffer& fb) { return fb.sample_color_.data(); }
    static float* depth(Framebuffer& fb) { return fb.depth_.data(); }
    static float* sample_depth(Framebuffer& fb) { return fb.sample_depth_.data(); }
    static uint8_t* stencil(Framebuffer& fb) { return fb.stencil_.data(); }
    static uint8_t* sample_stencil(Framebuffer& fb) { return fb.sample_stencil_.data(); }

    // The tiles known to hold a clear; nothing is known once a caller has
    // asked for writable storage.
    static ClearedTiles& cleared(Framebuffer& fb) { return fb.cleared_; }
    static bool known(const Framebuffer& fb) { return !fb.caller_writes_.set; }
    static void forget_cleared(Framebuffer& fb) { fb.cleared_.held.clear(); }
};

}  // namespace facet
