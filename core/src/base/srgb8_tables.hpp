// Exact 8-bit sRGB by table, shared by the scalar codecs (base/color.cpp)
// and the per-ISA kernels (pipeline/pixels.hpp).
//
// Encoding: code c starts at threshold[c], the least float whose exact
// sRGB encoding (in double precision) is at least (c - 0.5) / 255, so the
// code of x is the number of thresholds at or below it, minus one. To find
// it without a search, floats in [2^-13, 1) fall into buckets by their
// exponent and top 7 mantissa bits (the top 16 bits of the float); a
// bucket is narrower than any code there (the curve's slope is at most
// 12.92), so it holds at most one threshold, whose float shares those 16
// bits with every x in the bucket. So one 32-bit entry says it all: the
// code of the bucket's first float in its top bits, and the low 16 bits of
// the threshold (0x10000 when the bucket holds none) in its low 17, and
// the code of x is base + (low 16 bits of x >= those). Floats below 2^-13
// all encode to 0 (threshold[1] is 1.5e-4).
#pragma once

#include <cstdint>

namespace facet {

struct Srgb8Tables {
    static constexpr int32_t kFirstBucket = 114 << 7;  // float bits of 2^-13, >> 16
    static constexpr int kBuckets = (13 << 7) + 1;     // up to 1.0, and 1.0 itself

    Srgb8Tables();

    float threshold[257];     // threshold[256] is infinity
    float decode[256];        // code -> linear, correctly rounded
    int32_t bucket[kBuckets]; // base code << 17 | low bits of the next threshold
};

// The code of a float in [2^-13, 1) from its bucket's entry.
inline int32_t srgb8_from_bucket(int32_t entry, int32_t float_bits) {
    return (entry >> 17) + ((float_bits & 0xFFFF) >= (entry & 0x1FFFF));
}

extern const Srgb8Tables kSrgb8;

}  // namespace facet
