// facet-bench-environment: image-based lighting's cost and error.
//
//     facet-bench-environment [--scene FILE] [--size WxH] [--runs N]
//                             [--threads N] [--reference-samples N]
//
// On a scene lit by an environment (by default the demo,
// configs/scenes/environment.yaml), measured side by side in one run:
//   - prefilter: load_environment() of a 2048x1024 HDR (the scene's image,
//     resampled) at its own size, median of --runs, on --threads threads;
//   - frames: the scene with no environment (each pbr material's constant
//     ambient), lit by it with no sky, and lit with the sky behind, frames
//     interleaved, medians (the scene's post chain in all three);
//   - error: the lit frame (post chain off, rgba32f) against a Monte Carlo
//     reference in double precision, which integrates pbr's own BRDF
//     (Lambert times 1 - F, GGX, Smith height-correlated, Schlick) against
//     the scene's HDR image itself, unoccluded as facet's lighting is, at
//     the centre of each pixel whose neighbours see the same object
//     (--reference-samples directions a pixel, GGX and cosine samples mixed,
//     one-sample MIS); and the sky against the image along each pixel's ray.
//     Errors are relative RMSE of linear RGB, and RMSE in 8-bit sRGB codes
//     at the scene's post exposure (2^exposure, clamped).
//   - quality: the same error and frame time for level-0 sizes and sample
//     counts (the prefilter's settings), with the Pareto front marked.
#include "reference/raycast.hpp"

#include <facet/color.hpp>
#include <facet/command_line.hpp>
#include <facet/environment_map.hpp>
#include <facet/isa.hpp>
#include <facet/math.hpp>
#include <facet/paths.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/tool.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

using namespace facet;

namespace {

constexpr double kPi = 3.14159265358979323846;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// An equirectangular HDR image in double, read as the reference reads it.
struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;

    explicit Image(const std::filesystem::path& file) {
        int channels = 0;
        float* p = stbi_loadf(file.string().c_str(), &width, &height, &channels, 3);
        if (!p) throw std::runtime_error(file.string() + ": " + stbi_failure_reason());
        rgb.assign(p, p + size_t(width) * size_t(height) * 3);
        stbi_image_free(p);
    }
    glm::dvec3 at(int x, int y) const {
        x = ((x % width) + width) % width;
        y = std::clamp(y, 0, height - 1);
        const float* t = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
        return {t[0], t[1], t[2]};
    }
    // Bilinear at unit direction d (load_cube's mapping).
    glm::dvec3 radiance(const glm::dvec3& d) const {
        const double u = (0.5 + std::atan2(d.x, -d.z) / (2.0 * kPi)) * width - 0.5;
        const double v = std::clamp(std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi * height - 0.5,
                                    0.0, double(height - 1));
        const int x0 = int(std::floor(u)), y0 = int(v);
        const double fx = u - x0, fy = v - y0;
        return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx),
                        glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
    }
};

// Directions drawn in proportion to the image's luminance times each
// pixel's solid angle: a pixel by its row's and then its column's
// cumulative sums, a direction uniform in solid angle within it. The sun
// of a sky is a few pixels that hold most of its light: without this, a
// reference would almost never find it.
class ImageSampler {
public:
    explicit ImageSampler(const Image& image) : image_(image) {
        const int w = image.width, h = image.height;
        rows_.assign(size_t(h) + 1, 0.0);
        columns_.assign(size_t(h) * size_t(w + 1), 0.0);
        double mean = 0.0;
        for (float v : image.rgb) mean += v;
        mean /= double(image.rgb.size());
        for (int y = 0; y < h; ++y) {
            double* c = &columns_[size_t(y) * size_t(w + 1)];
            for (int x = 0; x < w; ++x) {
                // The brightest of the pixel and its neighbours: the image is
                // read bilinearly, so a pixel beside the sun holds some of it.
                double lum = 0.0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const glm::dvec3 t = image.at(x + dx, y + dy);
                        lum = std::max(lum, 0.2126 * t.x + 0.7152 * t.y + 0.0722 * t.z);
                    }
                c[x + 1] = c[x] + (lum + 1e-3 * mean) * solid_angle(y);
            }
            rows_[size_t(y) + 1] = rows_[size_t(y)] + c[w];
        }
    }

    // A direction (the image's frame) from two uniform numbers, and its pdf.
    glm::dvec3 sample(double u1, double u2, double& pdf) const {
        const int h = image_.height, w = image_.width;
        const double r = u1 * rows_.back();
        const int y = std::clamp(int(std::upper_bound(rows_.begin(), rows_.end(), r) - rows_.begin()) - 1, 0, h - 1);
        const double* c = &columns_[size_t(y) * size_t(w + 1)];
        const double cr = u2 * c[w];
        const int x = std::clamp(int(std::upper_bound(c, c + w + 1, cr) - c) - 1, 0, w - 1);
        // Uniform in the pixel: the leftover of each draw, rescaled.
        const double fy = std::clamp((r - rows_[size_t(y)]) / (rows_[size_t(y) + 1] - rows_[size_t(y)]), 0.0, 1.0);
        const double fx = std::clamp((cr - c[x]) / (c[x + 1] - c[x]), 0.0, 1.0);
        const double cos0 = std::cos(kPi * y / h), cos1 = std::cos(kPi * (y + 1) / h);
        const double cos_t = cos0 + (cos1 - cos0) * fy, sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
        const double phi = ((x + fx) / w - 0.5) * 2 * kPi;
        const glm::dvec3 d(sin_t * std::sin(phi), cos_t, -sin_t * std::cos(phi));
        pdf = density(d);
        return d;
    }
    // The pdf of unit direction d (the image's frame), per steradian.
    double density(const glm::dvec3& d) const {
        const int h = image_.height, w = image_.width;
        const int y = std::clamp(int(std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi * h), 0, h - 1);
        const int x = std::clamp(int((0.5 + std::atan2(d.x, -d.z) / (2 * kPi)) * w), 0, w - 1);
        const double* c = &columns_[size_t(y) * size_t(w + 1)];
        return (c[x + 1] - c[x]) / rows_.back() / solid_angle(y);
    }

private:
    double solid_angle(int y) const {
        const int h = image_.height;
        return 2 * kPi / image_.width * (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h));
    }
    const Image& image_;
    std::vector<double> rows_, columns_;
};

// ---- the reference -------------------------------------------------------------

struct PbrSurface {
    glm::dvec3 c_diff, f0;
    double a2 = 0.0;
};

double number(const Material& m, const std::string& name, double fallback, int k = 0) {
    for (const MaterialParam& p : m.params)
        if (p.name == name && size_t(k) < p.numbers.size()) return p.numbers[size_t(k)];
    return fallback;
}

PbrSurface surface_of(const Material& m) {
    const glm::dvec3 base(number(m, "base_color", 1, 0), number(m, "base_color", 1, 1),
                          number(m, "base_color", 1, 2));
    const double metallic = number(m, "metallic", 0.0);
    const double roughness = std::max(number(m, "roughness", 0.5), 0.03);  // as pbr holds it
    const double a = roughness * roughness;
    return {base * (1.0 - metallic), glm::mix(glm::dvec3(0.04), base, metallic), a * a};
}

// pbr's BRDF times n.l, and the two sampling densities of l.
struct Lobe {
    glm::dvec3 value;
    double pdf_ggx, pdf_cosine;
};

Lobe brdf(const PbrSurface& s, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l) {
    const double n_l = glm::dot(n, l), n_v = std::max(glm::dot(n, v), 1e-4);
    if (n_l <= 0.0) return {glm::dvec3(0.0), 0.0, 0.0};
    const glm::dvec3 h = glm::normalize(l + v);
    const double n_h = std::max(glm::dot(n, h), 0.0), v_h = std::max(glm::dot(v, h), 0.0);
    const glm::dvec3 f = s.f0 + (1.0 - s.f0) * std::pow(1.0 - v_h, 5.0);
    const double k = n_h * n_h * (s.a2 - 1.0) + 1.0;
    const double d = s.a2 / (kPi * k * k);
    const double vis = 0.5 / (n_l * std::sqrt(n_v * n_v * (1.0 - s.a2) + s.a2) +
                              n_v * std::sqrt(n_l * n_l * (1.0 - s.a2) + s.a2));
    const glm::dvec3 value = ((1.0 - f) * s.c_diff / kPi + f * (d * vis)) * n_l;
    return {value, v_h > 0.0 ? d * n_h / (4.0 * v_h) : 0.0, n_l / kPi};
}

// A frame (t, b, n) around unit n.
void frame_of(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
    const double sign = std::copysign(1.0, n.z), a = -1.0 / (sign + n.z), c = n.x * n.y * a;
    t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

// The environment a reference pixel sees: the image's radiance in world
// direction l, and the image's sampler.
struct Lighting {
    const Image& image;
    const ImageSampler& sampler;
    glm::dmat3 to_env;  // world -> the image's frame (a rotation)
    double intensity;
    glm::dvec3 radiance(const glm::dvec3& l) const {
        return image.radiance(glm::normalize(to_env * l)) * intensity;
    }
};

// The i-th of n points of the unit square (Hammersley), rotated by `seed`.
glm::dvec2 hammersley(int i, int n, uint32_t seed) {
    uint32_t bits = uint32_t(i);
    bits = (bits << 16) | (bits >> 16);
    bits = ((bits & 0x00FF00FFu) << 8) | ((bits & 0xFF00FF00u) >> 8);
    bits = ((bits & 0x0F0F0F0Fu) << 4) | ((bits & 0xF0F0F0F0u) >> 4);
    bits = ((bits & 0x33333333u) << 2) | ((bits & 0xCCCCCCCCu) >> 2);
    bits = ((bits & 0x55555555u) << 1) | ((bits & 0xAAAAAAAAu) >> 1);
    const double r1 = (seed & 0xFFFF) / 65536.0, r2 = (seed >> 16) / 65536.0;
    return {std::fmod((i + 0.5) / n + r1, 1.0), std::fmod(bits * 0x1p-32 + r2, 1.0)};
}

// Reflected radiance towards v, by `samples` directions, a third each from
// the GGX distribution of half vectors, the cosine and the image's
// luminance, each weighted by the mixture of the three densities (one-sample
// MIS, balance heuristic). Its standard error too.
glm::dvec3 reflected(const PbrSurface& s, const glm::dvec3& n, const glm::dvec3& v,
                     const Lighting& light, int samples, uint32_t seed, double& error) {
    glm::dvec3 t, b;
    frame_of(n, t, b);
    const glm::dmat3 from_env = glm::transpose(light.to_env);
    const int per = std::max(1, samples / 3);
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int i = 0; i < 3 * per; ++i) {
        const glm::dvec2 u = hammersley(i / 3, per, seed * 3u + uint32_t(i % 3));
        glm::dvec3 l;
        if (i % 3 == 0) {
            const double cos_h = std::sqrt((1.0 - u.y) / (1.0 + (s.a2 - 1.0) * u.y));
            const double sin_h = std::sqrt(std::max(0.0, 1.0 - cos_h * cos_h));
            const glm::dvec3 h = t * (sin_h * std::cos(2 * kPi * u.x)) +
                                 b * (sin_h * std::sin(2 * kPi * u.x)) + n * cos_h;
            l = 2.0 * glm::dot(v, h) * h - v;
        } else if (i % 3 == 1) {
            const double r = std::sqrt(u.y);
            l = t * (r * std::cos(2 * kPi * u.x)) + b * (r * std::sin(2 * kPi * u.x)) +
                n * std::sqrt(std::max(0.0, 1.0 - u.y));
        } else {
            double pdf;
            l = from_env * light.sampler.sample(u.x, u.y, pdf);
        }
        const Lobe f = brdf(s, n, v, l);
        glm::dvec3 x(0.0);
        if (f.value != glm::dvec3(0.0)) {
            const double p_env = light.sampler.density(glm::normalize(light.to_env * l));
            const double pdf = (f.pdf_ggx + f.pdf_cosine + p_env) / 3.0;
            if (pdf > 0.0) x = f.value * light.radiance(l) / pdf;
        }
        sum += x;
        sum2 += x * x;
    }
    const double count = 3.0 * per;
    const glm::dvec3 mean = sum / count;
    const glm::dvec3 variance = glm::max(sum2 / count - mean * mean, glm::dvec3(0.0));
    error = std::sqrt((variance.x + variance.y + variance.z) / 3.0 / count);
    return mean;
}

}  // namespace

namespace {

// The reference image: per pixel its radiance (linear RGB), the object
// seen (-1: the sky), and whether it is measured (its eight neighbours see
// the same object, and that object is pbr).
struct Reference {
    int width = 0, height = 0;
    std::vector<glm::dvec3> color;
    std::vector<int> object;
    std::vector<char> measured;
    double noise = 0.0;  // RMS of the estimates' relative standard errors
};

void reference_rows(const Scene& scene, const reference::RayCaster& rc, const Image& image,
                    const ImageSampler& sampler, int samples, int first, int step, Reference& r, double& noise2, int& count) {
    const Lighting light{image, sampler, glm::dmat3(scene.environment.to_environment()),
                         scene.environment.settings.intensity};
    for (int y = first; y < r.height; y += step)
        for (int x = 0; x < r.width; ++x) {
            const size_t i = size_t(y) * size_t(r.width) + size_t(x);
            glm::dvec3 origin, dir;
            reference::RayCaster::camera_ray(scene, x + 0.5, y + 0.5, origin, dir);
            const auto hit = rc.camera_hit(scene, x + 0.5, y + 0.5);
            if (!hit) {
                r.object[i] = -1;
                r.color[i] = light.radiance(glm::normalize(dir));
                continue;
            }
            r.object[i] = hit->object;
            const Object& o = scene.objects[size_t(hit->object)];
            const Material* m = o.material_of(size_t(hit->part));
            if (!m || m->shader != "pbr") {
                r.object[i] = -2;  // not measured
                continue;
            }
            const Mesh& mesh = *o.mesh;
            const uint32_t* t = &mesh.indices[size_t(hit->triangle) * 3];
            const glm::dvec3 local = (1.0 - hit->u - hit->v) * glm::dvec3(mesh.normals[t[0]]) +
                                     hit->u * glm::dvec3(mesh.normals[t[1]]) +
                                     hit->v * glm::dvec3(mesh.normals[t[2]]);
            const glm::dvec3 n =
                glm::normalize(glm::dmat3(normal_matrix(o.part_matrix(size_t(hit->part)))) * local);
            double error = 0.0;
            r.color[i] = reflected(surface_of(*m), n, glm::normalize(-dir), light, samples,
                                   uint32_t(i * 2654435761u), error);
            const double level = std::max(1e-6, (r.color[i].x + r.color[i].y + r.color[i].z) / 3);
            noise2 += (error / level) * (error / level);
            ++count;
        }
}

Reference reference_image(const Scene& scene, const Image& image, int samples, int threads) {
    Reference r;
    r.width = scene.settings.width, r.height = scene.settings.height;
    const size_t pixels = size_t(r.width) * size_t(r.height);
    r.color.assign(pixels, glm::dvec3(0.0));
    r.object.assign(pixels, -2);
    r.measured.assign(pixels, 0);
    const reference::RayCaster rc(scene);
    const ImageSampler sampler(image);
    std::vector<double> noise2(size_t(threads), 0.0);
    std::vector<int> counts(size_t(threads), 0);
    std::vector<std::thread> workers;
    for (int k = 0; k < threads; ++k)
        workers.emplace_back([&, k] {
            reference_rows(scene, rc, image, sampler, samples, k, threads, r, noise2[size_t(k)],
                           counts[size_t(k)]);
        });
    for (std::thread& w : workers) w.join();
    double sum = 0.0;
    int count = 0;
    for (int k = 0; k < threads; ++k) sum += noise2[size_t(k)], count += counts[size_t(k)];
    r.noise = count ? std::sqrt(sum / count) : 0.0;
    for (int y = 1; y + 1 < r.height; ++y)
        for (int x = 1; x + 1 < r.width; ++x) {
            const size_t i = size_t(y) * size_t(r.width) + size_t(x);
            bool same = r.object[i] != -2;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    same = same && r.object[i + size_t(dy * r.width + dx)] == r.object[i];
            r.measured[i] = same;
        }
    return r;
}

struct Errors {
    double surface_relative = 0, surface_codes = 0, sky_relative = 0, sky_codes = 0;
    int surface_pixels = 0, sky_pixels = 0;
    std::vector<double> object_relative;  // per object: relative RMSE
};

// `frame` (linear, rgba32f) against the reference, on the measured pixels.
Errors compare(const Framebuffer& frame, const Reference& r, double exposure) {
    double s_rel = 0, s_code = 0, k_rel = 0, k_code = 0;
    Errors e;
    std::vector<double> per_sum;
    std::vector<int> per_count;
    const double scale = std::exp2(exposure);
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            const size_t i = size_t(y) * size_t(r.width) + size_t(x);
            if (!r.measured[i]) continue;
            const glm::dvec3 got(glm::vec3(frame.pixel(x, y))), want = r.color[i];
            const double level = std::max(1e-6, (want.x + want.y + want.z) / 3.0);
            const glm::dvec3 d = (got - want) / level;
            double codes = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double a = linear_to_srgb8(float(got[c] * scale));
                const double b = linear_to_srgb8(float(want[c] * scale));
                codes += (a - b) * (a - b);
            }
            const bool sky = r.object[i] == -1;
            (sky ? k_rel : s_rel) += glm::dot(d, d) / 3.0;
            if (!sky) {
                const size_t o = size_t(r.object[i]);
                if (per_sum.size() <= o) per_sum.resize(o + 1, 0.0), per_count.resize(o + 1, 0);
                per_sum[o] += glm::dot(d, d) / 3.0;
                ++per_count[o];
            }
            (sky ? k_code : s_code) += codes / 3.0;
            ++(sky ? e.sky_pixels : e.surface_pixels);
        }
    e.surface_relative = std::sqrt(s_rel / std::max(1, e.surface_pixels));
    e.surface_codes = std::sqrt(s_code / std::max(1, e.surface_pixels));
    e.sky_relative = std::sqrt(k_rel / std::max(1, e.sky_pixels));
    e.sky_codes = std::sqrt(k_code / std::max(1, e.sky_pixels));
    for (size_t o = 0; o < per_sum.size(); ++o)
        e.object_relative.push_back(per_count[o] ? std::sqrt(per_sum[o] / per_count[o]) : 0.0);
    return e;
}

}  // namespace

namespace {

struct Frames {
    double none = 0, lighting = 0, both = 0;
};

// The scene with no environment, lit by it, and lit with the sky: frames
// interleaved, medians.
Frames time_frames(const Scene& scene, int threads, int runs) {
    Scene none = scene, lighting = scene;
    none.environment = {};
    lighting.environment.settings.use = EnvironmentUse::lighting;
    Renderer renderer(threads);
    Framebuffer fb;
    std::vector<double> t[3];
    for (int i = 0; i < runs + 1; ++i) {  // the first round warms up
        const Scene* scenes[3] = {&none, &lighting, &scene};
        for (int k = 0; k < 3; ++k) {
            const double ms = renderer.render(*scenes[k], fb).milliseconds;
            if (i > 0) t[k].push_back(ms);
        }
    }
    return {median(t[0]), median(t[1]), median(t[2])};
}

// The scene's image resampled to 2048 x 1024, written to `file`.
void write_2048(const Image& image, const std::filesystem::path& file) {
    const int w = 2048, h = 1024;
    std::vector<float> rgb;
    rgb.reserve(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double phi = ((x + 0.5) / w - 0.5) * 2 * kPi, theta = (y + 0.5) / h * kPi;
            const glm::dvec3 d(std::sin(theta) * std::sin(phi), std::cos(theta),
                               -std::sin(theta) * std::cos(phi));
            const glm::dvec3 c = image.radiance(d);
            rgb.insert(rgb.end(), {float(c.x), float(c.y), float(c.z)});
        }
    if (!stbi_write_hdr(file.string().c_str(), w, h, 3, rgb.data()))
        throw std::runtime_error("cannot write " + file.string());
}

double time_prefilter(const EnvironmentSettings& s, int threads, int runs) {
    std::vector<double> t;
    for (int i = 0; i < runs; ++i) {
        const auto start = std::chrono::steady_clock::now();
        const auto maps = load_environment(s, threads);  // dropped before the next: no cache
        t.push_back(ms_since(start));
    }
    return median(t);
}

// The lit frame, post chain off, in floats.
Framebuffer lit_frame(Scene scene, int threads) {
    scene.settings.post = false;
    scene.settings.color_format = ColorFormat::rgba32f;
    scene.environment.settings.use = EnvironmentUse::both;
    Framebuffer fb;
    Renderer(threads).render(scene, fb);
    return fb;
}

void quality_sweep(Scene scene, const Reference& ref, double exposure, int threads) {
    struct Row {
        int size, samples;
        double prefilter, error, codes;
        bool front = true;
    };
    std::vector<Row> rows;
    for (int size : {32, 64, 128, 256, 512})
        for (int samples : {16, 64, 256}) {
            EnvironmentSettings s = scene.environment.settings;
            s.size = size;
            s.samples = samples;
            scene.environment.settings = s;
            scene.environment.maps.reset();
            const auto start = std::chrono::steady_clock::now();
            scene.environment.maps = load_environment(s, threads);
            const double prefilter = ms_since(start);
            const Errors e = compare(lit_frame(scene, threads), ref, exposure);
            rows.push_back({size, samples, prefilter, e.surface_relative, e.surface_codes});
        }
    for (Row& a : rows)
        for (const Row& b : rows)
            if (b.prefilter <= a.prefilter && b.error <= a.error &&
                (b.prefilter < a.prefilter || b.error < a.error))
                a.front = false;
    std::printf("\nquality: level 0's size and GGX samples a texel (the frame's time does not "
                "depend on them)\n%6s %8s %14s %14s %12s %7s\n", "size", "samples",
                "prefilter ms", "surface RMSE", "sRGB codes", "front");
    for (const Row& r : rows)
        std::printf("%6d %8d %14.1f %13.2f%% %12.2f %7s\n", r.size, r.samples, r.prefilter,
                    100 * r.error, r.codes, r.front ? "*" : "");
}

double post_exposure(const Scene& scene) {
    for (const PostPass& p : scene.post)
        if (p.name == "tonemap")
            for (const MaterialParam& m : p.params)
                if (m.name == "exposure" && !m.numbers.empty()) return m.numbers[0];
    return 0.0;
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 7, threads = 2, samples = 256;
    std::string size = "960x540", scene_file = (data_dir() / "configs" / "scenes" / "environment.yaml").string();
    CLI::App app{"Image-based lighting: prefilter time, frame cost, and error against Monte Carlo.",
                 "facet-bench-environment"};
    app.add_option("--scene", scene_file, "a scene with an environment and pbr materials")
        ->capture_default_str();
    app.add_option("--size", size, "image size WxH")->capture_default_str();
    app.add_option("--runs", runs, "frames or prefilters per timing (median)")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    app.add_option("--threads", threads, "threads, counting the caller")
        ->check(CLI::Range(1, 256))->capture_default_str();
    app.add_option("--reference-samples", samples, "Monte Carlo directions per pixel")
        ->check(CLI::Range(2, 1 << 20))->capture_default_str();
    Verbosity verbosity;
    add_common_options(app, verbosity);
    if (const std::optional<int> status = parse_command_line(app, argc, argv)) return *status;
    start_logging(verbosity, spdlog::level::warn);
    const std::optional<glm::ivec2> wh = parse_size(size);
    if (!wh) {
        std::fprintf(stderr, "--size: expected WxH, got '%s'\n", size.c_str());
        return 2;
    }
    PluginRegistry registry;
    Scene scene = load_scene(scene_file, registry);
    if (!scene.environment || scene.environment.settings.files.size() != 1) {
        std::fprintf(stderr, "%s: needs an environment of one equirectangular image\n", scene_file.c_str());
        return 2;
    }
    scene.settings.width = wh->x, scene.settings.height = wh->y;
    const Image image(scene.environment.settings.files[0]);
    std::printf("facet-bench-environment: %s, %dx%d, %d threads, %s path on %s\n", scene_file.c_str(),
                wh->x, wh->y, threads, std::string(isa_name(default_isa())).c_str(), cpu_name().c_str());
    std::printf("environment %s: %dx%d, %d levels from %u a side, %d samples\n",
                scene.environment.settings.files[0].string().c_str(), image.width, image.height,
                scene.environment.maps->levels, scene.environment.maps->size[0],
                scene.environment.settings.samples);

    const std::filesystem::path big = std::filesystem::temp_directory_path() / "facet-bench-2048.hdr";
    write_2048(image, big);
    EnvironmentSettings s2048 = scene.environment.settings;
    s2048.files = {big};
    s2048.size = 0;
    const double prefilter = time_prefilter(s2048, threads, runs);
    std::filesystem::remove(big);
    std::printf("prefilter of a 2048x1024 HDR (its own size, 512): median %.1f ms\n", prefilter);

    const Frames f = time_frames(scene, threads, runs);
    std::printf("frames (the scene's post chain in each), median of %d, interleaved:\n"
                "  no environment %.2f ms, lit by it %.2f ms (x%.2f), lit with the sky %.2f ms (x%.2f)\n",
                runs, f.none, f.lighting, f.lighting / f.none, f.both, f.both / f.none);

    const double exposure = post_exposure(scene);
    const auto start = std::chrono::steady_clock::now();
    const Reference ref = reference_image(scene, image, samples, threads);
    const Errors e = compare(lit_frame(scene, threads), ref, exposure);
    std::printf("error against Monte Carlo (%d directions a pixel, double; its own noise %.2f%%; %.1f s):\n"
                "  surfaces: RMSE %.2f%% of the radiance, %.2f sRGB codes at exposure %g (%d pixels)\n"
                "  sky:      RMSE %.2f%% of the radiance, %.2f sRGB codes (%d pixels)\n",
                samples, 100 * ref.noise, ms_since(start) / 1000, 100 * e.surface_relative,
                e.surface_codes, exposure, e.surface_pixels, 100 * e.sky_relative, e.sky_codes,
                e.sky_pixels);
    std::printf("  by object:");
    for (size_t o = 0; o < e.object_relative.size(); ++o)
        if (e.object_relative[o] > 0.0)
            std::printf("%s %s %.1f%%", o ? "," : "", scene.objects[o].name.c_str(), 100 * e.object_relative[o]);
    std::printf("\n");
    quality_sweep(scene, ref, exposure, threads);
    return 0;
}
