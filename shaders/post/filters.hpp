// Image filters the built-in screen passes share: separable convolutions
// (Gaussian weights, box sums), 2x box downsampling and bilinear 2x
// upsampling, on images of linear RGBA floats. Edges clamp: a tap past
// the image reads its nearest edge pixel.
//
// An Image is a view (pixels, size, row stride); the functions write `to`
// from `from`, which must be different images of the same size (the
// resampling ones excepted), and share rows or columns out to the frame's
// threads.
#pragma once

#include <facet/post.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace facet::post {

// A pixel in one SSE register (GCC and Clang vector extensions): glm::vec4
// arithmetic compiles to four scalar operations.
using V4 = float __attribute__((vector_size(16)));
inline V4 load(const glm::vec4& p) {
    V4 v;
    std::memcpy(&v, &p, sizeof v);
    return v;
}
inline void store(glm::vec4& p, V4 v) { std::memcpy(&p, &v, sizeof v); }

struct Image {
    glm::vec4* pixels = nullptr;
    int width = 0, height = 0, stride = 0;
    glm::vec4* row(int y) const { return pixels + size_t(y) * size_t(stride); }
};

// The frame's own image.
inline Image frame_image(const sdk::PostFrame& f) {
    return {f.row(0), f.width(), f.height(), f.stride()};
}

// A width x height image in scratch slot `slot`; pixels null if refused.
inline Image scratch_image(const sdk::PostFrame& f, int slot, int width, int height) {
    return {f.scratch<glm::vec4>(slot, size_t(width) * size_t(height)), width, height, width};
}

// The weights of a Gaussian of standard deviation sigma (pixels) at taps
// -R..R, R = ceil(3 sigma), normalised to sum to 1: w[R + k].
inline std::vector<float> gaussian_weights(float sigma) {
    const int radius = std::max(1, int(std::ceil(3.0f * sigma)));
    std::vector<double> w(size_t(2 * radius + 1));
    double sum = 0.0;
    for (int k = -radius; k <= radius; ++k)
        sum += w[size_t(k + radius)] = std::exp(-double(k) * k / (2.0 * double(sigma) * sigma));
    std::vector<float> out(w.size());
    for (size_t i = 0; i < w.size(); ++i) out[i] = float(w[i] / sum);
    return out;
}

// to(x, y) = sum over k of w[R + k] from(clamp(x + k), y): along rows.
inline void convolve_rows(const sdk::PostFrame& f, const Image& from, const Image& to,
                          const std::vector<float>& w) {
    const int radius = int(w.size() / 2), width = from.width;
    f.for_rows(from.height, [&](int y) {
        const glm::vec4* src = from.row(y);
        glm::vec4* dst = to.row(y);
        for (int x = 0; x < width; ++x) {
            V4 sum = {0.0f, 0.0f, 0.0f, 0.0f};
            if (x >= radius && x + radius < width) {  // no tap past an edge
                for (int k = -radius; k <= radius; ++k) sum += w[size_t(k + radius)] * load(src[x + k]);
            } else {
                for (int k = -radius; k <= radius; ++k)
                    sum += w[size_t(k + radius)] * load(src[std::clamp(x + k, 0, width - 1)]);
            }
            store(dst[x], sum);
        }
    });
}

// to(x, y) = sum over k of w[R + k] from(x, clamp(y + k)): along columns,
// a row at a time (each tap a whole row, so the loop runs along memory).
inline void convolve_columns(const sdk::PostFrame& f, const Image& from, const Image& to,
                             const std::vector<float>& w) {
    const int radius = int(w.size() / 2), width = from.width, height = from.height;
    f.for_rows(height, [&](int y) {
        glm::vec4* dst = to.row(y);
        std::fill(dst, dst + width, glm::vec4(0.0f));
        for (int k = -radius; k <= radius; ++k) {
            const glm::vec4* src = from.row(std::clamp(y + k, 0, height - 1));
            const float wk = w[size_t(k + radius)];
            for (int x = 0; x < width; ++x) store(dst[x], load(dst[x]) + wk * load(src[x]));
        }
    });
}

// The mean of the 2 radius + 1 pixels around each, along rows, by a
// running sum (kept in double, so that its rounding does not build up
// along a row). A value that is not finite counts as 0: in a running sum it
// would spoil the rest of the row.
inline glm::dvec4 finite_or_zero(const glm::vec4& p) {
    glm::dvec4 d(p);
    for (int c = 0; c < 4; ++c) d[c] = std::isfinite(d[c]) ? d[c] : 0.0;
    return d;
}
inline void box_rows(const sdk::PostFrame& f, const Image& from, const Image& to, int radius) {
    const int width = from.width;
    const double scale = 1.0 / double(2 * radius + 1);
    f.for_rows(from.height, [&](int y) {
        const glm::vec4* src = from.row(y);
        glm::vec4* dst = to.row(y);
        const auto at = [&](int x) { return finite_or_zero(src[std::clamp(x, 0, width - 1)]); };
        glm::dvec4 sum(0.0);
        for (int k = -radius; k <= radius; ++k) sum += at(k);
        for (int x = 0; x < width; ++x) {
            dst[x] = glm::vec4(sum * scale);
            sum += at(x + radius + 1) - at(x - radius);
        }
    });
}

// The same along columns: bands of 64 columns, each walked down the image
// with a running sum per column.
inline void box_columns(const sdk::PostFrame& f, const Image& from, const Image& to, int radius) {
    constexpr int kBand = 64;
    const int width = from.width, height = from.height;
    const double scale = 1.0 / double(2 * radius + 1);
    f.parallel_for((width + kBand - 1) / kBand, [&](int band, int) {
        const int x0 = band * kBand, n = std::min(kBand, width - x0);
        glm::dvec4 sum[kBand];
        const auto row = [&](int y) { return from.row(std::clamp(y, 0, height - 1)) + x0; };
        for (int i = 0; i < n; ++i) sum[i] = glm::dvec4(0.0);
        for (int k = -radius; k <= radius; ++k)
            for (int i = 0; i < n; ++i) sum[i] += finite_or_zero(row(k)[i]);
        for (int y = 0; y < height; ++y) {
            glm::vec4* dst = to.row(y) + x0;
            const glm::vec4* in = row(y + radius + 1);
            const glm::vec4* out = row(y - radius);
            for (int i = 0; i < n; ++i) {
                dst[i] = glm::vec4(sum[i] * scale);
                sum[i] += finite_or_zero(in[i]) - finite_or_zero(out[i]);
            }
        }
    });
}

// The half-size image (width and height rounded up): each pixel the mean
// of the 2x2 pixels it covers, an edge pixel repeated where the image has
// an odd size.
inline Image half_size(const Image& from) {
    return {nullptr, (from.width + 1) / 2, (from.height + 1) / 2, (from.width + 1) / 2};
}
inline void downsample(const sdk::PostFrame& f, const Image& from, const Image& to) {
    f.for_rows(to.height, [&](int y) {
        const glm::vec4* a = from.row(std::min(2 * y, from.height - 1));
        const glm::vec4* b = from.row(std::min(2 * y + 1, from.height - 1));
        glm::vec4* dst = to.row(y);
        for (int x = 0; x < to.width; ++x) {
            const int x0 = std::min(2 * x, from.width - 1), x1 = std::min(2 * x + 1, from.width - 1);
            store(dst[x], 0.25f * (load(a[x0]) + load(a[x1]) + load(b[x0]) + load(b[x1])));
        }
    });
}

// Adds `scale` times `from` (the half-size image of `to`) to `to`, read
// bilinearly at each pixel's centre: pixel x of `to` lies at (x + 0.5) / 2
// - 0.5 in `from`'s pixels, clamped to its edges.
inline void add_upsampled(const sdk::PostFrame& f, const Image& from, const Image& to,
                          float scale) {
    const auto tap = [](int i, int n, int& i0, int& i1, float& t) {
        const float p = std::clamp((float(i) + 0.5f) * 0.5f - 0.5f, 0.0f, float(n - 1));
        i0 = int(p);
        i1 = std::min(i0 + 1, n - 1);
        t = p - float(i0);
    };
    f.for_rows(to.height, [&](int y) {
        int y0, y1;
        float ty;
        tap(y, from.height, y0, y1, ty);
        const glm::vec4* a = from.row(y0);
        const glm::vec4* b = from.row(y1);
        glm::vec4* dst = to.row(y);
        for (int x = 0; x < to.width; ++x) {
            int x0, x1;
            float tx;
            tap(x, from.width, x0, x1, tx);
            const V4 top = load(a[x0]) + tx * (load(a[x1]) - load(a[x0]));
            const V4 bottom = load(b[x0]) + tx * (load(b[x1]) - load(b[x0]));
            store(dst[x], load(dst[x]) + scale * (top + ty * (bottom - top)));
        }
    });
}

}  // namespace facet::post
