// fxaa: fast approximate anti-aliasing after Lottes (2009): edges found in
// the image's luma and blended across, for a pass after tone mapping.
//
// Per pixel M, with luma l = sqrt(clamp(Rec. 709 luminance, 0, 1)) (close
// to the sRGB encoding) of M and its neighbours N, S, W, E and the
// diagonals (edges clamped):
//   1. range = max - min of l over M, N, S, W, E. Below
//      max(edge_threshold_min, edge_threshold * max) M is kept.
//   2. The edge is horizontal when the second differences across rows,
//      2 |lN - 2 lM + lS| + |lNW - 2 lW + lSW| + |lNE - 2 lE + lSE|, are at
//      least those across columns (the same, transposed); else vertical.
//   3. Of the two neighbours across the edge (N and S, or W and E), the one
//      whose luma differs more from lM is its other side; g is that
//      difference, and a = (l side + lM) / 2 the luma on the edge.
//   4. Along the edge, step by one pixel each way, up to `search_steps`,
//      reading the mean luma of the pixel pair straddling the edge, until it
//      differs from a by at least g / 4: the edge's ends, at distances
//      dn and dp (search_steps + 1 when none was found).
//   5. edge offset = 1/2 - min(dn, dp) / (dn + dp) if the nearer end's
//      luma lies on the other side of a from lM, else 0.
//   6. subpixel offset = subpixel * s^2 with s = smoothstep(0, 1,
//      |(2 (lN + lS + lW + lE) + lNW + lNE + lSW + lSE) / 12 - lM| / range).
//   7. M becomes M + max(the two offsets) * (its neighbour across the
//      edge - M), RGBA alike.
#include "filters.hpp"

#include <cmath>

namespace {

using facet::post::Image;

struct Fxaa {
    static constexpr const char* name = "fxaa";
    static constexpr const char* version = "1.0";
    FACET_PARAMS((float1, edge_threshold, 0.125f, 0.0f, 1.0f,
                  "least luma contrast, relative to the brightest, that is an edge"),
                 (float1, edge_threshold_min, 0.0312f, 0.0f, 1.0f,
                  "least luma contrast that is an edge (dark areas)"),
                 (float1, subpixel, 0.75f, 0.0f, 1.0f, "how much single-pixel detail is smoothed"),
                 (int1, search_steps, 12, 1, 64, "pixels searched each way for an edge's ends"))

    static void run(const facet::sdk::PostFrame& f, const Params& p) {
        const Image image = facet::post::frame_image(f);
        const Image source = facet::post::scratch_image(f, 0, f.width(), f.height());
        float* luma = f.scratch<float>(1, size_t(f.width()) * size_t(f.height()));
        if (!source.pixels || !luma) return;
        const int w = f.width(), h = f.height();
        f.for_rows([&](int y) {
            const glm::vec4* row = image.row(y);
            std::copy(row, row + w, source.row(y));
            for (int x = 0; x < w; ++x) {
                const float l = 0.2126f * row[x].r + 0.7152f * row[x].g + 0.0722f * row[x].b;
                luma[size_t(y) * size_t(w) + size_t(x)] =
                    std::sqrt(l > 0.0f ? (l < 1.0f ? l : 1.0f) : 0.0f);
            }
        });
        const auto L = [&](int x, int y) {
            return luma[size_t(std::clamp(y, 0, h - 1)) * size_t(w) + size_t(std::clamp(x, 0, w - 1))];
        };
        f.for_rows([&](int y) {
            glm::vec4* out = image.row(y);
            for (int x = 0; x < w; ++x) {
                const float offset = pixel_offset(L, x, y, p);
                if (offset <= 0.0f) continue;  // M kept
                const glm::vec4 m = source.row(y)[x];
                const glm::ivec2 across = side_of(L, x, y);
                const glm::vec4 n = source.row(std::clamp(y + across.y, 0, h - 1))
                                        [std::clamp(x + across.x, 0, w - 1)];
                out[x] = m + offset * (n - m);
            }
        });
    }

    // Whether the edge through (x, y) is horizontal (steps 2).
    template <class Luma>
    static bool horizontal(const Luma& L, int x, int y) {
        const float m = L(x, y);
        const float rows = 2.0f * std::abs(L(x, y - 1) - 2.0f * m + L(x, y + 1)) +
                           std::abs(L(x - 1, y - 1) - 2.0f * L(x - 1, y) + L(x - 1, y + 1)) +
                           std::abs(L(x + 1, y - 1) - 2.0f * L(x + 1, y) + L(x + 1, y + 1));
        const float columns = 2.0f * std::abs(L(x - 1, y) - 2.0f * m + L(x + 1, y)) +
                              std::abs(L(x - 1, y - 1) - 2.0f * L(x, y - 1) + L(x + 1, y - 1)) +
                              std::abs(L(x - 1, y + 1) - 2.0f * L(x, y + 1) + L(x + 1, y + 1));
        return rows >= columns;
    }

    // The step from (x, y) to its neighbour across the edge (step 3).
    template <class Luma>
    static glm::ivec2 side_of(const Luma& L, int x, int y) {
        const glm::ivec2 normal = horizontal(L, x, y) ? glm::ivec2(0, 1) : glm::ivec2(1, 0);
        const float m = L(x, y);
        const float back = std::abs(L(x - normal.x, y - normal.y) - m);
        const float ahead = std::abs(L(x + normal.x, y + normal.y) - m);
        return back >= ahead ? -normal : normal;
    }

    // How far M moves toward its neighbour across the edge (steps 1 to 6);
    // 0 where it is kept.
    template <class Luma>
    static float pixel_offset(const Luma& L, int x, int y, const Params& p) {
        const float m = L(x, y), n = L(x, y - 1), s = L(x, y + 1), w = L(x - 1, y), e = L(x + 1, y);
        const float hi = std::max({m, n, s, w, e}), lo = std::min({m, n, s, w, e});
        const float range = hi - lo;
        if (range < std::max(p.edge_threshold_min, p.edge_threshold * hi)) return 0.0f;
        const glm::ivec2 across = side_of(L, x, y);
        const glm::ivec2 along(across.y != 0, across.x != 0);
        const float side = L(x + across.x, y + across.y);
        const float gradient = std::abs(side - m);
        const float average = 0.5f * (side + m);
        // Each way along the edge: the distance to its end, and the luma there.
        const auto end = [&](int sign, float& delta) {
            for (int i = 1; i <= p.search_steps; ++i) {
                const int px = x + sign * i * along.x, py = y + sign * i * along.y;
                delta = 0.5f * (L(px, py) + L(px + across.x, py + across.y)) - average;
                if (std::abs(delta) >= 0.25f * gradient) return float(i);
            }
            return float(p.search_steps + 1);
        };
        float delta_n = 0.0f, delta_p = 0.0f;
        const float dn = end(-1, delta_n), dp = end(1, delta_p);
        const float nearer = std::min(dn, dp);
        const float delta = dn < dp ? delta_n : delta_p;
        const bool right_side = (delta < 0.0f) != (m < average);
        const float edge = right_side ? 0.5f - nearer / (dn + dp) : 0.0f;
        const float mean =
            (2.0f * (n + s + w + e) + L(x - 1, y - 1) + L(x + 1, y - 1) + L(x - 1, y + 1) +
             L(x + 1, y + 1)) / 12.0f;
        const float t = std::clamp(std::abs(mean - m) / range, 0.0f, 1.0f);
        const float smooth = (3.0f - 2.0f * t) * t * t;
        return std::max(edge, p.subpixel * smooth * smooth);
    }
};

}  // namespace

FACET_POST(Fxaa)
