// wide.hpp's loads built for one instruction-set path (tests/CMakeLists.txt
// compiles this file once per path beyond the baseline, naming the function
// FACET_WIDE_LOADS), so that test_wide.cpp can hold each path's
// intrinsics to plain indexing.
#include <facet/wide.hpp>

#include <cstdint>

using namespace facet::sdk::wide;

// For lanes 0 .. n - 1 (n a multiple of 16), with index[i] the lane's index:
// records[k * n + i], gather4's float k of lane i; gathered[i], gather's
// base[index[i]] for even i and -1 for odd i; quads[i / 2], gather_quads'
// 64 bits at texels + index[i] for even i; mixed[k * n + i], bilinear4's
// component k of lane i for the 2x2 records at index[i] % 225 and `row`
// floats on, at fractions fx[i], fy[i]. Returns the path's lane count.
extern "C" int FACET_WIDE_LOADS(const float* base, const uint16_t* texels, const int32_t* index,
                                int n, float* records, float* gathered, uint64_t* quads,
                                const float* fx, const float* fy, int row, float* mixed) {
    for (int first = 0; first < n; first += kLanes) {
        Mask at, even, top;
        Float x, y;
        HalfIndex half;
        for (int i = 0; i < kLanes; ++i) {
            at[i] = index[first + i], even[i] = i % 2 ? 0 : -1, top[i] = at[i] % 225;
            x[i] = fx[first + i], y[i] = fy[first + i];
        }
        for (int i = 0; i < kLanes / 2; ++i) half[i] = index[first + 2 * i];
        Float r[4];
        gather4(base, at, r);
        const Float g = gather(base, at, even, -1.0f);
        const Quads q = gather_quads(texels, half);
        Float m[4];
        bilinear4(base, top, top + row, x, y, m);
        for (int i = 0; i < kLanes; ++i) {
            for (int k = 0; k < 4; ++k) {
                records[k * n + first + i] = r[k][i];
                mixed[k * n + first + i] = m[k][i];
            }
            gathered[first + i] = g[i];
        }
        for (int i = 0; i < kLanes / 2; ++i) quads[(first + 2 * i) / 2] = q[i];
    }
    return kLanes;
}
