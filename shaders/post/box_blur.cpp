// box_blur: each pixel the mean of the (2 radius + 1)^2 pixels around it
// (edges clamped, a value that is not finite counted as 0), RGBA alike: a
// box filter along the rows, then along the columns, each a running sum.
#include "filters.hpp"

namespace {

struct BoxBlur {
    static constexpr const char* name = "box_blur";
    static constexpr const char* version = "1.0";
    FACET_PARAMS((int1, radius, 2, 1, 256, "pixels each side of the centre"))

    static void run(const facet::sdk::PostFrame& f, const Params& p) {
        const facet::post::Image image = facet::post::frame_image(f);
        const facet::post::Image rows = facet::post::scratch_image(f, 0, f.width(), f.height());
        if (!rows.pixels) return;
        facet::post::box_rows(f, image, rows, p.radius);
        facet::post::box_columns(f, rows, image, p.radius);
    }
};

}  // namespace

FACET_POST(BoxBlur)
