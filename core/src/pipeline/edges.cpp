// The edges of a part's triangles, and the cache that keeps them (edges.hpp).
#include "pipeline/edges.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

namespace facet {

std::vector<MeshEdge> find_edges(const uint32_t* indices, size_t count) {
    // Each side of each triangle as (its ends, low then high; its triangle),
    // sorted: the sides of one edge come together, by triangle.
    std::vector<std::pair<uint64_t, uint32_t>> sides;
    sides.reserve(count);
    for (size_t t = 0; t + 2 < count; t += 3)
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t a = indices[t + k], b = indices[t + (k + 1) % 3];
            if (a != b)
                sides.emplace_back(uint64_t(std::min(a, b)) << 32 | std::max(a, b), uint32_t(t));
        }
    std::sort(sides.begin(), sides.end());
    std::vector<MeshEdge> edges;
    edges.reserve(sides.size() / 2 + 1);
    for (size_t i = 0; i < sides.size();) {
        const uint64_t key = sides[i].first;
        // A triangle with a repeated corner, (a, b, a), has two sides on
        // one edge: it counts once.
        MeshEdge e{uint32_t(key >> 32), uint32_t(key), {sides[i].second, kNoTriangle}};
        for (++i; i < sides.size() && sides[i].first == key; ++i) {
            if (sides[i].second == e.triangle[0] || sides[i].second == e.triangle[1]) continue;
            if (e.triangle[1] == kNoTriangle) {
                e.triangle[1] = sides[i].second;
            } else {
                edges.push_back(e);
                e.triangle[0] = sides[i].second;
                e.triangle[1] = kNoTriangle;
            }
        }
        edges.push_back(e);
    }
    return edges;
}

namespace {

uint64_t hash_indices(const uint32_t* indices, size_t count) {
    uint64_t h = 0x9E3779B97F4A7C15ull ^ count;
    for (size_t i = 0; i < count; ++i) {
        h = (h ^ indices[i]) * 0xFF51AFD7ED558CCDull;
        h ^= h >> 29;
    }
    return h;
}

}  // namespace

size_t EdgeCache::Entry::bytes() const {
    return indices.size() * sizeof(uint32_t) + edges.size() * sizeof(MeshEdge);
}

const std::vector<MeshEdge>& EdgeCache::edges(const uint32_t* indices, size_t count) {
    const uint64_t hash = hash_indices(indices, count);
    ++clock_;
    for (Entry& e : entries_)
        if (e.hash == hash && e.indices.size() == count &&
            std::equal(indices, indices + count, e.indices.begin())) {
            e.used = clock_;
            return e.edges;
        }
    Entry fresh;
    fresh.hash = hash;
    fresh.indices.assign(indices, indices + count);
    fresh.edges = find_edges(indices, count);
    fresh.used = clock_;
    // The least recently asked go while the rest are over budget.
    size_t total = fresh.bytes();
    for (const Entry& e : entries_) total += e.bytes();
    while (total > kBudget && !entries_.empty()) {
        auto oldest = std::min_element(entries_.begin(), entries_.end(),
                                       [](const Entry& x, const Entry& y) { return x.used < y.used; });
        total -= oldest->bytes();
        entries_.erase(oldest);
    }
    entries_.push_back(std::move(fresh));
    return entries_.back().edges;
}

}  // namespace facet
