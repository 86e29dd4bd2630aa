// facet image-based lighting for shaders (C++20, header-only): the light
// arriving from the scene's environment, prefiltered by the host
// ("facet.environment", <facet/shader_abi.h>), for kLanes points at once.
//
//     const Environment env = environment_of(f);   // f: the Fragment
//     if (env) {
//         diffuse  = albedo * env.irradiance(n);
//         const Vec2 ab = env.brdf(n_v, roughness);
//         specular = env.specular(reflect(-v, n), roughness) * (f0 * ab.x + ab.y);
//     }
//
// irradiance() is irradiance / pi: for a uniform environment of radiance L,
// L, so that it takes the place of a constant ambient term. specular() is
// the radiance the split sum prefilters with the GGX lobe of a perceptual
// roughness (alpha its square), and brdf() the scale and bias that turn it
// into reflected light for a Fresnel reflectance f0 (Karis 2013).
#pragma once

#include <facet/shader.hpp>

namespace facet::sdk {

class Environment {
public:
    explicit Environment(const facet_environment* e) : e_(e) {}
    // Whether the draw's scene lights by an environment.
    explicit operator bool() const { return e_ != nullptr; }

    // Irradiance / pi at unit normals n (world space): at least 0.
    Vec3 irradiance(const Vec3& n) const {
        const Vec3 d = to_environment(n);
        const auto c = [&](int k) { return glm::vec3(e_->irradiance[k][0], e_->irradiance[k][1],
                                                     e_->irradiance[k][2]); };
        Vec3 r = Vec3(c(0)) + c(1) * d.y + c(2) * d.z + c(3) * d.x + c(4) * (d.x * d.y) +
                 c(5) * (d.y * d.z) + c(6) * (3.0f * d.z * d.z - 1.0f) + c(7) * (d.x * d.z) +
                 c(8) * (d.x * d.x - d.y * d.y);
        return max(r, Vec3(splat(0.0f)));
    }

    // The prefiltered radiance around directions r (world space, any
    // length) at perceptual roughness 0..1: the two levels around it,
    // each bilinear, mixed (trilinear).
    Vec3 specular(const Vec3& r, const Float& roughness) const {
        const float top = float(e_->levels - 1);
        const Float level = clamp(select(roughness == roughness, roughness, splat(0.0f)), 0.0f,
                                  1.0f) * top;
        const Float below = floor(level);
        const Mask l0 = __builtin_convertvector(below, Mask);
        const Mask l1 = min_index(l0 + 1, Mask{} + int32_t(e_->levels - 1));
        const CubePoint p = cube_point(to_environment(r));
        const Float t = level - below;
        const Vec3 lower = at_level(p, l0);
        // mix(a, b, 0) is a: one level where every lane is on one (the
        // roughest, or a roughness that falls on a level).
        if (all(l1 == l0 || t == 0.0f)) return lower * e_->intensity;
        return mix(lower, at_level(p, l1), t) * e_->intensity;
    }

    // Level `level` alone (0: the environment itself) around directions r
    // (world space, any length), bilinear.
    Vec3 radiance(const Vec3& r, int level) const {
        const int top = int(e_->levels) - 1;
        const uint32_t l = uint32_t(level < 0 ? 0 : level > top ? top : level);
        return bilinear(cube_point(to_environment(r)), Mask{} + int32_t(e_->size[l]),
                        Mask{} + int32_t(e_->offset[l])) * e_->intensity;
    }

    // The split-sum scale (x) and bias (y) at n.v and perceptual roughness,
    // each 0..1.
    Vec2 brdf(const Float& n_v, const Float& roughness) const {
        const int n = int(e_->brdf_size);
        const float top = float(n - 1);
        const Float x = unit(n_v) * top, y = unit(roughness) * top;
        const Float x0 = min(floor(x), splat(top - 1.0f)), y0 = min(floor(y), splat(top - 1.0f));
        const Float fx = x - x0, fy = y - y0;
        const Mask cell = (__builtin_convertvector(y0, Mask) * n + __builtin_convertvector(x0, Mask)) * 4;
        Float lo[4], hi[4];
        gather4(e_->brdf, cell, lo);
        gather4(e_->brdf, cell + 4 * n, hi);
        const Float a = mix(mix(lo[0], lo[2], fx), mix(hi[0], hi[2], fx), fy);
        const Float b = mix(mix(lo[1], lo[3], fx), mix(hi[1], hi[3], fx), fy);
        return {a, b};
    }

private:
    const facet_environment* e_;

    static Mask min_index(const Mask& a, const Mask& b) { return select(a < b, a, b); }
    // x within 0..1, NaN as 0.
    static Float unit(const Float& x) {
        return clamp(select(x == x, x, splat(0.0f)), 0.0f, 1.0f);
    }

    Vec3 to_environment(const Vec3& v) const {
        const float* m = e_->to_environment;
        return {m[0] * v.x + m[3] * v.y + m[6] * v.z, m[1] * v.x + m[4] * v.y + m[7] * v.z,
                m[2] * v.x + m[5] * v.y + m[8] * v.z};
    }

    // Where a direction meets the cube: the face of its largest component
    // (x before y before z), and (u, v) 0..1 across it.
    struct CubePoint {
        Mask face;
        Float u, v;
    };
    static CubePoint cube_point(const Vec3& d) {
        const Float ax = abs(d.x), ay = abs(d.y), az = abs(d.z);
        const Mask x_major = ax >= ay && ax >= az, y_major = !x_major && ay >= az;
        const Float major = select(x_major, ax, select(y_major, ay, az));
        const Mask positive = select(x_major, d.x > 0.0f, select(y_major, d.y > 0.0f, d.z > 0.0f));
        const Mask face = select(x_major, Mask{}, select(y_major, Mask{} + 2, Mask{} + 4)) +
                          select(positive, Mask{}, Mask{} + 1);
        const Float sc = select(x_major, select(positive, -d.z, d.z),
                                select(y_major, d.x, select(positive, d.x, -d.x)));
        const Float tc = select(y_major, select(positive, d.z, -d.z), -d.y);
        // No direction (0, subnormal, infinite or NaN): the face's middle;
        // and a NaN left in a coordinate (a NaN minor component) too.
        const Mask valid = major > 1e-30f && major < 3.0e38f;
        const Float inv = 0.5f / select(valid, major, splat(1.0f));
        const Float u = sc * inv + 0.5f, v = tc * inv + 0.5f;
        return {face, select(valid && u == u, u, splat(0.5f)), select(valid && v == v, v, splat(0.5f))};
    }

    // Level l (per lane) at p: one read of the level's numbers where every
    // lane is at one level (a material of one roughness), else a gather.
    Vec3 at_level(const CubePoint& p, const Mask& l) const {
        if (all(l == l[0]))
            return bilinear(p, Mask{} + int32_t(e_->size[l[0]]), Mask{} + int32_t(e_->offset[l[0]]));
        const Mask size = std::bit_cast<Mask>(
            gather(reinterpret_cast<const float*>(e_->size), l, Mask{} - 1, 0.0f));
        const Mask offset = std::bit_cast<Mask>(
            gather(reinterpret_cast<const float*>(e_->offset), l, Mask{} - 1, 0.0f));
        return bilinear(p, size, offset);
    }

    // The four texels around p of the bordered faces `size` a side from
    // texel `offset`, mixed.
    Vec3 bilinear(const CubePoint& p, const Mask& size, const Mask& offset) const {
        const Float s = __builtin_convertvector(size, Float);
        const Float x = clamp(p.u * s - 0.5f, splat(-0.5f), s - 0.5f);
        const Float y = clamp(p.v * s - 0.5f, splat(-0.5f), s - 0.5f);
        const Float x0 = floor(x), y0 = floor(y);
        const Float fx = x - x0, fy = y - y0;
        const Mask row = size + 2;
        const Mask texel = offset + p.face * row * row +
                           (__builtin_convertvector(y0, Mask) + 1) * row +
                           __builtin_convertvector(x0, Mask) + 1;
        Float t[4];
        bilinear4(e_->texels, texel * 4, (texel + row) * 4, fx, fy, t);
        return {t[0], t[1], t[2]};
    }
};

// The environment lighting a fragment batch, or one that reads false
// (looked up once a batch).
inline Environment environment_of(const Fragment& f) {
    return Environment(f.batch_->environment());
}

// The environment lighting draw d, or one that reads false (looked up at
// each call: for a vertex function).
inline Environment environment_of(const Draw& d) {
    const auto* service = static_cast<const facet_environment_service*>(
        d.raw->host->extension(FACET_ENVIRONMENT_EXTENSION, FACET_ENVIRONMENT_VERSION));
    return Environment(service && service->struct_size >= sizeof(facet_environment_service)
                           ? service->lighting(d.raw)
                           : nullptr);
}

}  // namespace facet::sdk
