// bloom: light that spills around what is brighter than the display.
//   1. Bright pass: each pixel's RGB scaled by max(0, L - threshold) / L,
//      L its luminance (Rec. 709: 0.2126 R + 0.7152 G + 0.0722 B; a pixel
//      whose L is not finite gives nothing, so that one bad pixel cannot
//      spread over the pyramid), at half
//      the frame's size per side (the mean of each 2x2 block).
//   2. A pyramid of `levels` images, each half the one before (2x2 means),
//      each blurred by a Gaussian of sigma 1.5 pixels (of its own level).
//   3. From the smallest up, each level gets the one below it added,
//      bilinearly upsampled; the frame gets `intensity` times the first
//      level, upsampled, added to its RGB. Alpha is kept.
// The wide blur comes from the small levels, so the cost stays near that of
// the first: about three quarters of a frame's pixels in all.
#include "filters.hpp"

#include <array>

namespace {

using facet::post::Image;

struct Bloom {
    static constexpr const char* name = "bloom";
    static constexpr const char* version = "1.0";
    FACET_PARAMS((float1, threshold, 1.0f, 0.0f, facet::sdk::infinity, "luminance above which light blooms"),
                 (float1, intensity, 0.05f, 0.0f, facet::sdk::infinity, "how much of the bloom is added"),
                 (int1, levels, 5, 1, 8, "pyramid levels: each doubles the reach"))
    static constexpr float kSigma = 1.5f;

    static void run(const facet::sdk::PostFrame& f, const Params& p) {
        const Image image = facet::post::frame_image(f);
        // Level i in slot i, its blurred copy in slot 8 + i.
        std::array<Image, 8> level{}, blurred{};
        Image size = image;
        int levels = 0;
        for (; levels < p.levels && (size.width > 1 || size.height > 1); ++levels) {
            size = facet::post::half_size(size);
            level[levels] = facet::post::scratch_image(f, levels, size.width, size.height);
            blurred[levels] = facet::post::scratch_image(f, 8 + levels, size.width, size.height);
            if (!level[levels].pixels || !blurred[levels].pixels) return;
        }
        if (levels == 0) return;
        bright_pass(f, image, level[0], p.threshold);
        for (int i = 1; i < levels; ++i) facet::post::downsample(f, level[i - 1], level[i]);
        const std::vector<float> w = facet::post::gaussian_weights(kSigma);
        for (int i = 0; i < levels; ++i) {  // the blur's first half goes to `blurred`
            facet::post::convolve_rows(f, level[i], blurred[i], w);
            facet::post::convolve_columns(f, blurred[i], level[i], w);
        }
        for (int i = levels - 1; i > 0; --i) facet::post::add_upsampled(f, level[i], level[i - 1], 1.0f);
        // RGB only: the levels' alpha is 0 throughout (bright_pass).
        facet::post::add_upsampled(f, level[0], image, p.intensity);
    }

    // Half-size mean of the frame's bright part: per pixel before the mean.
    static void bright_pass(const facet::sdk::PostFrame& f, const Image& from, const Image& to,
                            float threshold) {
        const auto bright = [&](const glm::vec4& c) {
            const float l = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
            if (!(l > threshold) || !std::isfinite(l)) return glm::vec4(0.0f);  // NaN, Inf: none
            return glm::vec4(glm::vec3(c) * ((l - threshold) / l), 0.0f);
        };
        f.for_rows(to.height, [&](int y) {
            const glm::vec4* a = from.row(std::min(2 * y, from.height - 1));
            const glm::vec4* b = from.row(std::min(2 * y + 1, from.height - 1));
            glm::vec4* dst = to.row(y);
            for (int x = 0; x < to.width; ++x) {
                const int x0 = std::min(2 * x, from.width - 1);
                const int x1 = std::min(2 * x + 1, from.width - 1);
                dst[x] = 0.25f * (bright(a[x0]) + bright(a[x1]) + bright(b[x0]) + bright(b[x1]));
            }
        });
    }
};

}  // namespace

FACET_POST(Bloom)
