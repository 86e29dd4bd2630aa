// Shared helpers for the tests: in-process test shaders, meshes made in
// code, and a one-call way to draw them.
#pragma once

#include <facet/memory.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/shader.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace spdlog::sinks {
class sink;
}

namespace facet::test {

// Outputs (1,1,1,1); drawn with additive blending, a pixel's red channel
// counts how many times it was covered.
struct CountShader {
    FACET_VARYINGS()
    FACET_PARAMS()
    static constexpr const char* name = "test_count";
    static constexpr const char* version = "test";
    static constexpr uint32_t needs = 0;
    static Varyings vertex(const sdk::VertexIn& in, const sdk::Draw& d, const Params&,
                           sdk::Vec4& clip) {
        clip = d.model_view_projection() * sdk::Vec4(in.position, 1.0f);
        return {};
    }
    static sdk::Vec4 fragment(const Varyings&, sdk::Fragment&, const sdk::Draw&, const Params&) {
        return sdk::Vec4(sdk::splat(1.0f));
    }
};

// Outputs the vertex colour, interpolated with interpolation mode I.
template <facet_interpolation I>
struct ColorShader {
    FACET_PARAMS()
    // By hand, for the template's interpolation: the table ends with kNoVarying.
    struct Varyings {
        sdk::Vec4 color;
    };
    static constexpr facet_varying_desc varyings[] = {sdk::varying("color", 4, I),
                                                      sdk::detail::kNoVarying};
    static constexpr const char* name = "test_color";
    static constexpr const char* version = "test";
    static constexpr uint32_t needs = FACET_NEED_COLORS;
    static Varyings vertex(const sdk::VertexIn& in, const sdk::Draw& d, const Params&,
                           sdk::Vec4& clip) {
        clip = d.model_view_projection() * sdk::Vec4(in.position, 1.0f);
        return {in.color};
    }
    static sdk::Vec4 fragment(const Varyings& v, sdk::Fragment&, const sdk::Draw&,
                              const Params&) {
        return v.color;
    }
};

template <class S>
std::shared_ptr<ShaderPlugin> plugin() {
    return ShaderPlugin::from_descriptor(sdk::describe<S>(), "test");
}

// A mesh from positions, triangles and optional colours (bounds computed).
Mesh make_mesh(std::vector<glm::vec3> positions, std::vector<uint32_t> indices,
               std::vector<glm::vec4> colors = {});

// A fan of n triangles around `centre` in NDC (z = 0.5), rotated by `angle`.
Mesh fan(int n, float radius, float angle, glm::vec2 centre);

// A DrawCall with identity matrices: positions are clip coordinates.
DrawCall clip_space_call(const Mesh& mesh, const ShaderPlugin& shader);

// Clip coordinates (w = 1) of a window position in a width x height target.
glm::vec3 window_to_ndc(glm::dvec2 window, int width, int height);

// How far p lies inside the rectangle of width w around segment a-b (no
// caps), the shape of a line (Topology::lines): positive inside, negative
// outside, in pixels.
double inside_line(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, double w);

// For a target drawn in white, added (so red counts how often a sample is
// covered), by shapes whose signed distances inside (pixels, positive
// inside) at a point `inside` gives: every sample more than 0.02 pixel
// (the snapping of corners to 1/256) inside some shape is covered, none
// more than that outside all of them is, and none more often than the
// shapes that hold it. Adds the covered samples to `covered`.
void check_coverage(const Framebuffer& fb,
                    const std::function<std::vector<double>(glm::dvec2)>& inside, int& covered);

// The same size, format and stored bits, colour and depth (padding too).
bool same_image(const Framebuffer& a, const Framebuffer& b);

// The demo scenes in configs/, each as small_demo_scene() loads it.
extern const char* const kDemoScenes[14];
// configs/<name>, at 197 x 111 (several tiles, and no multiple of the tile
// or block size), with shadow maps 256 texels a side (unless a light asks
// for its own size).
Scene small_demo_scene(PluginRegistry& registry, const std::string& name);

// Another plugin for each material of a scene that `replace` gives one
// for (it returns null to leave a material alone), each material once
// however many objects share it. swap() puts them in; swap() again puts
// the originals back.
class PluginSwap {
public:
    PluginSwap(const Scene& scene,
               const std::function<std::shared_ptr<ShaderPlugin>(const Material&)>& replace);
    void swap();
    bool empty() const { return swaps_.empty(); }

private:
    std::vector<std::pair<Material*, std::shared_ptr<ShaderPlugin>>> swaps_;
};

// A fresh, empty folder under the system temp folder, named after `tag`,
// removed with everything in it when the TempDir goes, even when a test
// fails. The one temporary-folder fixture of the tests.
class TempDir {
public:
    explicit TempDir(const std::string& tag);
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    // Writes `text` (bytes, as they are) to `name` inside the folder, making
    // the folders on the way; returns its path.
    std::filesystem::path write(const std::string& name, const std::string& text) const;

    const std::filesystem::path path;
};

// Sets the memory budget (facet/memory.hpp) for one test; the one before
// comes back after it.
struct Budget {
    const uint64_t before = memory_budget();
    explicit Budget(uint64_t bytes) { set_memory_budget(bytes); }
    ~Budget() { set_memory_budget(before); }
};

// A folder for a test's scene file and the files it names, with a
// registry to load it through.
struct SceneDir {
    explicit SceneDir(const std::string& tag = "scene") : folder(tag) {}
    TempDir folder;
    const std::filesystem::path& dir = folder.path;
    PluginRegistry registry;
    // Writes `yaml` as dir / "scene.yaml" and loads it.
    Scene load(const std::string& yaml);
    // The error load() throws; throws std::runtime_error (failing the test)
    // if the scene loads.
    std::string error(const std::string& yaml);
};

// Resident memory of this process, in bytes: "VmRSS:" now, or "VmHWM:" (the
// peak). 0 where /proc does not say.
size_t resident_bytes(const char* key);

// A square of side 18 at z = 0, facing +Z, as OBJ text: it fills the view
// of a camera at the default position.
inline constexpr const char* kQuadObj =
    "v -9 -9 0\nv 9 -9 0\nv 9 9 0\nv -9 9 0\nf 1 2 3\nf 1 3 4\n";

// Everything logged through spdlog's default logger while it lives, as
// text (warnings the tests expect).
class LogCapture {
public:
    LogCapture();
    ~LogCapture();
    LogCapture(const LogCapture&) = delete;
    LogCapture& operator=(const LogCapture&) = delete;
    std::string text() const;

private:
    std::ostringstream out_;
    std::shared_ptr<spdlog::sinks::sink> sink_;
};

// The parameter block `plugin`'s schema lays out: every parameter at its
// default, then `values` by name (up to four floats; an int, bool, texture
// or choice as the whole number of its first). Whatever the plugin adds to
// its schema later gets its default, never bytes past a short struct.
ParamBlock param_block(const ShaderPlugin& plugin,
                       std::initializer_list<std::pair<const char*, glm::vec4>> values);

// Writes `text` to `file`.
void write(const std::filesystem::path& file, const std::string& text);
// A file's bytes, as they are (empty if it cannot be read).
std::string read_file(const std::filesystem::path& file);

// Compiles the test plugin (tests/plugins/c_plugin.c) as shader `name` into
// `out`, with extra compiler `flags` (-DFILL_RED=..., -DWITH_GAIN, ...).
bool compile_plugin(const std::filesystem::path& out, const std::string& name,
                    const std::string& flags);
// The same with the test screen pass (tests/plugins/c_post.c: -DSCALE=...).
bool compile_post_plugin(const std::filesystem::path& out, const std::string& name,
                         const std::string& flags);

}  // namespace facet::test
