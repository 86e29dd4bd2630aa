// Anisotropic filtering on the per-path sampler (sampler.hpp), in a file
// of its own: compiled beside the other filters, it grew their unit past
// GCC's inlining limits, which then called simd::gather4 out of line, and
// trilinear filtering on AVX-512 took a third longer.
#include "pipeline/texel_filters.hpp"

#include <algorithm>

namespace facet::FACET_KERNEL_NS::texel_filters {

namespace {

// Each lane's quad's derivatives, in part p.
FACET_INLINE Derivatives<Float> lanes_of(const Derivatives<Quad>& d, int p) {
    return {per_lane(d.ux, p), per_lane(d.vx, p), per_lane(d.uy, p), per_lane(d.vy, p)};
}

// The mean of up to `most` trilinear samples a lane along the longer axis
// of its footprint, at raw (unfolded) coordinates u, v with derivatives d:
// the reference's anisotropic_footprint() and anisotropic() (texture.cpp),
// step by step. A part loops to its largest count of samples; a lane past
// its own count reads nothing.
template <TexelFormat F, Wrap W>
FACET_INLINE Texels anisotropic(const TexelLevels& t, const Derivatives<Float>& d,
                                const Float& u, const Float& v, int most, const Int& active) {
    const float w = float(t.level[0].width), h = float(t.level[0].height);
    const Float xu = d.ux * w, xv = d.vx * h, yu = d.uy * w, yv = d.vy * h;
    const Float x2 = xu * xu + xv * xv, y2 = yu * yu + yv * yv;
    const Int along_y = y2 > x2;
    const Float longer = along_y ? y2 : x2, shorter = along_y ? x2 : y2;
    const Int sized = longer > 0.0f;  // else (no size, NaN) one sample at level 0
    // ceil(sqrt(longer / shorter)) up to `most`: NaN and infinity are `most`.
    const Float ratio = simd::min(simd::sqrt(longer / shorter), splat(float(most)));
    const Int whole = __builtin_convertvector(ratio, Int);
    const Int n = sized ? whole - (simd::to_float(whole) < ratio) : Int{} + 1;
    const Float nf = simd::to_float(n);
    const Float lod = kept(log2(longer / (nf * nf)) * 0.5f, sized);
    const Float su = kept(along_y ? d.uy : d.ux, sized), sv = kept(along_y ? d.vy : d.vx, sized);
    int samples = 1;
    for (int j = 0; j < kWidth; ++j) samples = active[j] ? std::max(samples, int(n[j])) : samples;
    Texels sum{};
    for (int k = 0; k < samples; ++k) {
        const Int on = active & (n > k);
        const Float at = (float(k) + 0.5f) / nf - 0.5f;
        const Texels c = trilinear<F, W>(t, lod, fold<W>(u + su * at), fold<W>(v + sv * at), on);
        sum = {sum.r + kept(c.r, on), sum.g + kept(c.g, on), sum.b + kept(c.b, on),
               sum.a + kept(c.a, on)};
    }
    return {sum.r / nf, sum.g / nf, sum.b / nf, sum.a / nf};
}

// Every part with a lane in `mask` of an anisotropic binding: over each
// lane's footprint, from its derivatives (given, or its quad's); at a
// level given with no derivatives, trilinear.
template <TexelFormat F, Wrap W>
void anisotropic_parts(const TexelLevels& t, const TextureBinding& b, const Lanes& in,
                       uint32_t mask, float* rgba) {
    const int most = std::clamp(b.anisotropy, 1, kMaxAnisotropy);  // as the reference holds it
    const Derivatives<Quad> quads =
        in.grads || in.lod ? Derivatives<Quad>{} : block_derivatives(in.u, in.v);
    for (int p = 0; p < kParts; ++p) {
        const uint32_t lanes = simd::part_mask(mask, p);
        if (!lanes) {
            store(rgba, p, Texels{}, Int{});
            continue;
        }
        const Int active = active_lanes(lanes);
        const auto at = [&](const float* a) { return simd::load<Float>(a + p * kWidth); };
        const Float u = at(in.u), v = at(in.v);
        if (in.lod && !in.grads) {
            store(rgba, p, trilinear<F, W>(t, at(in.lod), fold<W>(u), fold<W>(v), active), active);
            continue;
        }
        const Derivatives<Float> d =
            in.grads ? Derivatives<Float>{at(in.grads), at(in.grads + N), at(in.grads + 2 * N),
                                          at(in.grads + 3 * N)}
                     : lanes_of(quads, p);
        store(rgba, p, anisotropic<F, W>(t, d, u, v, most, active), active);
    }
}

template <TexelFormat F>
void sample_format(const TexelLevels& t, const TextureBinding& b, const Lanes& in, uint32_t mask,
                   float* rgba) {
    switch (b.wrap) {
        case Wrap::repeat: return anisotropic_parts<F, Wrap::repeat>(t, b, in, mask, rgba);
        case Wrap::clamp: return anisotropic_parts<F, Wrap::clamp>(t, b, in, mask, rgba);
        case Wrap::mirror: return anisotropic_parts<F, Wrap::mirror>(t, b, in, mask, rgba);
    }
}

}  // namespace

void sample_anisotropic(const TexelLevels& t, const TextureBinding& b, const Lanes& in,
                        uint32_t mask, float* rgba) {
    if (t.format == TexelFormat::rgba16) sample_format<TexelFormat::rgba16>(t, b, in, mask, rgba);
    else sample_format<TexelFormat::rgba8>(t, b, in, mask, rgba);
}

}  // namespace facet::FACET_KERNEL_NS::texel_filters
