// The Kernels table of one instruction-set path (kernels.hpp), and the tile
// loop that joins rasterization to the fragment stage.
#include "pipeline/kernels.hpp"

#include "pipeline/draw_queue.hpp"
#include "pipeline/framebuffer_access.hpp"
#include "pipeline/fragment.hpp"
#include "pipeline/narrow_coverage.hpp"
#include "pipeline/pixels.hpp"
#include "pipeline/rasterize.hpp"
#include "pipeline/sampler.hpp"

namespace facet::FACET_KERNEL_NS {

void ao_position_rows(const AoFrame& f, int first, int count);  // ao_kernels.cpp
void ao_normal_rows(const AoFrame& f, int first, int count);
void ao_occlusion_rows(const AoFrame& f, int first, int count, int x_first,
                       int x_count);  // ao_kernels.cpp
void ao_blur_rows(const AoFrame& f, int first, int count);
void shadow_distance_rows(const ShadowDistanceRows& rows, int first, int count);  // shadow_kernels.cpp
void shadow_plane_rows(const ShadowPlaneRows& rows, int first, int count);
void sky_rows(const SkyRows& sky, int first, int count);  // sky_kernels.cpp
void project_vertices(const glm::vec4* clip, size_t count, const Viewport& viewport,
                      WindowVertex* out);  // project_kernels.cpp
size_t assemble_triangles(const WideAssembly& a, const uint32_t* idx, size_t count,
                          SetupChunk& chunk);  // assembly_kernels.cpp

namespace {

// Calls visit(const Block&) for every block of t's coverage within the
// tile [x0, x1] x [y0, y1]: by NarrowCoverage for a narrow triangle at one
// sample a pixel (nearly every one), else by BlockCoverage (`width` as it
// takes it), the same blocks either way.
template <class Visit>
void for_each_covered_block(const TriangleSetup& t, int samples, EdgeWidth width, int x0, int y0,
                            int x1, int y1, Visit&& visit) {
    if (samples == 1 && t.narrow && width == EdgeWidth::automatic) {
        const NarrowCoverage cover(t);
        Block block;
        cover.for_each_block(x0, y0, x1, y1, [&](int bx, int by, uint32_t mask, const int64_t* e) {
            cover.fill(bx, by, mask, e, block);
            visit(block);
        });
        return;
    }
    rasterize(BlockCoverage(t, samples, width), t, x0, y0, x1, y1, visit);
}

// One of a tile's triangles: rasterized and shaded, or (a narrow one of a
// depth_only draw) its depth drawn.
void draw_triangle(const DrawContext& dc, bool depth_only_draw, const TriangleSetup& t,
                   int samples, int x0, int y0, int x1, int y1, PackedBatch& packed, TileAo& ao,
                   FrameStats& stats) {
    if (depth_only_draw && t.narrow) {  // one sample a pixel (depth_only)
        if (!packed.empty()) packed.flush(stats);  // what came first is written first
        draw_depth_only(dc, NarrowCoverage(t), t, x0, y0, x1, y1, stats);
        return;
    }
    TriangleVaryings tv;
    bool prepared = false;  // many triangles cover nothing in a tile
    for_each_covered_block(t, samples, EdgeWidth::automatic, x0, y0, x1, y1, [&](const Block& b) {
        if (!prepared) prepare_varyings(dc, t, tv);
        prepared = true;
        shade_block(dc, t, tv, b, packed, ao, stats);
    });
}

// Rasterizes and shades one tile's triangles, in submission order: chunk
// by chunk, and in each its setups that touch the tile (bin.hpp).
void draw_tile(const DrawQueue& g, int tile, FrameStats& stats) {
    int x0, y0, x1, y1;
    g.bins.rect(tile, x0, y0, x1, y1);
    const int samples = g.target->samples();
    // The tile no longer holds what the target's last clear wrote (each
    // tile is one thread's: no two threads write the same byte).
    std::vector<uint8_t>& held = FramebufferAccess::cleared(*g.target).held;
    if (size_t(tile) < held.size()) held[size_t(tile)] = 0;
    if (PendingClear* c = g.clear_now; c && !c->cleared[size_t(tile)]) {
        int cx0, cy0, cx1, cy1;
        c->storage_rect(tile, cx0, cy0, cx1, cy1);
        clear_rect(*g.target, cx0, cy0, cx1, cy1, c->color, c->depth, c->stencil, false);
        c->cleared[size_t(tile)] = 1;
    }
    PackedBatch packed;
    alignas(64) static thread_local float visibility[kTileSize * kTileSize];  // the tile's AO
    TileAo ao{x0, y0, x1, y1, false, visibility};
    for (const uint32_t c : g.bins.chunks(tile)) {
        const SetupChunk& chunk = g.chunks[c];
        const DrawContext& dc = g.draws[size_t(chunk.draw)]->dc;
        const bool depth_only_draw = depth_only(dc);
        const uint32_t* range = chunk.first.data() + (tile - chunk.tile0);
        for (uint32_t i = range[0]; i < range[1]; ++i)
            draw_triangle(dc, depth_only_draw, chunk.setups[chunk.binned[i]], samples, x0, y0, x1,
                          y1, packed, ao, stats);
    }
    packed.flush(stats);
}

void cover(const TriangleSetup& t, int x0, int y0, int x1, int y1, int samples, EdgeWidth width,
           std::vector<Block>& out) {
    for_each_covered_block(t, samples, width, x0, y0, x1, y1,
                           [&](const Block& b) { out.push_back(b); });
}

}  // namespace

}  // namespace facet::FACET_KERNEL_NS

extern "C" const facet::Kernels FACET_KERNEL_TABLE = {
    facet::Isa::FACET_KERNEL_ISA,
    &facet::FACET_KERNEL_NS::project_vertices,
    &facet::FACET_KERNEL_NS::assemble_triangles,
    &facet::FACET_KERNEL_NS::draw_tile,
    &facet::FACET_KERNEL_NS::cover,
    &facet::FACET_KERNEL_NS::clear_rect,
    &facet::FACET_KERNEL_NS::resolve_rows,
    &facet::FACET_KERNEL_NS::srgb8_rows,
    &facet::FACET_KERNEL_NS::encode_pixels,
    &facet::FACET_KERNEL_NS::decode_pixels,
    &facet::FACET_KERNEL_NS::ao_position_rows,
    &facet::FACET_KERNEL_NS::ao_normal_rows,
    &facet::FACET_KERNEL_NS::ao_occlusion_rows,
    &facet::FACET_KERNEL_NS::ao_blur_rows,
    &facet::FACET_KERNEL_NS::ao_upsample_rows,
    &facet::FACET_KERNEL_NS::shadow_distance_rows,
    &facet::FACET_KERNEL_NS::shadow_plane_rows,
    &facet::FACET_KERNEL_NS::sample_block,
    &facet::FACET_KERNEL_NS::sample_lanes,
    &facet::FACET_KERNEL_NS::sky_rows,
};
