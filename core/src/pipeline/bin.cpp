#include "pipeline/bin.hpp"

#include <algorithm>
#include <cstdint>

namespace facet {

namespace {

// Can the triangle cover any sample in pixels [x0, x1] x [y0, y1]? False
// when one edge is negative over the whole rectangle (its best corner, on
// the pixels' outer boundary, so MSAA samples are included).
bool overlaps(const TriangleSetup& t, int x0, int y0, int x1, int y1) {
    const int64_t left = int64_t(x0) * kSubpixelOne, right = int64_t(x1 + 1) * kSubpixelOne;
    const int64_t top = int64_t(y0) * kSubpixelOne, bottom = int64_t(y1 + 1) * kSubpixelOne;
    for (const EdgeFunction& e : t.edge) {
        // E grows with x when dy < 0 and with y when dx > 0.
        const int64_t x = e.dy < 0 ? right : left, y = e.dx > 0 ? bottom : top;
        if (e.at(x, y) + e.bias < 0) return false;
    }
    return true;
}

}  // namespace

void Bins::resize(int width, int height) {
    width_ = width;
    height_ = height;
    columns_ = tiles_across(width);
    rows_ = tiles_across(height);
    // Only ever grows: a shadow map's many tiles keep their lists' storage
    // while the (smaller) main target uses the first few.
    if (tiles_.size() < size_t(columns_) * rows_) {
        tiles_.resize(size_t(columns_) * rows_);
        counts_.resize(size_t(columns_) * rows_);
    }
}

void Bins::bin_chunk(SetupChunk& chunk) const {
    // Each (tile, setup) a setup touches, in order, then a counting sort of
    // them by tile over the range of tiles the chunk touches.
    std::vector<uint64_t>& touches = chunk.touches;
    touches.clear();
    int lo = INT32_MAX, hi = -1;
    const std::vector<TriangleSetup>& setups = chunk.setups;
    const auto touch = [&](int tile, size_t i) {
        touches.push_back(uint64_t(tile) << 32 | i);
        lo = std::min(lo, tile);
        hi = std::max(hi, tile);
    };
    for (size_t i = 0; i < setups.size(); ++i) {
        const TriangleSetup& t = setups[i];
        // A box is never left of or above the target: its corners are not
        // negative, so a shift divides them.
        const int tx0 = t.x0 >> kTileShift, tx1 = t.x1 >> kTileShift;
        const int ty0 = t.y0 >> kTileShift, ty1 = t.y1 >> kTileShift;
        if (tx0 == tx1 && ty0 == ty1) {  // most triangles
            touch(ty0 * columns_ + tx0, i);
            continue;
        }
        for (int ty = ty0; ty <= ty1; ++ty)
            for (int tx = tx0; tx <= tx1; ++tx)
                // Large triangles skip the tiles of their box they miss.
                if (overlaps(t, tx * kTileSize, ty * kTileSize, tx * kTileSize + kTileSize - 1,
                             ty * kTileSize + kTileSize - 1))
                    touch(ty * columns_ + tx, i);
    }
    chunk.tile0 = lo;
    chunk.tile1 = hi;
    if (hi < lo) return;
    chunk.first.assign(size_t(hi - lo + 2), 0u);
    for (const uint64_t e : touches) ++chunk.first[size_t((e >> 32) - uint64_t(lo)) + 1];
    for (size_t k = 1; k < chunk.first.size(); ++k) chunk.first[k] += chunk.first[k - 1];
    chunk.binned.resize(touches.size());
    // Each setup to the next place of its tile, which moves each tile's
    // start to the next one's; then back by one tile.
    for (const uint64_t e : touches)
        chunk.binned[chunk.first[size_t((e >> 32) - uint64_t(lo))]++] = uint16_t(e);
    std::copy_backward(chunk.first.begin(), chunk.first.end() - 1, chunk.first.end());
    chunk.first[0] = 0;
}

void Bins::gather(const std::deque<SetupChunk>& chunks, int count) {
    for (int c = 0; c < count; ++c) {
        const SetupChunk& chunk = chunks[size_t(c)];
        for (int tile = chunk.tile0; tile <= chunk.tile1; ++tile) {
            const uint32_t* first = chunk.first.data() + (tile - chunk.tile0);
            if (first[1] == first[0]) continue;
            std::vector<uint32_t>& list = tiles_[size_t(tile)];
            if (list.empty()) busy_.push_back(tile);
            list.push_back(uint32_t(c));
            counts_[size_t(tile)] += first[1] - first[0];
        }
    }
    order_busy();
}

// The tiles with the most triangles first (ties by index: any order draws
// the same image, tiles being independent). std::sort allocates nothing.
void Bins::order_busy() {
    std::sort(busy_.begin(), busy_.end(), [&](int a, int b) {
        const uint32_t na = counts_[size_t(a)], nb = counts_[size_t(b)];
        return na != nb ? na > nb : a < b;
    });
}

void Bins::clear() {
    for (int tile : busy_) {
        tiles_[size_t(tile)].clear();
        counts_[size_t(tile)] = 0;
    }
    busy_.clear();
}

void Bins::rect(int tile, int& x0, int& y0, int& x1, int& y1) const {
    x0 = (tile % columns_) * kTileSize;
    y0 = (tile / columns_) * kTileSize;
    x1 = std::min(x0 + kTileSize, width_) - 1;
    y1 = std::min(y0 + kTileSize, height_) - 1;
}

}  // namespace facet
