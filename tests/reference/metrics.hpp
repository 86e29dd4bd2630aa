// How far an image is from the reference, as a viewer sees it: both are
// encoded to sRGB (0..1, exactly, without 8-bit rounding) before comparing.
//
//   rmse   root mean square difference over pixels and R, G, B;
//   max    largest difference of any channel;
//   dssim  (1 - SSIM) / 2 on luma, SSIM by Wang et al. (2004): 11x11
//          Gaussian windows (sigma 1.5), C1 = (0.01)^2, C2 = (0.03)^2; a
//          perceptual distance, 0 for identical images.
#pragma once

#include <facet/framebuffer.hpp>

#include <glm/glm.hpp>

#include <vector>

namespace facet::reference {

struct ImageError {
    double rmse = 0.0;
    double max = 0.0;
    double dssim = 0.0;
};

// `image` and `reference` are linear RGB, width x height, top row first.
ImageError compare(const std::vector<glm::dvec4>& image, const std::vector<glm::dvec4>& reference,
                   int width, int height);

// The resolved colour of `fb` as doubles, for compare().
std::vector<glm::dvec4> linear_image(const Framebuffer& fb);

}  // namespace facet::reference
