#include "metrics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace facet::reference {

namespace {

double encode(double linear) {
    linear = std::clamp(linear, 0.0, 1.0);
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// Rec. 709 luma of the encoded values.
std::vector<double> luma(const std::vector<glm::dvec4>& image) {
    std::vector<double> out(image.size());
    for (size_t i = 0; i < image.size(); ++i)
        out[i] = 0.2126 * encode(image[i].r) + 0.7152 * encode(image[i].g) +
                 0.0722 * encode(image[i].b);
    return out;
}

// Separable Gaussian blur (11 taps, sigma 1.5), the window clamped at the borders.
std::vector<double> blur(const std::vector<double>& in, int w, int h) {
    double k[11], total = 0.0;
    for (int i = 0; i < 11; ++i) total += k[i] = std::exp(-0.5 * (i - 5) * (i - 5) / (1.5 * 1.5));
    for (double& v : k) v /= total;
    std::vector<double> tmp(in.size()), out(in.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double s = 0.0;
            for (int i = 0; i < 11; ++i) s += k[i] * in[size_t(y) * w + std::clamp(x + i - 5, 0, w - 1)];
            tmp[size_t(y) * w + x] = s;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double s = 0.0;
            for (int i = 0; i < 11; ++i) s += k[i] * tmp[size_t(std::clamp(y + i - 5, 0, h - 1)) * w + x];
            out[size_t(y) * w + x] = s;
        }
    return out;
}

double mean_ssim(const std::vector<double>& a, const std::vector<double>& b, int w, int h) {
    std::vector<double> aa(a.size()), bb(a.size()), ab(a.size());
    for (size_t i = 0; i < a.size(); ++i) {
        aa[i] = a[i] * a[i];
        bb[i] = b[i] * b[i];
        ab[i] = a[i] * b[i];
    }
    const std::vector<double> ma = blur(a, w, h), mb = blur(b, w, h), saa = blur(aa, w, h),
                              sbb = blur(bb, w, h), sab = blur(ab, w, h);
    const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    double total = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        const double va = saa[i] - ma[i] * ma[i], vb = sbb[i] - mb[i] * mb[i];
        const double cov = sab[i] - ma[i] * mb[i];
        total += ((2 * ma[i] * mb[i] + c1) * (2 * cov + c2)) /
                 ((ma[i] * ma[i] + mb[i] * mb[i] + c1) * (va + vb + c2));
    }
    return total / double(a.size());
}

}  // namespace

ImageError compare(const std::vector<glm::dvec4>& image, const std::vector<glm::dvec4>& reference,
                   int width, int height) {
    if (image.size() != reference.size() || image.size() != size_t(width) * size_t(height) ||
        image.empty())
        throw std::invalid_argument("compare: images of different sizes");
    ImageError e;
    double sq = 0.0;
    for (size_t i = 0; i < image.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = encode(image[i][c]) - encode(reference[i][c]);
            sq += d * d;
            e.max = std::max(e.max, std::abs(d));
        }
    e.rmse = std::sqrt(sq / (3.0 * double(image.size())));
    e.dssim = (1.0 - mean_ssim(luma(image), luma(reference), width, height)) / 2.0;
    return e;
}

std::vector<glm::dvec4> linear_image(const Framebuffer& fb) {
    std::vector<glm::dvec4> out(size_t(fb.width()) * fb.height());
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) out[size_t(y) * fb.width() + x] = glm::dvec4(fb.pixel(x, y));
    return out;
}

}  // namespace facet::reference
