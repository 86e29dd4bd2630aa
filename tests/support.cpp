#include "support.hpp"

#include <facet/error.hpp>

#include <catch2/catch.hpp>

#include <algorithm>

#include <glm/gtc/constants.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <stdexcept>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <unistd.h>

namespace facet::test {

Mesh make_mesh(std::vector<glm::vec3> positions, std::vector<uint32_t> indices,
               std::vector<glm::vec4> colors) {
    Mesh m;
    m.source = "test";
    m.positions = std::move(positions);
    m.indices = std::move(indices);
    m.colors = std::move(colors);
    m.bounds = compute_bounds(m.positions);
    return m;
}

Mesh fan(int n, float radius, float angle, glm::vec2 centre) {
    std::vector<glm::vec3> pos{{centre, 0.5f}};
    std::vector<uint32_t> idx;
    for (int i = 0; i < n; ++i) {
        const float a = angle + glm::two_pi<float>() * float(i) / float(n);
        pos.push_back({centre + radius * glm::vec2(std::cos(a), std::sin(a)), 0.5f});
        idx.insert(idx.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % n)});
    }
    return make_mesh(pos, idx);
}

DrawCall clip_space_call(const Mesh& mesh, const ShaderPlugin& shader) {
    DrawCall call;
    call.mesh = &mesh;
    call.shader = &shader;
    call.state.cull = CullMode::none;
    call.state.depth_compare = DepthCompare::always;
    return call;
}

glm::vec3 window_to_ndc(glm::dvec2 window, int width, int height) {
    return {float(window.x / width * 2.0 - 1.0), float(1.0 - window.y / height * 2.0), 0.5f};
}

double inside_line(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, double w) {
    const glm::dvec2 d = b - a;
    const double length = glm::length(d);
    const glm::dvec2 along = d / length, across(-along.y, along.x);
    const double s = glm::dot(p - a, along), t = glm::dot(p - a, across);
    return std::min({s, length - s, w / 2 - std::abs(t)});
}

void check_coverage(const Framebuffer& fb,
                    const std::function<std::vector<double>(glm::dvec2)>& inside, int& covered) {
    const double tol = 0.02;
    const int n = fb.samples();
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x)
            for (int s = 0; s < n; ++s) {
                const glm::dvec2 p =
                    glm::dvec2(x + 0.5, y + 0.5) + glm::dvec2(sample_offset(n, s)) / 16.0;
                int surely = 0, maybe = 0;
                for (const double d : inside(p)) surely += d > tol, maybe += d > -tol;
                const float count = fb.sample(x, y, s).r;
                INFO("pixel " << x << ", " << y << " sample " << s << ": covered " << count);
                REQUIRE(count >= float(surely));
                REQUIRE(count <= float(maybe));
                covered += count > 0.0f;
            }
}

bool same_image(const Framebuffer& a, const Framebuffer& b) {
    const size_t n = size_t(a.stride()) * size_t(a.rows());
    const size_t bytes = size_t(bytes_per_pixel(a.format()));
    return a.width() == b.width() && a.height() == b.height() && a.format() == b.format() &&
           a.samples() == b.samples() &&
           std::memcmp(a.color_data(), b.color_data(), n * bytes) == 0 &&
           std::memcmp(a.depth(), b.depth(), n * sizeof(float)) == 0;
}

const char* const kDemoScenes[14] = {"default.yaml",           "scenes/lit.yaml",
                                    "scenes/phong.yaml",       "scenes/toon.yaml",
                                    "scenes/shadow.yaml",      "scenes/ao.yaml",
                                    "scenes/showcase.yaml",    "scenes/gallery.yaml",
                                    "scenes/environment.yaml", "scenes/skinning.yaml",
                                    "scenes/blending.yaml",    "scenes/anisotropic.yaml",
                                    "scenes/stencil.yaml",     "scenes/lines.yaml"};

Scene SceneDir::load(const std::string& yaml) {
    write(dir / "scene.yaml", yaml);
    return load_scene(dir / "scene.yaml", registry);
}

std::string SceneDir::error(const std::string& yaml) {
    try {
        load(yaml);
    } catch (const Error& e) {
        return e.what();
    }
    throw std::runtime_error("the scene loaded, with no error");
}

Scene small_demo_scene(PluginRegistry& registry, const std::string& name) {
    Scene s = load_scene(std::string(FACET_SOURCE_DIR) + "/configs/" + name, registry);
    s.settings.width = 197;
    s.settings.height = 111;
    // Maps of 256 texels a side serve an image this small as 2048 serve
    // the scene's own size, through the same code at a 64th of the work
    // (the tests under the sanitizers draw hundreds of them).
    s.settings.shadow_map_size = 256;
    // A demo's environment, prefiltered once: held here, so that each later
    // load of the scene finds it in the process's cache (load_environment).
    static std::mutex holding;
    static std::vector<std::shared_ptr<const EnvironmentMaps>> held;
    const std::lock_guard lock(holding);
    if (s.environment.maps && std::find(held.begin(), held.end(), s.environment.maps) == held.end())
        held.push_back(s.environment.maps);
    return s;
}

PluginSwap::PluginSwap(const Scene& scene,
                       const std::function<std::shared_ptr<ShaderPlugin>(const Material&)>& replace) {
    for (Material* m : scene.materials())
        if (std::shared_ptr<ShaderPlugin> other = replace(*m)) swaps_.emplace_back(m, std::move(other));
}

void PluginSwap::swap() {
    for (auto& [material, plugin] : swaps_) std::swap(material->plugin, plugin);
}

namespace {

std::filesystem::path fresh_folder(const std::string& tag) {
    static std::atomic<int> counter{0};
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                ("facet-test-" + tag + "-" + std::to_string(getpid()) + "-" +
                                 std::to_string(stamp) + "-" + std::to_string(counter++));
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace

TempDir::TempDir(const std::string& tag) : path(fresh_folder(tag)) {}

TempDir::~TempDir() {
    std::error_code ignored;  // a destructor must not throw
    std::filesystem::remove_all(path, ignored);
}

std::filesystem::path TempDir::write(const std::string& name, const std::string& text) const {
    const std::filesystem::path file = path / name;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << text;
    return file;
}

void write(const std::filesystem::path& file, const std::string& text) {
    std::ofstream(file) << text;
}

std::string read_file(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

ParamBlock param_block(const ShaderPlugin& plugin,
                       std::initializer_list<std::pair<const char*, glm::vec4>> values) {
    ParamBlock block;
    const auto put = [&](const facet_param_desc& d, const float* v) {
        if (const int n = param_float_count(d.type)) {
            std::memcpy(block.bytes + d.offset, v, sizeof(float) * size_t(n));
        } else {
            const int32_t i = int32_t(std::lround(v[0]));
            std::memcpy(block.bytes + d.offset, &i, sizeof i);
        }
    };
    const facet_schema& desc = plugin.schema();
    for (uint32_t i = 0; i < desc.param_count; ++i) {
        const facet_param_desc& d = desc.params[i];
        const float zero[4] = {};
        put(d, d.type == FACET_PARAM_TEXTURE ? zero : d.default_value);
    }
    for (const auto& [name, value] : values) {
        const facet_param_desc* d = plugin.find_param(name);
        if (!d) throw std::invalid_argument(std::string("no parameter ") + name);
        put(*d, &value.x);
    }
    return block;
}

namespace {

bool compile_c(const std::filesystem::path& out, const std::string& name,
               const std::string& flags, const char* source) {
    const std::string cmd = std::string(FACET_TEST_C_COMPILER) + " -shared -fPIC -O1 -I" +
                            FACET_SOURCE_DIR + "/plugins/include -DPLUGIN_NAME='\"" + name +
                            "\"' " + flags + " " + FACET_SOURCE_DIR + "/tests/plugins/" +
                            source + " -o " + out.string();
    return std::system(cmd.c_str()) == 0;
}

}  // namespace

bool compile_plugin(const std::filesystem::path& out, const std::string& name,
                    const std::string& flags) {
    return compile_c(out, name, flags, "c_plugin.c");
}

bool compile_post_plugin(const std::filesystem::path& out, const std::string& name,
                         const std::string& flags) {
    return compile_c(out, name, flags, "c_post.c");
}

size_t resident_bytes(const char* key) {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind(key, 0) == 0)
            return size_t(std::stoull(line.substr(std::strlen(key) + 1))) * 1024;
    return 0;
}

LogCapture::LogCapture() : sink_(std::make_shared<spdlog::sinks::ostream_sink_mt>(out_)) {
    spdlog::default_logger()->sinks().push_back(sink_);
}

LogCapture::~LogCapture() {
    auto& sinks = spdlog::default_logger()->sinks();
    sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
}

std::string LogCapture::text() const {
    spdlog::default_logger()->flush();
    return out_.str();
}

}  // namespace facet::test
