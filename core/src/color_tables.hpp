// Exact 8-bit sRGB by table, shared by the scalar codecs (framebuffer.cpp)
// and the per-ISA kernels (pixels.hpp).
//
// Encoding: code c starts at threshold[c], the least float whose exact
// sRGB encoding (in double precision) is at least (c - 0.5) / 255, so the
// code of x is the number of thresholds at or below it, minus one. To find
// it without a search, floats in [2^-13, 1) fall into buckets by their
// exponent and top 7 mantissa bits; a bucket is narrower than any code
// there (the curve's slope is at most 12.92), so it holds at most one
// threshold: the code is base[b], plus one when x reaches next[b]. Floats
// below 2^-13 all encode to 0 (threshold[1] is 1.5e-4).
#pragma once

#include <cstdint>

namespace facet {

struct Srgb8Tables {
    static constexpr int32_t kFirstBucket = 114 << 7;  // float bits of 2^-13, >> 16
    static constexpr int kBuckets = 13 << 7;           // up to 1.0

    Srgb8Tables();

    float threshold[257];     // threshold[256] is infinity
    float decode[256];        // code -> linear, correctly rounded
    int32_t base[kBuckets];   // the code of the bucket's first float
    float next[kBuckets];     // threshold[base + 1]
};

extern const Srgb8Tables kSrgb8;

}  // namespace facet
