#include "frame/ao.hpp"

#include "base/timing.hpp"
#include "pipeline/kernels.hpp"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstring>
#include <utility>

namespace facet {

namespace {

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

void AoPass::make_directions(int samples) {
    if (direction_samples_ == samples) return;
    directions_.resize(size_t(16 * 3 * samples));
    for (int row = 0; row < 4; ++row)         // y & 3
        for (int k = 0; k < samples; ++k)
            for (int column = 0; column < 4; ++column) {  // x & 3
                const int rotation = column * 4 + row;
                const glm::vec3 d =
                    hemisphere(k, samples, float(rotation) * (glm::two_pi<float>() / 16.0f));
                for (int c = 0; c < 3; ++c)
                    directions_[size_t(((row * samples + k) * 3 + c) * 4 + column)] = d[c];
            }
    direction_samples_ = samples;
}

void AoFrame::set_pixel_rays(const glm::mat4& proj) {
    // Pixel column px has ndc x (px + 1/2) 2 / W - 1, which is
    // (P00 x + P20 z) / (P23 z) in perspective and P00 x + P30 in
    // orthographic (w = 1): solved for x, affine in px, times z in
    // perspective. The same for y, whose ndc falls as the row grows.
    assert(proj[1][0] == 0.0f && proj[0][1] == 0.0f && proj[0][3] == 0.0f &&
           proj[1][3] == 0.0f);
    perspective = proj[2][3] != 0.0f;
    const float to_ndc_x = 2.0f / float(target_width), to_ndc_y = 2.0f / float(target_height);
    const float ndc_x0 = 0.5f * to_ndc_x - 1.0f, ndc_y0 = 1.0f - 0.5f * to_ndc_y;
    if (perspective) {
        assert(proj[3][0] == 0.0f && proj[3][1] == 0.0f && proj[3][3] == 0.0f);
        const float w = proj[2][3];
        x1 = to_ndc_x * w / proj[0][0], x0 = (ndc_x0 * w - proj[2][0]) / proj[0][0];
        y1 = -to_ndc_y * w / proj[1][1], y0 = (ndc_y0 * w - proj[2][1]) / proj[1][1];
    } else {
        assert(proj[2][0] == 0.0f && proj[2][1] == 0.0f && proj[3][3] == 1.0f);
        x1 = to_ndc_x / proj[0][0], x0 = (ndc_x0 - proj[3][0]) / proj[0][0];
        y1 = -to_ndc_y / proj[1][1], y0 = (ndc_y0 - proj[3][1]) / proj[1][1];
    }
}

void AoPass::draw_prepass(const std::vector<DrawItem>& items, const glm::mat4& view,
                          const glm::mat4& proj, const RenderSettings& settings, float time,
                          Pipeline& pipeline, FrameStats& stats) {
    const int width = settings.width, height = settings.height;
    const bool reversed_z = settings.reversed_z;
    const auto start = std::chrono::steady_clock::now();
    if (depth_.width() != width || depth_.height() != height)
        depth_.resize(width, height, ColorFormat::none);
    pipeline.clear(depth_, glm::vec4(0.0f), settings.far_depth());
    DrawCall call;
    call.view = view;
    call.projection = proj;
    call.state.front_ccw = settings.front_ccw;
    call.state.depth_compare = reversed_z ? DepthCompare::greater : DepthCompare::less;
    call.state.color_write = false;
    call.time = time;
    FrameStats pass;
    for (const DrawItem& d : items) {
        set_item(call, d);
        // The faces the main pass draws, and only those, where it draws them:
        // the material's own vertex shader places them, on the scene's
        // sub-pixel grid, so that this depth is the frame's pre-pass's bit for
        // bit; a cutout's own shader runs (with no lights) to discard what its
        // alpha cuts away, and no other shader runs.
        const Material& m = *d.material;
        if (!m.color_write && !m.writes_depth()) continue;  // a stencil mask hides nothing
        call.state.cull = m.cull.value_or(settings.cull);
        call.state.subpixel_bits = settings.subpixel_bits;
        pipeline.queue(call, depth_, pass);
    }
    pipeline.flush(pass);
    stats.fragments_depth_only += pass.fragments_depth_only;
    stats.prepasses += 1;
    stats.ms_prepass += elapsed_ms(start);
}

void AoPass::run(const std::vector<DrawItem>& items, const glm::mat4& view,
                 const glm::mat4& proj, const RenderSettings& settings, float time,
                 const Framebuffer* depth, Pipeline& pipeline, FrameStats& stats) {
    const int width = settings.width, height = settings.height;
    ThreadPool& pool = pipeline.pool();
    const Kernels& kernels = pipeline.kernels();
    if (!depth) {
        draw_prepass(items, view, proj, settings, time, pipeline, stats);
        depth = &depth_;
    }
    const auto start = std::chrono::steady_clock::now();
    scale_ = settings.ao_half_resolution ? 2 : 1;
    AoFrame& f = frame_;
    f.scale = scale_;
    f.width = (width + scale_ - 1) / scale_;
    f.height = (height + scale_ - 1) / scale_;
    f.target_width = width;
    f.target_height = height;
    f.samples = settings.ao_samples;
    f.radius = settings.ao_radius;
    f.projection = proj;
    const size_t texels = size_t(f.width) * size_t(f.height);
    for (std::vector<float>* v : {&raw_, &blurred_}) v->resize(texels);
    // The positions pass writes every texel of the grid; the key's border
    // and z's padding are zeroed only when the grid changes.
    constexpr int border = AoFrame::kBorder;
    const size_t pad = size_t(f.width) + 16;  // a row and a vector, on either side
    // Rows an odd number of cache lines (16 floats) apart: a march down a
    // column then reads its rows through different cache sets. Rows 4 KiB
    // apart (960 texels and the border, at 1920x1080 and half size) share
    // a few, which cost the occlusion a tenth of its time.
    f.key_stride = (((f.width + 2 * border + 15) / 16) | 1) * 16;
    if (zeroed_width_ != f.width || zeroed_height_ != f.height) {
        key_.assign(size_t(f.key_stride) * size_t(f.height + 2 * border), 0.0f);
        z_.assign(texels + 2 * pad, 0.0f);
        zeroed_width_ = f.width, zeroed_height_ = f.height;
    }
    f.key = key_.data() + size_t(border) * size_t(f.key_stride) + border;
    f.z = z_.data() + pad;
    f.raw = raw_.data();
    f.blurred = blurred_.data();
    make_directions(settings.ao_samples);
    f.directions = directions_.data();
    const glm::mat4 inverse = glm::inverse(proj);
    f.target_depth = std::as_const(*depth).depth();
    f.target_stride = depth->stride();
    f.background = settings.far_depth();
    f.set_pixel_rays(proj);
    f.z_row = {inverse[0][2], inverse[1][2], inverse[2][2], inverse[3][2]};
    f.w_row = {inverse[0][3], inverse[1][3], inverse[2][3], inverse[3][3]};

    constexpr int kBand = 8;  // rows per task
    const auto bands = [&](int rows, auto&& fn) {
        pool.parallel_for((rows + kBand - 1) / kBand, [&](int band, int) {
            fn(band * kBand, std::min(kBand, rows - band * kBand));
        });
    };
    bands(f.height, [&](int first, int count) { kernels.ao_position_rows(f, first, count); });
    // Occlusion in tiles, whose marches' loads (up to `radius` away) stay
    // within a few hundred kilobytes; row bands as wide as the image would
    // reach over several megabytes and miss the cache.
    constexpr int kTileWidth = 128, kTileRows = 16;
    // Tiles start at multiples of the occlusion's group of texels, on which
    // its groups and each texel's turn of the direction set depend.
    static_assert(kTileWidth % AoFrame::kGroupWidth == 0 && kTileRows % AoFrame::kGroupRows == 0);
    const int columns = (f.width + kTileWidth - 1) / kTileWidth;
    const int tile_rows = (f.height + kTileRows - 1) / kTileRows;
    pool.parallel_for(columns * tile_rows, [&](int tile, int) {
        const int ty = tile / columns, tx = tile % columns;
        kernels.ao_occlusion_rows(f, ty * kTileRows, std::min(kTileRows, f.height - ty * kTileRows),
                                  tx * kTileWidth, kTileWidth);
    });
    bands(f.height, [&](int first, int count) { kernels.ao_blur_rows(f, first, count); });
    stats.ao_passes += 1;
    stats.ms_ao += elapsed_ms(start);
}

}  // namespace facet
