// Environments (facet/environment_map.hpp): the image files read into linear
// light, their radiance in any direction, the prefilter's settings, the
// process's cache of results (and the one on disk: environment_cache.hpp),
// and the record a frame hands shaders.
#include "facet/environment_map.hpp"

#include "assets/decoder_peak.hpp"
#include "assets/environment_cache.hpp"
#include "assets/environment_prefilter.hpp"
#include "assets/hdr_check.hpp"
#include "assets/image_decoder.hpp"
#include "base/file_digest.hpp"

#include "facet/color.hpp"
#include "facet/error.hpp"
#include "facet/memory.hpp"
#include "facet/pipeline.hpp"
#include "facet/texture.hpp"

#include <spdlog/spdlog.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <mutex>

namespace facet {

namespace {

// An image in linear RGB.
struct FloatImage {
    std::string source;
    int width = 0, height = 0;
    std::vector<float> rgb;

    glm::vec3 at(int x, int y) const {
        const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

// An HDR file's radiance as it is; an 8-bit image's decoded from sRGB.
// (A change to what this, the radiance functions below or prefilter_input
// give changes kept maps: kPrefilterVersion, environment_prefilter.hpp.)
FloatImage decode_image(const std::string& bytes, const std::string& source) {
    FloatImage image;
    image.source = source;
    const std::optional<ImageInfo> info = image_info(bytes, source);
    if (!info) {
        if (looks_like_hdr(bytes)) check_hdr(bytes, source);  // says what is wrong with its header
        throw Error(ErrorCode::texture_load_failed,
                    "not an image facet reads: " + image_failure_reason(), source);
    }
    image.width = info->width, image.height = info->height;
    if (image.width <= 0 || image.height <= 0)
        throw Error(ErrorCode::texture_load_failed,
                    "an image of " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + " pixels: it has none",
                    source);
    const uint64_t pixels = uint64_t(image.width) * uint64_t(image.height);
    // the decoder's floats, then ours; or its 8-bit pixels and its peak
    require_within_budget(
        info->hdr ? pixels * 24 : pixels * 12 + decoder_peak_bytes(bytes, uint64_t(image.width),
                                                                   uint64_t(image.height)),
        "a " + std::to_string(image.width) + "x" + std::to_string(image.height) + " environment image",
        source);
    if (info->hdr) {
        check_hdr(bytes, source);
        image.rgb = decode_float_rgb(bytes, source, image.width, image.height);
        if (image.width <= 0 || image.height <= 0)
            throw Error(ErrorCode::texture_load_failed, "an image of no pixels", source);
    } else {
        const Pixels8 p = decode_8bit(bytes, 3, source);
        image.rgb.resize(pixels * 3);
        for (size_t i = 0; i < pixels * 3; ++i) image.rgb[i] = srgb8_to_linear(p.data[i]);
        spdlog::info("environment {}: an 8-bit image, whose light stops at 1 (an .hdr file "
                     "keeps the sky's range)",
                     source);
    }
    for (float& v : image.rgb)  // RGBE holds neither; a sum of them could overflow
        if (!(v >= 0.0f) || v > 6.5e4f) v = std::isnan(v) || v < 0.0f ? 0.0f : 6.5e4f;
    return image;
}

// Bilinear in an equirectangular image at unit direction d: columns wrap
// around, rows clamp at the poles (load_cube's mapping).
glm::vec3 equirect_radiance(const FloatImage& image, glm::dvec3 direction) {
    const glm::vec3 d(direction);  // in float: a texel is far coarser than its rounding
    constexpr float pi = float(kEnvironmentPi);
    const float u = (0.5f + std::atan2(d.x, -d.z) / (2.0f * pi)) * float(image.width) - 0.5f;
    const float v = std::clamp(std::acos(std::clamp(d.y, -1.0f, 1.0f)) / pi * float(image.height) - 0.5f,
                               0.0f, float(image.height - 1));
    const int w = image.width, left = int(std::floor(u)), y0 = int(v);
    const float fx = u - float(left), fy = v - float(y0);
    // u lies in [-0.5, w - 0.5]: the columns either side, wrapped
    const int x0 = left < 0 ? left + w : left, x1 = left + 1 >= w ? left + 1 - w : left + 1;
    const int y1 = std::min(y0 + 1, image.height - 1);
    return glm::mix(glm::mix(image.at(x0, y0), image.at(x1, y0), fx),
                    glm::mix(image.at(x0, y1), image.at(x1, y1), fx), fy);
}

// Bilinear in six square faces at direction d, each clamped to its edges.
glm::vec3 faces_radiance(const std::vector<FloatImage>& faces, glm::dvec3 d) {
    glm::vec2 uv;
    const FloatImage& f = faces[size_t(cube_face(glm::vec3(d), uv))];
    const int n = f.width;
    const float x = std::clamp(uv.x * float(n) - 0.5f, 0.0f, float(n - 1));
    const float y = std::clamp(uv.y * float(n) - 0.5f, 0.0f, float(n - 1));
    const int x0 = int(x), y0 = int(y), x1 = std::min(x0 + 1, n - 1), y1 = std::min(y0 + 1, n - 1);
    const float fx = x - float(x0), fy = y - float(y0);
    return glm::mix(glm::mix(f.at(x0, y0), f.at(x1, y0), fx), glm::mix(f.at(x0, y1), f.at(x1, y1), fx),
                    fy);
}

int floor_power_of_two(int n) { return n < 1 ? 1 : int(std::bit_floor(unsigned(n))); }

// The prefilter's input for the images of `settings`.
PrefilterInput prefilter_input(const EnvironmentSettings& settings,
                               std::shared_ptr<std::vector<FloatImage>> images) {
    PrefilterInput in;
    in.source = images->front().source;
    in.samples = settings.samples;
    const bool equirect = images->size() == 1;
    const int natural = equirect ? images->front().height / 2 : images->front().width;
    in.size = settings.size > 0 ? settings.size : std::clamp(floor_power_of_two(natural), 8, 1024);
    // Level 0's texels each the mean of as many directions as the image has
    // texels a side there (up to 4 x 4): one, at the image's own size.
    in.supersample = std::clamp((natural + in.size - 1) / in.size, 1, 4);
    if (equirect)
        in.radiance = [images](glm::dvec3 d) { return equirect_radiance(images->front(), d); };
    else
        in.radiance = [images](glm::dvec3 d) { return faces_radiance(*images, d); };
    return in;
}

std::shared_ptr<std::vector<FloatImage>> read_images(const EnvironmentSettings& settings,
                                                     const std::vector<std::string>& bytes) {
    auto images = std::make_shared<std::vector<FloatImage>>();
    for (size_t i = 0; i < bytes.size(); ++i)
        images->push_back(decode_image(bytes[i], settings.files[i].string()));
    if (images->size() == 6)
        for (const FloatImage& f : *images)
            if (f.width != f.height || f.width != images->front().width)
                throw Error(ErrorCode::texture_load_failed,
                            "a cube face of " + std::to_string(f.width) + "x" +
                                std::to_string(f.height) + ": the six must be square and of one size (the first is " +
                                std::to_string(images->front().width) + "x" +
                                std::to_string(images->front().height) + ")",
                            f.source);
    return images;
}

// Results by content and settings (the key the disk's files go by too),
// while some scene holds them.
std::mutex cache_mutex;
std::map<EnvironmentCacheKey, std::weak_ptr<const EnvironmentMaps>> cache;

// The maps of the images in `bytes`, decoded and prefiltered on `threads`.
std::shared_ptr<const EnvironmentMaps> prefiltered(const EnvironmentSettings& settings,
                                                   std::vector<std::string>& bytes, int threads) {
    const auto images = read_images(settings, bytes);
    bytes.clear();
    const PrefilterInput in = prefilter_input(settings, images);
    require_within_budget(prefilter_bytes(in.size),
                          "prefiltering an environment of " + std::to_string(in.size) +
                              " texels a side",
                          in.source);
    ThreadPool pool(threads > 0 ? threads : default_threads());
    const auto start = std::chrono::steady_clock::now();
    auto maps = std::make_shared<const EnvironmentMaps>(prefilter_environment(in, pool));
    spdlog::info("environment {}: {} levels from {} texels a side, {} samples, in {:.0f} ms",
                 in.source, maps->levels, in.size, in.samples,
                 std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count());
    return maps;
}

}  // namespace

std::shared_ptr<const EnvironmentMaps> load_environment(const EnvironmentSettings& settings,
                                                         int threads) {
    if (settings.files.size() != 1 && settings.files.size() != 6)
        throw Error(ErrorCode::config_invalid,
                    "an environment is one equirectangular image or six cube faces, not " +
                        std::to_string(settings.files.size()) + " files");
    std::vector<std::string> bytes;
    EnvironmentCacheKey key{{}, settings.size, settings.samples};
    for (const auto& file : settings.files) {
        bytes.push_back(read_image_file(file));
        key.digests.push_back(bytes_digest(bytes.back()));
    }
    {
        const std::lock_guard lock(cache_mutex);
        const auto found = cache.find(key);  // a lookup inserts nothing
        if (auto held = found == cache.end() ? nullptr : found->second.lock()) {
            spdlog::debug("environment {}: prefiltered already", held->source);
            return held;
        }
    }
    brdf_table();  // made at the first load, not in the first frame
    const auto kept = environment_cache_file(key);
    std::shared_ptr<const EnvironmentMaps> maps =
        kept ? read_environment_cache(*kept, settings.files.front().string()) : nullptr;
    if (maps) {
        spdlog::debug("environment {}: prefiltered maps read from {}", maps->source, kept->string());
    } else {
        maps = prefiltered(settings, bytes, threads);
        if (kept) write_environment_cache(*kept, *maps);
    }
    const std::lock_guard lock(cache_mutex);
    std::erase_if(cache, [](const auto& entry) { return entry.second.expired(); });
    cache[key] = maps;
    return maps;
}

glm::vec3 sample_environment(const EnvironmentMaps& maps, int level, glm::vec3 d) {
    level = std::clamp(level, 0, maps.levels - 1);
    return bilinear_bordered(int(maps.size[size_t(level)]), d, [&](int f, int x, int y) {
        return maps.texel(level, f, x, y);
    });
}

glm::vec3 environment_irradiance(const EnvironmentMaps& maps, glm::vec3 n) {
    const auto& c = maps.irradiance;
    const glm::vec3 r = c[0] + c[1] * n.y + c[2] * n.z + c[3] * n.x + c[4] * (n.x * n.y) +
                        c[5] * (n.y * n.z) + c[6] * (3.0f * n.z * n.z - 1.0f) + c[7] * (n.x * n.z) +
                        c[8] * (n.x * n.x - n.y * n.y);
    return glm::max(r, glm::vec3(0.0f));
}

glm::mat3 Environment::to_environment() const {
    const glm::vec3 r = glm::radians(settings.rotation);
    glm::mat4 m(1.0f);  // X, then Y, then Z: Z Y X applied to a direction
    m = glm::rotate(m, r.z, glm::vec3(0, 0, 1));
    m = glm::rotate(m, r.y, glm::vec3(0, 1, 0));
    m = glm::rotate(m, r.x, glm::vec3(1, 0, 0));
    return glm::transpose(glm::mat3(m));
}

facet_environment Environment::record() const {
    facet_environment e{};
    e.struct_size = sizeof e;
    if (!maps) return e;
    e.levels = uint32_t(maps->levels);
    const glm::mat3 m = to_environment();
    std::memcpy(e.to_environment, &m[0][0], sizeof e.to_environment);
    e.intensity = settings.intensity;
    // The polynomial of a rotated normal is the polynomial of the
    // environment's frame: the rotation is applied to n, not folded here.
    for (int k = 0; k < 9; ++k)
        for (int c = 0; c < 3; ++c) e.irradiance[k][c] = maps->irradiance[size_t(k)][c] * settings.intensity;
    for (int l = 0; l < maps->levels; ++l) {
        e.size[l] = maps->size[size_t(l)];
        e.offset[l] = maps->offset[size_t(l)];
    }
    e.texels = maps->texels.data();
    const BrdfTable& brdf = brdf_table();
    e.brdf_size = uint32_t(brdf.size);
    e.brdf = brdf.cells.data();
    return e;
}

}  // namespace facet
