#include "pipeline/fragment.hpp"

#include "pipeline/blend.hpp"
#include "pipeline/framebuffer_access.hpp"
#include "pipeline/narrow_coverage.hpp"
#include "pipeline/pixels.hpp"
#include "pipeline/rasterize.hpp"
#include "pipeline/sampler.hpp"
#include "pipeline/stencil.hpp"
#include "base/simd.hpp"
#include "plugin/plugin_calls.hpp"

#include "facet/plugin.hpp"
#include "facet/texture.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace facet::FACET_KERNEL_NS {

namespace {

constexpr int N = FACET_BLOCK_LANES;

using simd::Float;
using simd::kParts;
using simd::kWidth;

// Lanes where z passes a depth test known at compile time.
template <DepthCompare Compare>
Int passes(const Float& z, const Float& stored) {
    if constexpr (Compare == DepthCompare::less) return z < stored;
    else if constexpr (Compare == DepthCompare::less_equal) return z <= stored;
    else if constexpr (Compare == DepthCompare::greater) return z > stored;
    else if constexpr (Compare == DepthCompare::greater_equal) return z >= stored;
    else if constexpr (Compare == DepthCompare::equal) return z == stored;
    else if constexpr (Compare == DepthCompare::always) return Int{} - 1;
    else return Int{};  // never
}

// f(std::integral_constant<DepthCompare, compare>{}): code that tests
// depth, specialised for the test once rather than switching on it per use.
template <class F>
decltype(auto) with_compare(DepthCompare compare, F&& f) {
    using C = DepthCompare;
    switch (compare) {
        case C::less: return f(std::integral_constant<C, C::less>{});
        case C::less_equal: return f(std::integral_constant<C, C::less_equal>{});
        case C::greater: return f(std::integral_constant<C, C::greater>{});
        case C::greater_equal: return f(std::integral_constant<C, C::greater_equal>{});
        case C::equal: return f(std::integral_constant<C, C::equal>{});
        case C::always: return f(std::integral_constant<C, C::always>{});
        case C::never: break;
    }
    return f(std::integral_constant<C, C::never>{});
}

// Lanes where z passes the depth test against `stored`.
uint32_t depth_passes(DepthCompare compare, const Float& z, const Float& stored) {
    return with_compare(compare, [&](auto c) {
        return simd::bits(passes<decltype(c)::value>(z, stored));
    });
}

// Window depth of part p, from the exact weights, clamped like std::clamp
// (NaN stays NaN).
Float interpolate_depth(const TriangleSetup& t, const Block& b, int p) {
    const Float z = t.z[0] + simd::load<Float>(b.bary[1] + p * kWidth) * (t.z[1] - t.z[0]) +
                    simd::load<Float>(b.bary[2] + p * kWidth) * (t.z[2] - t.z[0]);
    return z < 0.0f ? 0.0f : z > 1.0f ? 1.0f : z;
}

// The early depth test, part by part; `z` gets each part's depth. The
// framebuffer is padded to whole blocks, so a block never reads or writes
// past its storage.
uint32_t depth_test(const DrawContext& dc, const TriangleSetup& t, const Block& b, Float* z) {
    const Framebuffer& fb = *dc.target;
    const float* depth = fb.depth() + pixel_index(fb, b.x, b.y);
    uint32_t mask = 0;
    for (int p = 0; p < kParts; ++p) {
        const uint32_t lanes = simd::part_mask(b.mask, p);
        if (!lanes) continue;
        z[p] = interpolate_depth(t, b, p);
        const uint32_t pass = dc.state.depth_compare == DepthCompare::always
                                  ? lanes
                                  : lanes & depth_passes(dc.state.depth_compare, z[p],
                                                         simd::load_part(depth, fb.stride(), p));
        mask |= pass << (p * kWidth);
    }
    return mask;
}

// The lanes the shader gets values for: each half of the block (two rows,
// whole 2x2 quads) with a lane in `mask`, or all of it when the shader takes
// derivatives (every lane interpolated, as the ABI promises).
uint32_t interpolated_lanes(const DrawContext& dc, uint32_t mask) {
    if (dc.shader->needs(FACET_NEED_DERIVATIVES)) return 0xFFFFu;
    return (mask & 0x00FFu ? 0x00FFu : 0u) | (mask & 0xFF00u ? 0xFF00u : 0u);
}

void interpolate_varyings(const DrawContext& dc, const TriangleVaryings& tv, const Block& b,
                          uint32_t lanes, float* out) {
    const uint32_t floats = dc.varying_floats;
    for (int p = 0; p < kParts; ++p) {
        const int first = p * kWidth;
        if (!simd::part_mask(lanes, p)) {  // values no shader call reads: zeros, not garbage
            for (uint32_t k = 0; k < floats; ++k) simd::store(out + k * N + first, Float{});
            continue;
        }
        const LaneWeights w = lane_weights(tv, b, p);
        if (dc.perspective_only) {
            for (uint32_t k = 0; k < floats; ++k)
                simd::store(out + k * N + first, interpolate(tv, k, w.p1, w.p2));
            continue;
        }
        for (uint32_t k = 0; k < floats; ++k) {
            const bool linear = screen_linear(dc, k);
            simd::store(out + k * N + first,
                        interpolate(tv, k, linear ? w.l1 : w.p1, linear ? w.l2 : w.p2));
        }
    }
}

// Texels of every texture slot the shader declares, at the lanes of `mask`
// (others read 0); unbound slots are white.
void sample_textures(const DrawContext& dc, const float* varyings, uint32_t mask, float* texels) {
    for (int s = 0; s < dc.shader->texture_count(); ++s) {
        float* out = texels + s * 4 * N;
        if (s >= dc.texture_count || !dc.textures[s].texture) {
            std::fill(out, out + 4 * N, 1.0f);
            continue;
        }
        const TextureBinding& binding = dc.textures[s];
        const int uv = dc.shader->texture_uv_float(s, binding.uv_set);
        if (uv < 0) {  // one only the shader samples (a cube map, ...): none here
            std::fill(out, out + 4 * N, 1.0f);
            continue;
        }
        const float* u = varyings + uv * N;
        if (binding.transform.identity()) {
            FACET_KERNEL_NS::sample_block(binding, u, u + N, mask, out);
            continue;
        }
        alignas(64) float placed[2 * N];  // every lane: the quads' differences give the level
        binding.transform.apply(u, u + N, N, placed, placed + N);
        FACET_KERNEL_NS::sample_block(binding, placed, placed + N, mask, out);
    }
}

// Part p of the shader's colour output ([4][16] floats).
Rgba shaded(const float* color, int p) {
    const int first = p * kWidth;
    return {simd::load<Float>(color + first), simd::load<Float>(color + N + first),
            simd::load<Float>(color + 2 * N + first), simd::load<Float>(color + 3 * N + first)};
}

// Ambient visibility of each lane; lanes off the target read 1.
void gather_ao(const DrawContext& dc, const Block& b, float* ao) {
    const int w = dc.target->width(), h = dc.target->height();
    if (b.x + 4 <= w && b.y + N / 4 <= h) {  // a whole block: rows of four
        for (int r = 0; r < N / 4; ++r)
            std::memcpy(ao + 4 * r, dc.ao + size_t(b.y + r) * size_t(w) + size_t(b.x),
                        4 * sizeof(float));
        return;
    }
    for (int i = 0; i < N; ++i) {
        const int x = b.x + i % 4, y = b.y + i / 4;
        ao[i] = x < w && y < h ? dc.ao[size_t(y) * w + x] : 1.0f;
    }
}

// Depth and (unless `color` is null) colour of the lanes of `mask`, blended
// and encoded in the target's format, part by part.
void write_pixels(const DrawContext& dc, const Block& b, const Float* z, const float* color,
                  uint32_t mask) {
    Framebuffer& fb = *dc.target;
    const size_t at = pixel_index(fb, b.x, b.y);
    const ColorFormat format = fb.format();
    const size_t bytes = size_t(bytes_per_pixel(format)), row_bytes = size_t(fb.stride()) * bytes;
    uint8_t* block = FramebufferAccess::color(fb) + at * bytes;
    const bool write_color = color && dc.state.color_write && fb.has_color();
    for (int p = 0; p < kParts; ++p) {
        const uint32_t lanes = simd::part_mask(mask, p);
        if (!lanes) continue;
        if (dc.state.depth_write)
            simd::store_part<4>(reinterpret_cast<uint8_t*>(FramebufferAccess::depth(fb) + at),
                                size_t(fb.stride()) * 4, p, &z[p], lanes);
        if (!write_color) continue;
        Rgba src = shaded(color, p);
        if (dc.state.blend != BlendMode::opaque)
            src = blend(dc.state, format, src, load_color(format, block, row_bytes, p));
        Packed packed;
        pack(format, src, packed.bytes);
        store_packed(format, block, row_bytes, p, packed, lanes);
    }
}

// MSAA: which covered samples pass the depth test: the surviving sample
// bits go to `passed`, the lanes with any to the result.
uint32_t sample_depth_test(const DrawContext& dc, const TriangleSetup& t, const Block& b,
                           uint32_t mask, SampleDepth& out) {
    const Framebuffer& fb = *dc.target;
    const int n = fb.samples();
    const float* depth = fb.sample_depth();
    const glm::vec2 dz = depth_gradient(t);
    uint32_t lanes = 0;
    for (uint32_t m = mask; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        const float centre = centre_depth(t, b, i);
        const size_t at = pixel_index(fb, b.x + i % 4, b.y + i / 4) * size_t(n);
        out.passed[i] = 0;
        for (uint32_t bits = b.samples[i]; bits; bits &= bits - 1) {
            const int s = std::countr_zero(bits);
            const float z = sample_depth(centre, dz, n, s);
            out.z[s][i] = z;
            if (depth_test_passes(dc.state.depth_compare, z, depth[at + size_t(s)]))
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
    const ColorFormat format = fb.format();
    const size_t bytes = size_t(bytes_per_pixel(format));
    const bool write_color = color && dc.state.color_write && fb.has_color();
    const bool opaque = dc.state.blend == BlendMode::opaque;
    for (int p = 0; p < kParts; ++p) {
        const uint32_t lanes = simd::part_mask(mask, p);
        if (!lanes) continue;
        Packed packed;  // opaque: each lane's encoded colour, the same for all its samples
        if (write_color && opaque) pack(format, shaded(color, p), packed.bytes);
        for (uint32_t m = lanes; m; m &= m - 1) {
            const int j = std::countr_zero(m), i = p * kWidth + j;
            const size_t at = pixel_index(fb, b.x + i % 4, b.y + i / 4) * size_t(n);
            for (uint32_t bits = sd.passed[i]; bits; bits &= bits - 1) {
                const int s = std::countr_zero(bits);
                if (dc.state.depth_write)
                    FramebufferAccess::sample_depth(fb)[at + size_t(s)] = sd.z[s][i];
                if (!write_color) continue;
                uint8_t* dst = FramebufferAccess::sample_color(fb) + (at + size_t(s)) * bytes;
                if (opaque) {
                    std::memcpy(dst, packed.bytes + size_t(j) * bytes, bytes);
                    continue;
                }
                const glm::vec4 src(color[i], color[N + i], color[2 * N + i], color[3 * N + i]);
                encode_pixel(format, blend(dc.state, format, src, decode_pixel(format, dst)), dst);
            }
        }
    }
}

// x | y << 16 of each lane's pixel, for a block at (x, y).
void lane_positions(const Block& b, int32_t* position) {
    for (int p = 0; p < kParts; ++p)
        simd::store(position + p * kWidth, (simd::column() + b.x) | (simd::row(p) + b.y) << 16);
}

}  // namespace

void PackedBatch::add(const DrawContext& dc, bool front_facing, const Block& b, uint32_t mask,
                      const float* varyings, const float* depth, const float* texels,
                      const float* ao, FrameStats& stats) {
    if (count_ && (dc_ != &dc || front_facing_ != front_facing)) flush(stats);
    dc_ = &dc;
    front_facing_ = front_facing;
    const int room = N - count_;
    if (simd::popcount(mask) > room) {  // the first `room` fragments fill this batch
        uint32_t first = 0;
        for (uint32_t m = mask; simd::popcount(first) < room; m &= m - 1) first |= m & (0u - m);
        append(b, first, varyings, depth, texels, ao);
        flush(stats);
        mask &= ~first;
    }
    append(b, mask, varyings, depth, texels, ao);
    if (count_ == N) flush(stats);
}

void PackedBatch::append(const Block& b, uint32_t mask, const float* varyings, const float* depth,
                         const float* texels, const float* ao) {
    const DrawContext& dc = *dc_;
    const simd::Compressor compress(mask);
    for (uint32_t k = 0; k < dc.varying_floats; ++k) compress(varyings + k * N, varyings_[k] + count_);
    if (dc.sample_textures)
        for (int row = 0; row < 4 * dc.shader->texture_count(); ++row)
            compress(texels + row * N, texels_[row] + count_);
    if (dc.needs_ao) compress(ao, ao_ + count_);
    compress(depth, depth_ + count_);
    alignas(64) int32_t position[N];
    lane_positions(b, position);
    compress(position, position_ + count_);
    count_ += compress.count();
}

void PackedBatch::flush(FrameStats& stats) {
    if (!count_) return;
    const DrawContext& dc = *dc_;
    // Into the ABI's layout, rows of 16 lanes; lanes past count_ read 0. A
    // row moves whole, in registers (the batch's rows have room past N): a
    // copy of a size known only at run time would be a call.
    simd::Int live[kParts];
    for (int p = 0; p < kParts; ++p)
        for (int j = 0; j < kWidth; ++j) live[p][j] = p * kWidth + j < count_ ? -1 : 0;
    const auto row = [&](const float* from, float* to) {
        for (int p = 0; p < kParts; ++p)
            simd::store(to + p * kWidth, live[p] ? simd::load<Float>(from + p * kWidth) : Float{});
    };
    alignas(64) float varyings[FACET_MAX_VARYING_FLOATS * N];
    for (uint32_t k = 0; k < dc.varying_floats; ++k) row(varyings_[k], varyings + k * N);
    alignas(64) float texels[FACET_MAX_TEXTURES * 4 * N];
    if (dc.sample_textures)
        for (int r = 0; r < 4 * dc.shader->texture_count(); ++r) row(texels_[r], texels + r * N);
    alignas(64) float depth[N], ao[N], coord[2 * N], color[4 * N];
    alignas(64) int32_t pixel[N];  // index into the target's pixels
    row(depth_, depth);
    if (dc.needs_ao) row(ao_, ao);
    const int32_t stride = dc.target->stride();
    for (int p = 0; p < kParts; ++p) {
        const simd::Int position =
            live[p] ? simd::load<simd::Int>(position_ + p * kWidth) : simd::Int{};
        const simd::Int x = position & 0xFFFF, y = position >> 16;
        simd::store(coord + p * kWidth, simd::to_float(x) + 0.5f);
        simd::store(coord + N + p * kWidth, simd::to_float(y + dc.first_row) + 0.5f);
        simd::store(pixel + p * kWidth, y * stride + x);
    }
    const uint32_t mask = count_ == N ? 0xFFFFu : (1u << count_) - 1u;
    facet_fragment_batch batch{};
    batch.coord = coord;
    batch.mask = mask;
    batch.front_facing = front_facing_ ? 1u : 0u;
    batch.varyings = varyings, batch.depth = depth;
    batch.texels = dc.sample_textures ? texels : nullptr;
    batch.ao = dc.needs_ao ? ao : nullptr;
    batch.color = color;
    call_plugin(dc.shader, PluginEntry::fragment, dc.fragment, dc.abi, &batch);
    stats.blocks_shaded += 1;
    stats.fragments_shaded += uint64_t(count_);
    // Opaque colours, in the order the fragments came (a pixel may come twice).
    Framebuffer& fb = *dc.target;
    const ColorFormat format = fb.format();
    const size_t bytes = size_t(bytes_per_pixel(format));
    // Each pixel's bytes, of a size known here (a copy of a size known only
    // at run time is a call).
    const auto scatter = [&](auto size) {
        for (int p = 0; p * kWidth < count_; ++p) {
            Packed packed;
            pack(format, shaded(color, p), packed.bytes);
            for (uint32_t m = simd::part_mask(mask, p); m; m &= m - 1) {
                const int j = std::countr_zero(m);
                std::memcpy(FramebufferAccess::color(fb) + size_t(pixel[p * kWidth + j]) * size,
                            packed.bytes + size_t(j) * size, size);
            }
        }
    };
    switch (bytes) {
        case 4: scatter(std::integral_constant<size_t, 4>{}); break;
        case 8: scatter(std::integral_constant<size_t, 8>{}); break;
        case 16: scatter(std::integral_constant<size_t, 16>{}); break;
        default: break;  // no colour
    }
    count_ = 0;
}

void prepare_varyings(const DrawContext& dc, const TriangleSetup& t, TriangleVaryings& out) {
    for (int v = 0; v < 3; ++v) out.inv_w[v] = t.inv_w[v];
    uint32_t k = 0;
    for (; k + 4 <= dc.varying_floats; k += 4) {  // four at a time, then one by one
        using Bytes = uint8_t __attribute__((vector_size(4)));
        using Ints = int32_t __attribute__((vector_size(16)));
        const simd::Row v0 = simd::load<simd::Row>(t.varyings[0] + k);
        const simd::Row v1 = simd::load<simd::Row>(t.varyings[1] + k);
        const simd::Row v2 = simd::load<simd::Row>(t.varyings[2] + k);
        const auto flat = __builtin_convertvector(simd::load<Bytes>(dc.interpolation + k), Ints) ==
                          int32_t(FACET_INTERP_FLAT);  // vertex 0 is the first
        simd::store(out.v0 + k, v0);
        simd::store(out.d1 + k, flat ? simd::Row{} : v1 - v0);
        simd::store(out.d2 + k, flat ? simd::Row{} : v2 - v0);
    }
    for (; k < dc.varying_floats; ++k) {
        const float v0 = t.varyings[0][k];
        const bool flat = dc.interpolation[k] == FACET_INTERP_FLAT;  // vertex 0 is the first
        out.v0[k] = v0;
        out.d1[k] = flat ? 0.0f : t.varyings[1][k] - v0;
        out.d2[k] = flat ? 0.0f : t.varyings[2][k] - v0;
    }
}

glm::vec2 depth_gradient(const TriangleSetup& t) {
    const double scale = double(kSubpixelOne) / double(t.area2);
    const double dz1 = double(t.z[1]) - t.z[0], dz2 = double(t.z[2]) - t.z[0];
    return {float((-t.edge[2].dy * dz1 - t.edge[0].dy * dz2) * scale),
            float((t.edge[2].dx * dz1 + t.edge[0].dx * dz2) * scale)};
}

bool depth_only(const DrawContext& dc) {
    return !dc.state.color_write && !dc.may_discard && !dc.state.alpha_to_coverage &&
           dc.target->samples() == 1 && !dc.stencil;
}

namespace {

// draw_depth_only for a test known at compile time: each part of a block
// with a covered lane read and tested in registers and, where the draw
// writes depth, written back whole, its covered lanes that pass taking
// their new depth and the rest keeping theirs (a tile is one thread's, and
// a target's rows are padded to whole blocks).
template <DepthCompare Compare>
void depth_blocks(const DrawContext& dc, const NarrowCoverage& cover, const TriangleSetup& t,
                  int x0, int y0, int x1, int y1, FrameStats& stats) {
    Framebuffer& fb = *dc.target;
    const size_t stride = size_t(fb.stride());
    const bool write = dc.state.depth_write;
    const float z0 = t.z[0], d1 = t.z[1] - t.z[0], d2 = t.z[2] - t.z[0];
    uint64_t written = 0, covered = 0;
    // Depth rows a block row ahead are asked for as each block row starts:
    // a tile's rows are too short for the hardware's prefetcher, and
    // otherwise a pre-pass waits on memory for most of them.
    const int px0 = std::max(t.x0, x0) & ~15, px1 = std::min(t.x1, x1);  // whole cache lines
    const int last_row = std::min(t.y1, y1);
    int fetched = -1;  // the block row whose next was asked for
    cover.for_each_block(x0, y0, x1, y1, [&](int bx, int by, uint32_t mask, const int64_t* e) {
        const float at1 = cover.at_lane0(e[2]), at2 = cover.at_lane0(e[0]);
        if (by != fetched) {
            fetched = by;
            for (int y = by + 4; y < by + 8 && y <= last_row; ++y)
                for (int x = px0; x <= px1; x += 16)
                    __builtin_prefetch(FramebufferAccess::depth(fb) + pixel_index(fb, x, y), 1);
        }
        float* depth = FramebufferAccess::depth(fb) + pixel_index(fb, bx, by);
        uint32_t pass = 0;
        for (int p = 0; p < kParts; ++p) {
            const uint32_t lanes = simd::part_mask(mask, p);
            if (!lanes) continue;
            // interpolate_depth's arithmetic, from the same weights.
            Float z = z0 + cover.weights(2, at1, p, mask) * d1 +
                      cover.weights(0, at2, p, mask) * d2;
            z = z < 0.0f ? 0.0f : z > 1.0f ? 1.0f : z;
            const Float stored = simd::load_part(depth, stride, p);
            const Int in = simd::part_lanes(mask, p);  // the covered lanes
            const Int passed = in & passes<Compare>(z, stored);
            if (write) simd::store_part(depth, stride, p, passed ? z : stored);
            pass |= simd::bits(passed) << (p * kWidth);
        }
        written += uint64_t(simd::popcount(pass));
        covered += uint64_t(simd::popcount(mask));
    });
    stats.fragments_depth_only += written;
    stats.fragments_depth_rejected += covered - written;
}

}  // namespace

void draw_depth_only(const DrawContext& dc, const NarrowCoverage& cover, const TriangleSetup& t,
                     int x0, int y0, int x1, int y1, FrameStats& stats) {
    // The test chosen once a triangle, not for every part of every block.
    with_compare(dc.state.depth_compare, [&](auto c) {
        depth_blocks<decltype(c)::value>(dc, cover, t, x0, y0, x1, y1, stats);
    });
}

// PipelineState::alpha_to_coverage: the samples each lane's alpha covers,
// kept in sd.passed with MSAA; the lanes of `mask` that keep any.
uint32_t alpha_to_coverage(const Block& b, const float* alpha, int n, uint32_t mask,
                           SampleDepth& sd) {
    // A 4x4 ordered (Bayer) dither, in 16ths.
    static constexpr uint8_t kDither[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
    const uint32_t all = (1u << n) - 1u;
    uint32_t kept = 0;
    for (uint32_t m = mask; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        const int x = b.x + i % 4, y = b.y + i / 4;
        const float a = alpha[i] > 0.0f ? std::min(alpha[i], 1.0f) : 0.0f;  // NaN: 0
        const float d = (float(kDither[(y & 3) * 4 + (x & 3)]) + 0.5f) / 16.0f;
        const int k = std::min(n, int(a * float(n) + d));
        const int r = (x + 2 * y) % n;
        const uint32_t run = (1u << k) - 1u;
        const uint32_t samples = ((run << r) | (run >> (n - r))) & all;
        if (n > 1) sd.passed[i] &= uint8_t(samples);
        if (n > 1 ? sd.passed[i] != 0 : samples != 0) kept |= 1u << i;
    }
    return kept;
}

void TileAo::upsample(const AoFrame& f) {
    const int columns = (x1 - x0 + kWidth) / kWidth * kWidth;  // whole vectors
    const int rows = y1 - y0 + 1;
    ao_upsample_rows(f, y0, rows, x0, columns, visibility, kTileSize / 4);
    if (rows % 4)  // the last blocks' rows past the target
        for (int b = 0; b < columns / 4; ++b) {
            float* block = visibility + size_t(rows / 4 * (kTileSize / 4) + b) * 16;
            std::fill(block + (rows % 4) * 4, block + 16, 1.0f);
        }
    ready = true;
}

void shade_block(const DrawContext& dc, const TriangleSetup& t, const TriangleVaryings& tv,
                 const Block& b, PackedBatch& packed, TileAo& tile_ao, FrameStats& stats) {
    const int n_samples = dc.target->samples();
    const bool msaa = n_samples > 1;
    Float z[kParts];
    SampleDepth sd;
    // With the stencil test, a shader that may remove lanes or samples has
    // its fragments tested (and the stencil written) after it runs, as GL
    // does; otherwise before.
    const bool late = dc.stencil && (dc.may_discard || dc.state.alpha_to_coverage);
    uint32_t mask;
    if (dc.stencil) {
        for (int p = 0; p < kParts; ++p) z[p] = interpolate_depth(t, b, p);
        for (int i = 0; i < N; ++i) sd.passed[i] = msaa ? b.samples[i] : 1;
        mask = late ? b.mask : stencil_depth_test(dc, t, b, b.mask, sd);
    } else {
        mask = msaa ? sample_depth_test(dc, t, b, b.mask, sd) : depth_test(dc, t, b, z);
    }
    stats.fragments_depth_rejected += simd::popcount(b.mask) - simd::popcount(mask);
    if (!mask) return;
    // Packed batches write depth before they shade, and opaque colours only.
    // A block whose every lane passes is a full batch as it is: shaded on its
    // own, it is copied nowhere, and its colours are written a row at a time.
    const bool pack = dc.packable && !msaa && dc.state.color_write &&
                      dc.state.blend == BlendMode::opaque && mask != 0xFFFFu;
    if (!pack && !packed.empty()) packed.flush(stats);  // what came first is written first
    if (!dc.state.color_write && !dc.may_discard && !dc.state.alpha_to_coverage) {
        // Depth only (shadow maps, pre-passes): the shader's colour would go nowhere.
        if (msaa) write_samples(dc, b, sd, nullptr, mask);
        else write_pixels(dc, b, z, nullptr, mask);
        stats.fragments_depth_only += simd::popcount(mask);
        return;
    }
    if (dc.state.wireframe) {  // the wire's colour, with no shader (PipelineState::wireframe)
        alignas(64) float color[4 * N];
        for (int c = 0; c < 4; ++c)
            std::fill(color + c * N, color + (c + 1) * N, c < 3 ? dc.state.wire_color[c] : 1.0f);
        if (msaa) write_samples(dc, b, sd, color, mask);
        else write_pixels(dc, b, z, color, mask);
        return;
    }

    alignas(64) float depth[N];
    for (int p = 0; p < kParts; ++p)
        simd::store(depth + p * kWidth, msaa || !simd::part_mask(mask, p)
                                            ? interpolate_depth(t, b, p)
                                            : z[p]);
    alignas(64) float gathered[N];
    const float* ao = gathered;
    if (dc.ao_grid) ao = tile_ao.block(*dc.ao_grid, b);  // half size: upsampled by tiles
    else if (dc.ao) gather_ao(dc, b, gathered);
    else if (dc.needs_ao) std::fill(gathered, gathered + N, 1.0f);  // AO off: full visibility
    alignas(64) float varyings[FACET_MAX_VARYING_FLOATS * N];
    interpolate_varyings(dc, tv, b, interpolated_lanes(dc, mask), varyings);
    alignas(64) float texels[FACET_MAX_TEXTURES * 4 * N];
    if (dc.sample_textures) sample_textures(dc, varyings, mask, texels);
    alignas(64) float color[4 * N];
    if (pack) {
        write_pixels(dc, b, z, nullptr, mask);
        packed.add(dc, t.front_facing, b, mask, varyings, depth, texels, ao, stats);
        return;
    }
    facet_fragment_batch batch{};
    batch.x = b.x, batch.y = b.y + dc.first_row;
    batch.mask = mask;
    batch.front_facing = t.front_facing ? 1u : 0u;
    batch.varyings = varyings, batch.depth = depth;
    batch.texels = dc.sample_textures ? texels : nullptr;
    batch.ao = dc.needs_ao ? ao : nullptr;
    batch.color = color;
    call_plugin(dc.shader, PluginEntry::fragment, dc.fragment, dc.abi, &batch);
    stats.blocks_shaded += 1;
    stats.fragments_shaded += simd::popcount(mask);
    uint32_t kept = batch.mask & mask;  // a shader may only clear bits
    if (dc.state.alpha_to_coverage) kept = alpha_to_coverage(b, color + 3 * N, n_samples, kept, sd);
    if (late) {
        const uint32_t tested = kept;
        kept = stencil_depth_test(dc, t, b, kept, sd);
        stats.fragments_depth_rejected += simd::popcount(tested) - simd::popcount(kept);
    }
    if (msaa) write_samples(dc, b, sd, color, kept);
    else write_pixels(dc, b, z, color, kept);
}

}  // namespace facet::FACET_KERNEL_NS
