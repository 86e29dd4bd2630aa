#include "fragment.hpp"

#include "simd.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace facet {

namespace {

constexpr int N = FACET_BLOCK_LANES;

bool depth_passes(DepthCompare compare, float z, float stored) {
    switch (compare) {
        case DepthCompare::never: return false;
        case DepthCompare::less: return z < stored;
        case DepthCompare::less_equal: return z <= stored;
        case DepthCompare::greater: return z > stored;
        case DepthCompare::greater_equal: return z >= stored;
        case DepthCompare::equal: return z == stored;
        case DepthCompare::always: return true;
    }
    return false;
}

using simd::f32x16;

f32x16 interpolate_depth(const TriangleSetup& t, const Block& b) {
    const f32x16 z = t.z[0] + simd::load<f32x16>(b.bary[1]) * (t.z[1] - t.z[0]) +
                     simd::load<f32x16>(b.bary[2]) * (t.z[2] - t.z[0]);
    const f32x16 zero = {}, one = zero + 1.0f;
    return z < zero ? zero : z > one ? one : z;  // clamps like std::clamp: NaN stays NaN
}

// Lanes where z passes the depth test against `stored`.
uint32_t depth_passes(DepthCompare compare, const f32x16& z, const f32x16& stored) {
    switch (compare) {
        case DepthCompare::never: return 0;
        case DepthCompare::less: return simd::bits(z < stored);
        case DepthCompare::less_equal: return simd::bits(z <= stored);
        case DepthCompare::greater: return simd::bits(z > stored);
        case DepthCompare::greater_equal: return simd::bits(z >= stored);
        case DepthCompare::equal: return simd::bits(z == stored);
        case DepthCompare::always: return 0xFFFFu;
    }
    return 0;
}

uint32_t depth_test(const DrawContext& dc, const Block& b, const f32x16& z, uint32_t mask) {
    if (dc.state.depth_compare == DepthCompare::always) return mask;
    const int width = dc.target->width(), height = dc.target->height();
    const float* depth = dc.target->depth() + size_t(b.y) * width + b.x;
    if (b.x + 4 <= width && b.y + 4 <= height)
        return mask & depth_passes(dc.state.depth_compare, z, simd::load_block(depth, width));
    for (uint32_t m = mask; m; m &= m - 1) {  // a block over the target's edge
        const int i = std::countr_zero(m);
        if (!depth_passes(dc.state.depth_compare, z[i], depth[size_t(i / 4) * width + i % 4]))
            mask &= ~(1u << i);
    }
    return mask;
}

// Perspective-correct weights: bary_k * (1/w_k), normalised per lane.
void perspective_weights(const TriangleSetup& t, const Block& b, float (*pw)[N]) {
    const f32x16 a = simd::load<f32x16>(b.bary[0]) * t.inv_w[0];
    const f32x16 c = simd::load<f32x16>(b.bary[1]) * t.inv_w[1];
    const f32x16 d = simd::load<f32x16>(b.bary[2]) * t.inv_w[2];
    const f32x16 w = 1.0f / (a + c + d);
    simd::store(pw[0], a * w);
    simd::store(pw[1], c * w);
    simd::store(pw[2], d * w);
}

void interpolate_varyings(const DrawContext& dc, const TriangleSetup& t, const Block& b,
                          float* out) {
    alignas(64) float pw[3][N];
    perspective_weights(t, b, pw);
    for (uint32_t k = 0; k < dc.varying_floats; ++k) {
        const float v0 = t.varyings[0][k], v1 = t.varyings[1][k], v2 = t.varyings[2][k];
        if (dc.interpolation[k] == FACET_INTERP_FLAT) {
            simd::store(out + k * N, f32x16{} + v0);  // vertex 0 is the first vertex
            continue;
        }
        const float(*w)[N] = dc.interpolation[k] == FACET_INTERP_PERSPECTIVE ? pw : b.bary;
        // Relative to v0: exact for constant attributes, better conditioned.
        simd::store(out + k * N, v0 + simd::load<f32x16>(w[1]) * (v1 - v0) +
                                     simd::load<f32x16>(w[2]) * (v2 - v0));
    }
}

// Texels of every texture slot the shader declares; unbound slots are white.
void sample_textures(const DrawContext& dc, const float* varyings, float* texels) {
    for (int s = 0; s < dc.shader->texture_count(); ++s) {
        float* out = texels + s * 4 * N;
        if (s >= dc.texture_count || !dc.textures[s].texture) {
            std::fill(out, out + 4 * N, 1.0f);
            continue;
        }
        const float* u = varyings + dc.shader->texture_uv_float(s) * N;
        sample_block(dc.textures[s], u, u + N, out);
    }
}

// Colour:  alpha    = src * a + dst * (1 - a)   (src-alpha, one-minus-src-alpha)
//          additive = src * a + dst             (src-alpha, one)
// Alpha:   alpha    = a + dst.a * (1 - a)       (coverage accumulates)
//          additive keeps dst.a.
// The factor a is the source alpha clamped to 0..1.
glm::vec4 blend(BlendMode mode, const glm::vec4& src, const glm::vec4& dst) {
    const float a = std::clamp(src.a, 0.0f, 1.0f);
    switch (mode) {
        case BlendMode::opaque: return src;
        case BlendMode::alpha:
            return {glm::vec3(src) * a + glm::vec3(dst) * (1.0f - a), a + dst.a * (1.0f - a)};
        case BlendMode::additive: return {glm::vec3(dst) + glm::vec3(src) * a, dst.a};
    }
    return src;
}

// Ambient visibility of each lane; lanes off the target read 1.
void gather_ao(const DrawContext& dc, const Block& b, float* ao) {
    const int w = dc.target->width(), h = dc.target->height();
    for (int i = 0; i < N; ++i) {
        const int x = b.x + i % 4, y = b.y + i / 4;
        ao[i] = x < w && y < h ? dc.ao[size_t(y) * w + x] : 1.0f;
    }
}

// `color` may be null when the state writes no colour.
void write_pixels(const DrawContext& dc, const Block& b, const f32x16& z, const float* color,
                  uint32_t mask) {
    Framebuffer& fb = *dc.target;
    const size_t width = size_t(fb.width());
    if (dc.state.depth_write) simd::store_block(fb.depth() + b.y * width + b.x, width, z, mask);
    if (!dc.state.color_write) return;
    const BlendMode mode = dc.state.blend;
    if (mode == BlendMode::opaque) {
        const simd::Rows rows = simd::interleave_rgba(
            simd::load<f32x16>(color), simd::load<f32x16>(color + N),
            simd::load<f32x16>(color + 2 * N), simd::load<f32x16>(color + 3 * N));
        for (int r = 0; r < 4; ++r) {
            const uint32_t lanes = mask >> (4 * r) & 0xFu;
            if (!lanes) continue;  // also keeps rows past the target's bottom unaddressed
            glm::vec4* row = &fb.pixel(b.x, b.y + r);
            if (lanes == 0xFu) {
                simd::store(row, rows.row[r]);
                continue;
            }
            for (uint32_t m = lanes; m; m &= m - 1) {
                const int i = std::countr_zero(m);
                std::memcpy(row + i, reinterpret_cast<const float*>(&rows.row[r]) + 4 * i, 16);
            }
        }
        return;
    }
    for (uint32_t m = mask; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        const glm::vec4 src(color[i], color[N + i], color[2 * N + i], color[3 * N + i]);
        glm::vec4& dst = fb.pixel(b.x + i % 4, b.y + i / 4);
        dst = blend(mode, src, dst);
    }
}

// MSAA: the depth plane's change per pixel in x and y, from the exact
// edge functions (vertex k+2's weight is edge k over twice the area).
glm::vec2 depth_gradient(const TriangleSetup& t) {
    const double scale = double(kSubpixelOne) / double(t.area2);
    const double dz1 = double(t.z[1]) - t.z[0], dz2 = double(t.z[2]) - t.z[0];
    return {float((-t.edge[2].dy * dz1 - t.edge[0].dy * dz2) * scale),
            float((t.edge[2].dx * dz1 + t.edge[0].dx * dz2) * scale)};
}

// Per-sample depth of one block, and which covered samples pass the depth
// test: the surviving sample bits go to `passed`, the lanes with any to the
// result.
struct SampleDepth {
    float z[Framebuffer::kMaxSamples][N];
    uint8_t passed[N];
};

uint32_t sample_depth_test(const DrawContext& dc, const TriangleSetup& t, const Block& b,
                           uint32_t mask, SampleDepth& out) {
    const int n = dc.target->samples(), width = dc.target->width();
    const float* depth = dc.target->sample_depth();
    const glm::vec2 dz = depth_gradient(t);
    uint32_t lanes = 0;
    for (uint32_t m = mask; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        const float centre = t.z[0] + b.bary[1][i] * (t.z[1] - t.z[0]) +
                             b.bary[2][i] * (t.z[2] - t.z[0]);
        const size_t at = (size_t(b.y + i / 4) * width + (b.x + i % 4)) * size_t(n);
        out.passed[i] = 0;
        for (uint32_t bits = b.samples[i]; bits; bits &= bits - 1) {
            const int s = std::countr_zero(bits);
            const glm::vec2 o = glm::vec2(sample_offset(n, s)) * (1.0f / 16.0f);
            const float z = std::clamp(centre + dz.x * o.x + dz.y * o.y, 0.0f, 1.0f);
            out.z[s][i] = z;
            if (depth_passes(dc.state.depth_compare, z, depth[at + size_t(s)]))
                out.passed[i] |= uint8_t(1u << s);
        }
        lanes |= uint32_t(out.passed[i] != 0) << i;
    }
    return lanes;
}

void write_samples(const DrawContext& dc, const Block& b, const SampleDepth& sd,
                   const float* color, uint32_t mask) {
    Framebuffer& fb = *dc.target;
    const int n = fb.samples();
    for (uint32_t m = mask; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        const size_t at = (size_t(b.y + i / 4) * fb.width() + (b.x + i % 4)) * size_t(n);
        for (uint32_t bits = sd.passed[i]; bits; bits &= bits - 1) {
            const int s = std::countr_zero(bits);
            if (dc.state.depth_write) fb.sample_depth()[at + size_t(s)] = sd.z[s][i];
            if (!dc.state.color_write) continue;
            const glm::vec4 src(color[i], color[N + i], color[2 * N + i], color[3 * N + i]);
            glm::vec4& dst = fb.sample_color()[at + size_t(s)];
            dst = blend(dc.state.blend, src, dst);
        }
    }
}

// Wireframe: blends the wire colour over the lanes within about a pixel of
// an edge. Lane i lies bary * area2 / length sub-pixels from an edge, where
// bary is the weight of the vertex opposite it; both triangles of a shared
// edge draw their own side, so the line is centred on the edge.
void blend_wire(const DrawContext& dc, const TriangleSetup& t, const Block& b, float* color) {
    float to_pixels[3];  // per edge k: pixels per unit of the weight of vertex k + 2
    for (int k = 0; k < 3; ++k) {
        const double length = std::hypot(double(t.edge[k].dx), double(t.edge[k].dy));
        to_pixels[k] = float(double(t.area2) / (length * double(kSubpixelOne)));
    }
    for (int i = 0; i < N; ++i) {
        const float d = std::min({b.bary[2][i] * to_pixels[0], b.bary[0][i] * to_pixels[1],
                                  b.bary[1][i] * to_pixels[2]});
        const float cover = std::clamp(2.0f * (1.0f - d), 0.0f, 1.0f);  // 1 up to 0.5 px
        for (int c = 0; c < 3; ++c)
            color[c * N + i] += cover * (dc.state.wire_color[c] - color[c * N + i]);
    }
}

void host_log(int level, const char* shader, const char* message) {
    const spdlog::level::level_enum levels[] = {spdlog::level::debug, spdlog::level::info,
                                                spdlog::level::warn, spdlog::level::err};
    spdlog::log(levels[std::clamp(level, 0, 3)], "[{}] {}", shader ? shader : "?",
                message ? message : "");
}

void host_sample(const facet_draw* draw, uint32_t slot, const float* u, const float* v,
                 uint32_t count, float* rgba) {
    const auto* dc = static_cast<const DrawContext*>(draw->host_data);
    if (slot >= uint32_t(dc->texture_count) || !dc->textures[slot].texture) {  // unbound: white
        std::fill(rgba, rgba + 4 * count, 1.0f);
        return;
    }
    sample_many(dc->textures[slot], u, v, int(count), rgba);
}

}  // namespace

void prepare_context(DrawContext& dc, const ShaderPlugin& shader, const TextureBinding* textures,
                     int texture_count) {
    dc.shader = &shader;
    dc.varying_floats = shader.varying_floats();
    dc.interpolation = shader.float_interpolation();
    dc.textures = textures;
    dc.texture_count = textures ? std::min(texture_count, shader.texture_count()) : 0;
    dc.sample_textures = shader.needs(FACET_NEED_TEXTURES) && shader.texture_count() > 0;
    dc.needs_ao = shader.needs(FACET_NEED_AO);
}

void shade_block(const DrawContext& dc, const TriangleSetup& t, const Block& b,
                 FrameStats& stats) {
    const f32x16 z = interpolate_depth(t, b);
    const bool msaa = dc.target->samples() > 1;
    SampleDepth sd;
    const uint32_t mask =
        msaa ? sample_depth_test(dc, t, b, b.mask, sd) : depth_test(dc, b, z, b.mask);
    stats.fragments_depth_rejected += std::popcount(b.mask) - std::popcount(mask);
    if (!mask) return;
    if (!dc.state.color_write && !dc.shader->needs(FACET_NEED_DISCARD)) {
        // Depth only (shadow maps): the shader's colour would go nowhere.
        if (msaa) write_samples(dc, b, sd, nullptr, mask);
        else write_pixels(dc, b, z, nullptr, mask);
        return;
    }

    alignas(64) float varyings[FACET_MAX_VARYING_FLOATS * N];
    interpolate_varyings(dc, t, b, varyings);
    alignas(64) float texels[FACET_MAX_TEXTURES * 4 * N];
    if (dc.sample_textures) sample_textures(dc, varyings, texels);
    alignas(64) float color[4 * N];
    alignas(64) float ao[N];
    if (dc.ao) gather_ao(dc, b, ao);
    else if (dc.needs_ao) std::fill(ao, ao + N, 1.0f);  // AO switched off: full visibility

    alignas(64) float depth[N];
    simd::store(depth, z);
    facet_fragment_batch batch{b.x,      b.y, mask, t.front_facing ? 1u : 0u, varyings, depth,
                               dc.sample_textures ? texels : nullptr,
                               nullptr,  dc.needs_ao ? ao : nullptr, color};
    dc.shader->desc().fragment(dc.abi, &batch);
    stats.blocks_shaded += 1;
    stats.fragments_shaded += std::popcount(mask);
    if (dc.state.wireframe && dc.state.color_write) blend_wire(dc, t, b, color);
    if (msaa) write_samples(dc, b, sd, color, batch.mask & mask);  // a shader may only clear bits
    else write_pixels(dc, b, z, color, batch.mask & mask);
}

const facet_host* host_services() {
    static const facet_host host = {FACET_ABI_MAJOR, FACET_ABI_MINOR, sizeof(facet_host),
                                    &host_log, &host_sample};
    return &host;
}

}  // namespace facet
