#include "ao.hpp"

#include "internal_shaders.hpp"
#include "timing.hpp"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <cmath>

namespace facet {

// AO radius and sample count from the material's `ao_radius` (float) and
// `ao_samples` (int) parameters, where its shader declares them.
AoSettings ao_settings(const Material& m) {
    AoSettings s;
    const facet_param_desc* radius = m.plugin->find_param("ao_radius");
    if (radius && radius->type == FACET_PARAM_FLOAT && m.block)
        std::memcpy(&s.radius, m.block->bytes + radius->offset, sizeof(float));
    const facet_param_desc* samples = m.plugin->find_param("ao_samples");
    if (samples && samples->type == FACET_PARAM_INT && m.block)
        std::memcpy(&s.samples, m.block->bytes + samples->offset, sizeof(int));
    s.radius = std::max(s.radius, 1e-4f);
    s.samples = std::clamp(s.samples, 1, 256);
    return s;
}

namespace {

constexpr int kSteps = 4;  // march steps along each direction

// View-space position of the pre-pass surface at pixel (x, y).
struct Unproject {
    glm::mat4 inverse;
    int width, height;

    glm::vec3 at(int x, int y, float depth) const {
        const glm::vec4 ndc((x + 0.5f) / width * 2.0f - 1.0f, 1.0f - (y + 0.5f) / height * 2.0f,
                            depth, 1.0f);
        const glm::vec4 p = inverse * ndc;
        return glm::vec3(p) / p.w;
    }
};

// Direction k of n, cosine-weighted over the hemisphere around +Z (a
// Hammersley set), turned by `angle` about +Z.
glm::vec3 hemisphere(int k, int n, float angle) {
    const float u = (float(k) + 0.5f) / float(n);
    uint32_t bits = uint32_t(k);
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    const float phi = glm::two_pi<float>() * float(bits) * 2.3283064365386963e-10f + angle;
    const float r = std::sqrt(u);
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(1.0f - u)};
}

}  // namespace

void AoPass::run(const std::vector<const Object*>& objects, const glm::mat4& view,
                 const glm::mat4& proj, bool reversed_z, int width, int height,
                 const AoSettings& settings, Renderer& renderer, ThreadPool& pool,
                 FrameStats& stats) {
    auto start = std::chrono::steady_clock::now();
    if (prepass_.width() != width || prepass_.height() != height)
        prepass_.resize(width, height, ColorFormat::rgba32f);
    renderer.clear(prepass_, glm::vec4(0.0f), reversed_z ? 0.0f : 1.0f);
    DrawCall call;
    call.shader = &internal::plugin<internal::ViewNormals>();
    call.view = view;
    call.projection = proj;
    call.state.cull = CullMode::none;
    call.state.depth_compare = reversed_z ? DepthCompare::greater : DepthCompare::less;
    FrameStats pass;
    for (const Object* o : objects) {
        call.mesh = o->mesh.get();
        call.model = o->transform.matrix();
        renderer.queue(call, prepass_, pass);
    }
    renderer.flush(pass);
    stats.prepasses += 1;
    stats.ms_prepass += elapsed_ms(start);

    start = std::chrono::steady_clock::now();
    view_z_.resize(size_t(width) * height);
    raw_.resize(view_z_.size());
    blurred_.resize(view_z_.size());
    pool.parallel_for(height, [&](int y, int) { linearize(proj, reversed_z, y); });
    pool.parallel_for(height, [&](int y, int) { occlusion(proj, settings, y); });
    pool.parallel_for(height, [&](int y, int) { blur(y); });
    stats.ao_passes += 1;
    stats.ms_ao += elapsed_ms(start);
}

// View-space z of row y of the pre-pass (0 where nothing was drawn).
void AoPass::linearize(const glm::mat4& proj, bool reversed_z, int y) {
    const int w = prepass_.width(), h = prepass_.height();
    const float background = reversed_z ? 0.0f : 1.0f;
    const Unproject unproject{glm::inverse(proj), w, h};
    for (int x = 0; x < w; ++x) {
        const float d = prepass_.depth_at(x, y);
        view_z_[size_t(y) * w + x] = d == background ? 0.0f : unproject.at(x, y, d).z;
    }
}

// Ambient visibility of row y, before the blur.
void AoPass::occlusion(const glm::mat4& proj, const AoSettings& s, int y) {
    const int w = prepass_.width(), h = prepass_.height();
    const Unproject unproject{glm::inverse(proj), w, h};
    for (int x = 0; x < w; ++x) {
        raw_[size_t(y) * w + x] = 1.0f;
        if (view_z_[size_t(y) * w + x] == 0.0f) continue;  // background
        const glm::vec3 p = unproject.at(x, y, prepass_.depth_at(x, y));
        const glm::vec3 n = glm::normalize(glm::vec3(prepass_.pixel(x, y)));
        const glm::vec3 t = glm::normalize(glm::abs(n.x) < 0.9f ? glm::cross(n, {1, 0, 0})
                                                                : glm::cross(n, {0, 1, 0}));
        const glm::mat3 tbn(t, glm::cross(n, t), n);
        const float angle = float((x & 3) * 4 + (y & 3)) * (glm::two_pi<float>() / 16.0f);
        int occluded = 0;
        for (int k = 0; k < s.samples; ++k)
            occluded += blocked(p, tbn * hemisphere(k, s.samples, angle), proj, s.radius);
        raw_[size_t(y) * w + x] = 1.0f - float(occluded) / float(s.samples);
    }
}

// Does the march from p along dir pass behind the pre-pass surface, by less
// than `radius`, within `radius`?
bool AoPass::blocked(const glm::vec3& p, const glm::vec3& dir, const glm::mat4& proj,
                     float radius) const {
    const int w = prepass_.width(), h = prepass_.height();
    for (int step = 1; step <= kSteps; ++step) {
        const glm::vec3 q = p + dir * (radius * float(step) / kSteps);
        const glm::vec4 c = proj * glm::vec4(q, 1.0f);
        if (c.w <= 0.0f) return false;
        const int sx = int(std::floor((c.x / c.w * 0.5f + 0.5f) * w));
        const int sy = int(std::floor((0.5f - c.y / c.w * 0.5f) * h));
        if (sx < 0 || sy < 0 || sx >= w || sy >= h) return false;
        const float surface = view_z_[size_t(sy) * w + sx];  // nearer is larger
        if (surface == 0.0f) continue;
        const float behind = surface - q.z;
        if (behind > 0.02f * radius && behind < radius) return true;
    }
    return false;
}

// Row y: mean of the 4x4 window aligned with the rotation pattern, weighted
// by depth similarity (view-space z, relative).
void AoPass::blur(int y) {
    const int w = prepass_.width(), h = prepass_.height();
    for (int x = 0; x < w; ++x) {
        const float z = view_z_[size_t(y) * w + x];
        blurred_[size_t(y) * w + x] = 1.0f;
        if (z == 0.0f) continue;
        float sum = 0.0f, weight = 0.0f;
        for (int j = std::max(y - 1, 0); j <= std::min(y + 2, h - 1); ++j)
            for (int i = std::max(x - 1, 0); i <= std::min(x + 2, w - 1); ++i) {
                const float rel = (view_z_[size_t(j) * w + i] - z) / std::abs(z);
                const float wgt = std::exp(-rel * rel * 2500.0f);  // ~2% depth difference
                sum += wgt * raw_[size_t(j) * w + i];
                weight += wgt;
            }
        blurred_[size_t(y) * w + x] = sum / weight;
    }
}

}  // namespace facet
