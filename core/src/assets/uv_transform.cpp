// Where a texture lies on its UVs (UvTransform, facet/texture.hpp).
#include "facet/texture.hpp"

#include <cmath>

namespace facet {

std::array<float, 4> UvTransform::matrix() const {
    const float c = std::cos(rotation), s = std::sin(rotation);
    return {c * scale.x, s * scale.y, -s * scale.x, c * scale.y};
}

void UvTransform::apply(const float* u, const float* v, int count, float* out_u,
                        float* out_v) const {
    const std::array<float, 4> m = matrix();
    for (int i = 0; i < count; ++i) {
        const float x = u[i], y = v[i];
        out_u[i] = m[0] * x + m[1] * y + offset.x;
        out_v[i] = m[2] * x + m[3] * y + offset.y;
    }
}

float UvTransform::lod_shift() const {
    const float area = std::abs(scale.x * scale.y);
    return area > 0.0f ? 0.5f * std::log2(area) : 0.0f;
}

}  // namespace facet
