// facet's C API (facet/facet.h) over the C++ core: handles that own a
// scene (with its plugin registry and texture cache) or a renderer (with
// its target), and every call's exceptions turned into the calling
// thread's last error.
#include "facet/facet.h"

#include "facet/error.hpp"
#include "facet/framebuffer.hpp"
#include "facet/material.hpp"
#include "facet/paths.hpp"
#include "facet/plugin.hpp"
#include "facet/png.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"
#include "facet/texture.hpp"

#include <glm/glm.hpp>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <vector>

struct facet_scene {
    // The registry outlives the scene's materials, which hold its plugins.
    facet::PluginRegistry registry;
    facet::TextureCache textures;  // a changed parameter's material is bound again through it
    facet::Scene scene;
};

struct facet_renderer {
    explicit facet_renderer(int threads) : renderer(threads) {}
    facet::Renderer renderer;
    facet::Framebuffer target;
    std::vector<uint8_t> rgba;
};

namespace {

struct LastError {
    std::string message, file;
    int line = 0;
};
thread_local LastError last_error;
thread_local std::string default_scene;

// Never throws: out of memory for the message, a fixed one.
void fail(const char* message, const std::string& file = {}, int line = 0) noexcept {
    try {
        last_error.message = message;
        last_error.file = file;
        last_error.line = line;
    } catch (...) {
        last_error.message.clear();  // keeps its capacity: no allocation
        last_error.file.clear();
        last_error.line = 0;
    }
}

// Runs `f` with the last error cleared; what it throws becomes the last
// error, and the call returns `failed`.
template <class F, class R = decltype(std::declval<F>()())>
R guarded(R failed, F&& f) noexcept {
    last_error.message.clear();
    last_error.file.clear();
    last_error.line = 0;
    try {
        return f();
    } catch (const facet::Error& e) {
        fail(e.what(), e.file(), e.line());
    } catch (const std::bad_alloc&) {
        fail("out of memory");
    } catch (const std::exception& e) {
        fail(e.what());
    } catch (...) {
        fail("an unknown error");
    }
    return failed;
}

// *p; or, when p is null, Error(config_invalid) naming `what`.
template <class T>
T& need(T* p, const char* what) {
    if (!p) throw facet::Error(facet::ErrorCode::config_invalid, std::string(what) + " is NULL");
    return *p;
}

const char* need(const char* text, const char* what) {
    if (!text) throw facet::Error(facet::ErrorCode::config_invalid, std::string(what) + " is NULL");
    return text;
}

// Rows of `row` bytes, `stride` apart: Error unless stride >= row.
void check_stride(size_t stride, size_t row) {
    if (stride < row)
        throw facet::Error(facet::ErrorCode::out_of_range,
                           "a stride of " + std::to_string(stride) + " bytes for rows of " +
                               std::to_string(row));
}

// `v`, n finite numbers; else Error naming `what`.
const float* finite(const float* v, int n, const char* what) {
    need(v, what);
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(v[i]))
            throw facet::Error(facet::ErrorCode::out_of_range,
                               std::string(what) + " is not a finite number");
    return v;
}

// The value a material file would give `desc` for `count` numbers, or an
// error naming the parameter when it is of another type or size.
facet::MaterialParam param_value(const facet_param_desc& desc, const char* name,
                                 const facet::ShaderPlugin& plugin, const float* values,
                                 int count) {
    static const int kComponents[] = {1, 1, 1, 2, 3, 4, 3, 4, 0, 1};
    const int want = desc.type < 10 ? kComponents[desc.type] : 0;
    if (want == 0)
        throw facet::Error(facet::ErrorCode::config_invalid,
                           std::string("parameter '") + name + "' of shader '" + plugin.name() +
                               "' is a texture: a material or scene file binds it");
    if (count != want)
        throw facet::Error(facet::ErrorCode::config_invalid,
                           std::string("parameter '") + name + "' of shader '" + plugin.name() +
                               "' takes " + std::to_string(want) + " number(s), not " +
                               std::to_string(count));
    facet::MaterialParam p;
    p.name = name;
    p.numbers.assign(values, values + count);
    p.kind = count == 1 ? facet::MaterialParam::Kind::number : facet::MaterialParam::Kind::vector;
    p.is_integer = count == 1 && values[0] == std::floor(values[0]);
    if (desc.type == FACET_PARAM_BOOL) {
        p.kind = facet::MaterialParam::Kind::boolean;
        p.flag = values[0] != 0.0f;
    }
    return p;
}

// A private copy of `m` with parameter `name` set, bound through `cache`
// (which checks the name, the type and the range as a file's would).
std::shared_ptr<facet::Material> with_param(const facet::Material& m, const char* name,
                                            const float* values, int count,
                                            facet::TextureCache& cache) {
    auto copy = std::make_shared<facet::Material>(m);
    const facet_param_desc* desc = m.plugin ? m.plugin->find_param(name) : nullptr;
    facet::MaterialParam value;
    if (desc) {
        value = param_value(*desc, name, *m.plugin, values, count);
    } else {  // unknown: bind() names the parameters the shader has
        value.name = name;
        value.numbers.assign(values, values + count);
    }
    std::erase_if(copy->params, [&](const facet::MaterialParam& p) { return p.name == name; });
    copy->params.push_back(value);
    facet::bind(*copy, copy->plugin, cache);
    return copy;
}

void set_param(facet_scene& s, const std::string& object, const char* param, const float* values,
               int count) {
    bool found = false;
    for (facet::Object& o : s.scene.objects) {
        if (o.name != object) continue;
        found = true;
        if (o.materials().empty())
            throw facet::Error(facet::ErrorCode::config_invalid,
                               "object '" + object + "' is drawn with no material to set",
                               s.scene.source.string());
        std::map<const facet::Material*, std::shared_ptr<facet::Material>> changed;
        const auto change = [&](std::shared_ptr<facet::Material>& slot) {
            if (!slot) return;
            auto& copy = changed[slot.get()];
            if (!copy) copy = with_param(*slot, param, values, count, s.textures);
            slot = copy;
        };
        // Every slot bound before any is replaced: an error changes nothing.
        facet::Object edited = o;
        change(edited.material);
        for (facet::PartMaterial& p : edited.part_materials) change(p.material);
        o = std::move(edited);
    }
    if (!found)
        throw facet::Error(facet::ErrorCode::config_invalid,
                           "the scene has no object named '" + object + "'",
                           s.scene.source.string());
}

// `renderer` with `scene` drawn into its target, in `format` (none: the
// scene's own), after checking the caller's buffer: rows of
// `bytes_per_pixel` a pixel, `stride` apart.
facet_renderer& rendered(facet_renderer* renderer, facet_scene* scene, const void* pixels,
                         size_t stride, size_t bytes_per_pixel, facet::ColorFormat format) {
    facet_renderer& r = need(renderer, "the renderer");
    facet::Scene& s = need(scene, "the scene").scene;
    if (!pixels) throw facet::Error(facet::ErrorCode::config_invalid, "the pixels are NULL");
    check_stride(stride, size_t(s.settings.width) * bytes_per_pixel);
    // Floats are the frame before any post-processing pass, in linear light.
    const facet::ColorFormat own = s.settings.color_format;
    const bool post = s.settings.post;
    if (format != facet::ColorFormat::none) {
        s.settings.color_format = format;
        s.settings.post = false;
    }
    const auto restore = [&] {
        s.settings.color_format = own;
        s.settings.post = post;
    };
    try {
        r.renderer.render(s, r.target);
    } catch (...) {
        restore();
        throw;
    }
    restore();
    return r;
}

}  // namespace

extern "C" {

unsigned facet_api_version(void) { return FACET_API_MAJOR << 16 | FACET_API_MINOR; }

const char* facet_error_message(void) { return last_error.message.c_str(); }
const char* facet_error_file(void) { return last_error.file.c_str(); }
int facet_error_line(void) { return last_error.line; }

facet_status facet_set_install_root(const char* prefix) {
    return guarded(FACET_FAILED, [&] {
        facet::set_install_root(need(prefix, "the prefix"));
        return FACET_OK;
    });
}

const char* facet_default_scene(void) {
    return guarded(static_cast<const char*>(nullptr), [] {
        default_scene = facet::default_scene_path().string();
        return default_scene.c_str();
    });
}

facet_status facet_set_log_level(const char* level) {
    return guarded(FACET_FAILED, [&] {
        const std::string name = need(level, "the level");
        const spdlog::level::level_enum l = spdlog::level::from_str(name);
        if (l == spdlog::level::off && name != "off")
            throw facet::Error(facet::ErrorCode::config_invalid,
                               "a log level of '" + name +
                                   "' (trace, debug, info, warn, error or off)");
        spdlog::set_level(l);
        return FACET_OK;
    });
}

facet_scene* facet_scene_load(const char* path) {
    return guarded(static_cast<facet_scene*>(nullptr), [&] {
        auto s = std::make_unique<facet_scene>();
        s->scene = facet::load_scene(need(path, "the path"), s->registry);
        return s.release();
    });
}

facet_scene* facet_scene_load_yaml(const char* yaml, const char* origin) {
    return guarded(static_cast<facet_scene*>(nullptr), [&] {
        auto s = std::make_unique<facet_scene>();
        s->scene = facet::load_scene_text(need(yaml, "the YAML"), origin ? origin : "scene.yaml",
                                          s->registry);
        return s.release();
    });
}

void facet_scene_free(facet_scene* scene) { delete scene; }

facet_status facet_scene_size(const facet_scene* scene, int* width, int* height) {
    return guarded(FACET_FAILED, [&] {
        const facet::RenderSettings& r = need(scene, "the scene").scene.settings;
        need(width, "width") = r.width;
        need(height, "height") = r.height;
        return FACET_OK;
    });
}

facet_status facet_scene_set_size(facet_scene* scene, int width, int height) {
    return guarded(FACET_FAILED, [&] {
        facet_scene& s = need(scene, "the scene");
        if (width < 1 || height < 1 || width > facet::Framebuffer::kMaxSize ||
            height > facet::Framebuffer::kMaxSize)
            throw facet::Error(facet::ErrorCode::out_of_range,
                               "a size of " + std::to_string(width) + "x" +
                                   std::to_string(height) + " (each side 1.." +
                                   std::to_string(facet::Framebuffer::kMaxSize) + ")");
        s.scene.settings.width = width;
        s.scene.settings.height = height;
        return FACET_OK;
    });
}

facet_status facet_scene_set_camera(facet_scene* scene, const float position[3],
                                    const float target[3], float fov_y) {
    return guarded(FACET_FAILED, [&] {
        facet_scene& s = need(scene, "the scene");
        finite(position, 3, "the position");
        finite(target, 3, "the target");
        if (!(fov_y > 0.0f && fov_y < 180.0f))
            throw facet::Error(facet::ErrorCode::out_of_range,
                               "a field of view of " + std::to_string(fov_y) +
                                   " degrees (it is between 0 and 180)");
        facet::Camera c = s.scene.camera;
        c.position = glm::vec3(position[0], position[1], position[2]);
        c.target = glm::vec3(target[0], target[1], target[2]);
        if (c.position == c.target)
            throw facet::Error(facet::ErrorCode::out_of_range,
                               "the camera's position is its target: it looks nowhere");
        c.fov_y = fov_y;
        s.scene.set_camera(c);
        return FACET_OK;
    });
}

facet_status facet_scene_set_param(facet_scene* scene, const char* object, const char* param,
                                   const float* values, int count) {
    return guarded(FACET_FAILED, [&] {
        facet_scene& s = need(scene, "the scene");
        if (count < 1 || count > 4)
            throw facet::Error(facet::ErrorCode::config_invalid,
                               "a parameter takes 1 to 4 numbers, not " + std::to_string(count));
        finite(values, count, "a value");
        set_param(s, need(object, "the object's name"), need(param, "the parameter's name"),
                  values, count);
        return FACET_OK;
    });
}

int facet_scene_light_count(const facet_scene* scene) {
    return guarded(-1, [&] { return int(need(scene, "the scene").scene.lights.size()); });
}

int facet_scene_light_index(const facet_scene* scene, const char* name) {
    return guarded(-1, [&] {
        const facet::Scene& s = need(scene, "the scene").scene;
        const std::string wanted = need(name, "the light's name");
        for (size_t i = 0; i < s.lights.size(); ++i)
            if (s.lights[i].name == wanted) return int(i);
        throw facet::Error(facet::ErrorCode::config_invalid,
                           "the scene has no light named '" + wanted + "'", s.source.string());
    });
}

facet_status facet_scene_set_light(facet_scene* scene, int index, const float color[3],
                                   float intensity) {
    return guarded(FACET_FAILED, [&] {
        facet_scene& s = need(scene, "the scene");
        if (index < 0 || size_t(index) >= s.scene.lights.size())
            throw facet::Error(facet::ErrorCode::out_of_range,
                               "light " + std::to_string(index) + ": the scene has " +
                                   std::to_string(s.scene.lights.size()),
                               s.scene.source.string());
        finite(color, 3, "the colour");
        finite(&intensity, 1, "the intensity");
        if (intensity < 0.0f || color[0] < 0.0f || color[1] < 0.0f || color[2] < 0.0f)
            throw facet::Error(facet::ErrorCode::out_of_range,
                               "a light's colour and intensity are at least 0");
        facet::Light& l = s.scene.lights[size_t(index)];
        l.color = glm::vec3(color[0], color[1], color[2]);
        l.intensity = intensity;
        return FACET_OK;
    });
}

facet_status facet_scene_set_time(facet_scene* scene, double seconds) {
    return guarded(FACET_FAILED, [&] {
        need(scene, "the scene").scene.pose(seconds);
        return FACET_OK;
    });
}

facet_renderer* facet_renderer_new(int threads) {
    return guarded(static_cast<facet_renderer*>(nullptr), [&] {
        if (threads < 0 || threads > 256)
            throw facet::Error(facet::ErrorCode::out_of_range,
                               std::to_string(threads) +
                                   " threads (0..256; 0: one a hardware thread)");
        return new facet_renderer(threads);
    });
}

void facet_renderer_free(facet_renderer* renderer) { delete renderer; }

facet_status facet_render_rgba8(facet_renderer* renderer, facet_scene* scene,
                                unsigned char* pixels, size_t stride) {
    return guarded(FACET_FAILED, [&] {
        facet_renderer& r = rendered(renderer, scene, pixels, stride, 4, facet::ColorFormat::none);
        const int w = r.target.width(), h = r.target.height();
        r.renderer.pipeline().resolve_srgb8(r.target, r.rgba);
        for (int y = 0; y < h; ++y)
            std::memcpy(pixels + size_t(y) * stride, r.rgba.data() + size_t(y) * size_t(w) * 4,
                        size_t(w) * 4);
        return FACET_OK;
    });
}

facet_status facet_render_rgba32f(facet_renderer* renderer, facet_scene* scene, float* pixels,
                                  size_t stride) {
    return guarded(FACET_FAILED, [&] {
        facet_renderer& r =
            rendered(renderer, scene, pixels, stride, 16, facet::ColorFormat::rgba32f);
        char* rows = reinterpret_cast<char*>(pixels);
        for (int y = 0; y < r.target.height(); ++y)
            for (int x = 0; x < r.target.width(); ++x) {
                const glm::vec4 c = r.target.pixel(x, y);
                std::memcpy(rows + size_t(y) * stride + size_t(x) * sizeof c, &c, sizeof c);
            }
        return FACET_OK;
    });
}

facet_status facet_write_png(const char* path, int width, int height, const unsigned char* pixels,
                             size_t stride) {
    return guarded(FACET_FAILED, [&] {
        need(path, "the path");
        need(pixels, "the pixels");
        if (width < 1 || height < 1 || stride < size_t(width) * 4)
            throw facet::Error(facet::ErrorCode::out_of_range,
                               "an image of " + std::to_string(width) + "x" +
                                   std::to_string(height) + " with rows " +
                                   std::to_string(stride) + " bytes apart",
                               path);
        facet::write_png_rows(path, pixels, stride, width, height);
        return FACET_OK;
    });
}

}  // extern "C"
