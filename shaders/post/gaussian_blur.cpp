// gaussian_blur: a Gaussian of standard deviation `sigma` pixels, taps out
// to 3 sigma (rounded up) each side, weights normalised to sum to 1, edges
// clamped, RGBA alike; separable: along the rows, then along the columns.
#include "filters.hpp"

namespace {

struct GaussianBlur {
    static constexpr const char* name = "gaussian_blur";
    static constexpr const char* version = "1.0";
    FACET_PARAMS((float1, sigma, 2.0f, 0.1f, 64.0f, "standard deviation, pixels"))

    static void run(const facet::sdk::PostFrame& f, const Params& p) {
        const facet::post::Image image = facet::post::frame_image(f);
        const facet::post::Image rows = facet::post::scratch_image(f, 0, f.width(), f.height());
        if (!rows.pixels) return;
        const std::vector<float> w = facet::post::gaussian_weights(p.sigma);
        facet::post::convolve_rows(f, image, rows, w);
        facet::post::convolve_columns(f, rows, image, w);
    }
};

}  // namespace

FACET_POST(GaussianBlur)
