// The edges of a part's triangles, for its lines (Topology::lines) and its
// wire (PipelineState::wireframe): each edge with the triangles it bounds
// (two to a listing), so that the wire can draw an edge where one of them
// faces the eye. They are found once for each index list and kept
// (EdgeCache).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace facet {

constexpr uint32_t kNoTriangle = UINT32_MAX;

struct MeshEdge {
    uint32_t a, b;         // its end points (vertex indices), a < b
    // Two of the triangles that share it, as the position of each one's
    // first index in the list; kNoTriangle for a second that is not there.
    // An edge of more than two triangles (not a manifold) is listed again
    // for each two more, the listings side by side: ceil(n / 2) for n.
    uint32_t triangle[2];
};

// The edges of the triangles of `indices` (a multiple of three), in order
// of (a, b). A triangle's side whose ends are one vertex is no edge.
std::vector<MeshEdge> find_edges(const uint32_t* indices, size_t count);

// find_edges' answers, kept by the index lists they came from (compared
// whole, so a changed list is found again), the least recently asked
// dropped once they hold more than kBudget bytes. Not thread-safe: one per
// Pipeline, asked from the thread that queues draws.
class EdgeCache {
public:
    static constexpr size_t kBudget = size_t(256) << 20;

    // The edges of `indices`, valid until the next call.
    const std::vector<MeshEdge>& edges(const uint32_t* indices, size_t count);

private:
    struct Entry {
        uint64_t hash = 0;
        std::vector<uint32_t> indices;
        std::vector<MeshEdge> edges;
        uint64_t used = 0;  // when last asked for, by clock_
        size_t bytes() const;
    };
    std::vector<Entry> entries_;
    uint64_t clock_ = 0;
};

}  // namespace facet
