#include "reference/environment.hpp"

#include "reference/raycast.hpp"

#include <facet/color.hpp>
#include <facet/math.hpp>

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

namespace facet::reference {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

EnvironmentImage::EnvironmentImage(const std::filesystem::path& file) {
    int channels = 0;
    float* p = stbi_loadf(file.string().c_str(), &width, &height, &channels, 3);
    if (!p) throw std::runtime_error(file.string() + ": " + stbi_failure_reason());
    rgb.assign(p, p + size_t(width) * size_t(height) * 3);
    stbi_image_free(p);
}

glm::dvec3 EnvironmentImage::at(int x, int y) const {
    x = ((x % width) + width) % width;
    y = std::clamp(y, 0, height - 1);
    const float* t = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
    return {t[0], t[1], t[2]};
}

glm::dvec3 EnvironmentImage::radiance(const glm::dvec3& d) const {
    const double u = (0.5 + std::atan2(d.x, -d.z) / (2.0 * kPi)) * width - 0.5;
    const double v = std::clamp(std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi * height - 0.5,
                                0.0, double(height - 1));
    const int x0 = int(std::floor(u)), y0 = int(v);
    const double fx = u - x0, fy = v - y0;
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx),
                    glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

namespace {

// Directions drawn in proportion to the image's luminance times each
// pixel's solid angle: a pixel by its row's and then its column's
// cumulative sums, a direction uniform in solid angle within it. The sun
// of a sky is a few pixels that hold most of its light: without this, a
// reference would almost never find it.
class ImageSampler {
public:
    explicit ImageSampler(const EnvironmentImage& image) : image_(image) {
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
    const EnvironmentImage& image_;
    std::vector<double> rows_, columns_;
};

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
    const EnvironmentImage& image;
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

void reference_rows(const Scene& scene, const RayCaster& rc, const EnvironmentImage& image,
                    const ImageSampler& sampler, int samples, int first, int step, EnvironmentTruth& r, double& noise2, int& count) {
    const Lighting light{image, sampler, glm::dmat3(scene.environment.to_environment()),
                         scene.environment.settings.intensity};
    for (int y = first; y < r.height; y += step)
        for (int x = 0; x < r.width; ++x) {
            const size_t i = size_t(y) * size_t(r.width) + size_t(x);
            glm::dvec3 origin, dir;
            RayCaster::camera_ray(scene, x + 0.5, y + 0.5, origin, dir);
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
            const Mesh& mesh = *o.drawn_mesh();
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

}  // namespace

EnvironmentTruth environment_truth(const Scene& scene, const EnvironmentImage& image, int samples,
                                   int threads) {
    EnvironmentTruth r;
    r.width = scene.settings.width, r.height = scene.settings.height;
    const size_t pixels = size_t(r.width) * size_t(r.height);
    r.color.assign(pixels, glm::dvec3(0.0));
    r.object.assign(pixels, -2);
    r.measured.assign(pixels, 0);
    const RayCaster rc(scene);
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

EnvironmentError environment_error(const Framebuffer& frame, const EnvironmentTruth& r,
                                   double exposure) {
    double s_rel = 0, s_code = 0, k_rel = 0, k_code = 0;
    EnvironmentError e;
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
            double& largest = sky ? e.sky_max : e.surface_max;
            largest = std::max(largest, std::sqrt(glm::dot(d, d) / 3.0));
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

}  // namespace facet::reference
