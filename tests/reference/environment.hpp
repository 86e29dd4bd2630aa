// The reference for image-based lighting (tests and benchmarks only): what
// a pbr surface lit by an environment image reflects, by Monte Carlo in
// double precision.
//
// environment_truth() integrates pbr's own BRDF (Lambert times 1 - F, GGX,
// Smith height-correlated, Schlick; glTF's, as shaders/pbr writes it)
// against the scene's HDR image itself (bilinear, in the scene's rotation
// and intensity), unoccluded as facet's lighting is, at the centre of each
// pixel: `samples` directions, a third each from the GGX lobe, the cosine
// and the image's luminance, weighted by the mixture of the three
// densities (one-sample MIS). Pixels that see no object take the image
// along their ray (the sky). A pixel is measured where its eight
// neighbours see the same object, and that object is pbr, or the sky.
//
// environment_error() compares a frame with it: relative RMSE of linear
// RGB, and RMSE in 8-bit sRGB codes at an exposure of 2^exposure.
#pragma once

#include <facet/framebuffer.hpp>
#include <facet/scene.hpp>

#include <glm/glm.hpp>

#include <filesystem>
#include <vector>

namespace facet::reference {

// An equirectangular HDR image in floats, read as the reference reads it.
struct EnvironmentImage {
    int width = 0, height = 0;
    std::vector<float> rgb;

    // Throws std::runtime_error naming the file when it cannot be read.
    explicit EnvironmentImage(const std::filesystem::path& file);
    // Pixel (x, y), x wrapping and y clamped.
    glm::dvec3 at(int x, int y) const;
    // Bilinear at unit direction d (facet's equirectangular mapping).
    glm::dvec3 radiance(const glm::dvec3& d) const;
};

// Per pixel its radiance (linear RGB), the object seen (-1: the sky, -2:
// not measured), and whether it is measured.
struct EnvironmentTruth {
    int width = 0, height = 0;
    std::vector<glm::dvec3> color;
    std::vector<int> object;
    std::vector<char> measured;
    double noise = 0.0;  // RMS of the estimates' relative standard errors
};

// The scene (which must have an environment of `image`) at its size.
EnvironmentTruth environment_truth(const Scene& scene, const EnvironmentImage& image, int samples,
                                   int threads);

struct EnvironmentError {
    double surface_relative = 0, surface_codes = 0, sky_relative = 0, sky_codes = 0;
    double surface_max = 0, sky_max = 0;  // the largest relative error of a pixel
    int surface_pixels = 0, sky_pixels = 0;
    std::vector<double> object_relative;  // per object: relative RMSE
};

// `frame` (linear, rgba32f) against the truth, on its measured pixels.
EnvironmentError environment_error(const Framebuffer& frame, const EnvironmentTruth& truth,
                                   double exposure);

}  // namespace facet::reference
