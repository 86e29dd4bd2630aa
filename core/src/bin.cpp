#include "bin.hpp"

#include <algorithm>

namespace facet {

void Bins::resize(int width, int height) {
    width_ = width;
    height_ = height;
    columns_ = (width + kTileSize - 1) / kTileSize;
    rows_ = (height + kTileSize - 1) / kTileSize;
    // Only ever grows: a shadow map's many tiles keep their lists' storage
    // while the (smaller) main target uses the first few.
    if (tiles_.size() < size_t(columns_) * rows_) tiles_.resize(size_t(columns_) * rows_);
}

void Bins::bin(const std::vector<SetupChunk>& chunks, int count) {
    for (int c = 0; c < count; ++c) {
        const std::vector<TriangleSetup>& setups = chunks[size_t(c)].setups;
        for (size_t i = 0; i < setups.size(); ++i) {
            const TriangleSetup& t = setups[i];
            const uint32_t entry = uint32_t(c) << 16 | uint32_t(i);
            for (int ty = t.y0 / kTileSize; ty <= t.y1 / kTileSize; ++ty)
                for (int tx = t.x0 / kTileSize; tx <= t.x1 / kTileSize; ++tx) {
                    const int tile = ty * columns_ + tx;
                    std::vector<uint32_t>& list = tiles_[size_t(tile)];
                    if (list.empty()) busy_.push_back(tile);
                    list.push_back(entry);
                }
        }
    }
}

void Bins::clear() {
    for (int tile : busy_) tiles_[size_t(tile)].clear();
    busy_.clear();
}

void Bins::rect(int tile, int& x0, int& y0, int& x1, int& y1) const {
    x0 = (tile % columns_) * kTileSize;
    y0 = (tile / columns_) * kTileSize;
    x1 = std::min(x0 + kTileSize, width_) - 1;
    y1 = std::min(y0 + kTileSize, height_) - 1;
}

}  // namespace facet
