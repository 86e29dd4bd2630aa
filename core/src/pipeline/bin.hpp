// Binning.
//
// Takes: the triangles the queued draws set up, in submission order (chunk
// by chunk).
// Gives: for each 64x64 screen tile, the triangles whose bounding box
// touches it, in the same order: each chunk sorts its own setups by tile
// as it is set up (Bins::bin_chunk, in parallel, while they are in cache),
// and each tile keeps the chunks that touch it (Bins::gather). Tiles are
// then rasterized independently and in parallel; since every tile replays
// its triangles in submission order, each pixel sees the same sequence of
// triangles whatever the thread count, and the image is bit-identical.
#pragma once

#include "pipeline/clip.hpp"
#include "pipeline/setup.hpp"

#include "facet/pipeline.hpp"

#include <cstdint>
#include <deque>
#include <vector>

namespace facet {

constexpr int kTileShift = 6;
constexpr int kTileSize = 1 << kTileShift;

// Tiles across `pixels` (the last one may be cut short).
constexpr int tiles_across(int pixels) { return (pixels + kTileSize - 1) / kTileSize; }

// What one setup task produced. Chunks sit side by side and two threads
// fill neighbours at once: each has cache lines of its own, or their
// counters would bounce between the cores (false sharing).
struct alignas(64) SetupChunk {
    std::vector<TriangleSetup> setups;
    // Vertices of clipped triangles: a deque, so setups can point into it;
    // its first `clipped_used` elements are this batch's, the rest are kept
    // for reuse, so a steady frame allocates nothing.
    std::deque<ClipVertex> clipped;
    size_t clipped_used = 0;
    int draw = 0;                    // the queued draw (DrawQueue::draws) they belong to
    FrameStats stats;                // triangle counters
    // Its setups by tile (Bins::bin_chunk): tile k (tile0 <= k <= tile1,
    // row-major) is touched by setups[binned[i]] for i in [first[k -
    // tile0], first[k - tile0 + 1]), in order. tile1 < tile0: none.
    int tile0 = 0, tile1 = -1;
    std::vector<uint32_t> first;
    std::vector<uint16_t> binned;
    std::vector<uint64_t> touches;  // bin_chunk's scratch: tile << 32 | setup
};

class Bins {
public:
    // Sizes the tile grid for a width x height target.
    void resize(int width, int height);
    // Sorts a chunk's setups by the tiles they touch (SetupChunk::binned).
    // Reads only the grid: chunks may be binned in parallel.
    void bin_chunk(SetupChunk& chunk) const;
    // Gives each tile the binned chunks [0, count) that touch it.
    void gather(const std::deque<SetupChunk>& chunks, int count);
    // Tiles with work, the ones with the most triangles first (so that the
    // threads finish together rather than one waiting on a late big tile),
    // and clearing them for the next batch.
    const std::vector<int>& busy() const { return busy_; }
    void clear();

    // The chunks that touch tile `tile`, in order.
    const std::vector<uint32_t>& chunks(int tile) const { return tiles_[size_t(tile)]; }
    void rect(int tile, int& x0, int& y0, int& x1, int& y1) const;

private:
    int columns_ = 0, rows_ = 0, width_ = 0, height_ = 0;
    std::vector<std::vector<uint32_t>> tiles_;
    std::vector<uint32_t> counts_;  // each tile's triangles, for order_busy
    void order_busy();

    std::vector<int> busy_;
};

}  // namespace facet
