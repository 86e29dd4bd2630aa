// tonemap: HDR to display range. Each colour channel x, scaled by 2^exposure,
// becomes
//   aces      the fit of the ACES filmic curve by Narkowicz (2015):
//             x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to 0..1
//   reinhard  x / (1 + x)
//   clamp     min(x, 1)
// (negative values and NaN give 0, +Inf gives 1). Alpha is kept. Its
// schema is a table rather than FACET_PARAMS: the curve's YAML name,
// "operator", as tone-mapping operators are called, is a C++ keyword.
#include <facet/post.hpp>

#include <algorithm>
#include <cmath>

namespace {

struct Tonemap {
    struct Params {
        float exposure;
        int32_t curve;
    };
    enum Curve { aces, reinhard, clamp };
    static constexpr const char* name = "tonemap";
    static constexpr const char* version = "1.0";
    static constexpr facet_param_desc params[] = {
        facet::sdk::float1("exposure", offsetof(Params, exposure), 0.0f, -20.0f, 20.0f,
                           "stops: the image is scaled by 2^exposure first"),
        facet::sdk::choice("operator", offsetof(Params, curve), aces, "the curve")};
    static constexpr const char* param_choices[] = {nullptr, "aces|reinhard|clamp"};

    template <Curve C>
    static float map(float x) {
        x = x > 0.0f ? x : 0.0f;  // and NaN to 0
        if constexpr (C == aces) {
            x = std::min(x, 1e4f);  // the curve is past 1 from x = 7.3 on; Inf would give NaN
            return std::min(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f), 1.0f);
        } else if constexpr (C == reinhard) {
            return std::isinf(x) ? 1.0f : x / (1.0f + x);
        } else {
            return std::min(x, 1.0f);
        }
    }

    template <Curve C>
    static void apply(const facet::sdk::PostFrame& f, float scale) {
        f.for_rows([&](int y) {
            glm::vec4* row = f.row(y);
            for (int x = 0; x < f.width(); ++x) {
                const glm::vec4 c = row[x];
                row[x] = {map<C>(c.r * scale), map<C>(c.g * scale), map<C>(c.b * scale), c.a};
            }
        });
    }

    static void run(const facet::sdk::PostFrame& f, const Params& p) {
        const float scale = std::exp2(p.exposure);
        switch (p.curve) {
            case aces: return apply<aces>(f, scale);
            case reinhard: return apply<reinhard>(f, scale);
            default: return apply<clamp>(f, scale);
        }
    }
};

}  // namespace

FACET_POST(Tonemap)
