#include "render.hpp"

#include "raycast.hpp"

#include <facet/math.hpp>
#include <facet/renderer.hpp>
#include <facet/texture.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <thread>

namespace facet::reference {

namespace {

constexpr int N = FACET_BLOCK_LANES;

// One drawable part of an object, ready to shade: its draw in three lightings (every
// light, none, and each light alone, all without shadow maps), its vertex
// outputs and its textures at level 0, filtered bilinearly.
struct Prepared {
    const ShaderPlugin* shader = nullptr;
    const Mesh* mesh = nullptr;
    std::vector<TextureBinding> textures;
    facet_draw all{}, none{};
    std::vector<facet_draw> alone;  // by light
    std::vector<float> varyings;    // [vertex][varying_floats]
    std::vector<glm::dvec2> window; // per vertex, for `linear` varyings
    bool has_linear = false;
    bool shadowed = false;          // the shader takes shadow maps, and shadows are on
    bool needs_ao = false;
    double ao_radius = 0.0;
};

// The oracle's own side of the plugin ABI (it uses no private part of the
// core): a plugin's log messages go to stderr, and the textures it samples
// itself ("facet.textures") are read by the scalar reference sampler
// (facet/texture.hpp) at the level each lane asks for; unbound slots read
// white.
void oracle_log(int, const char* shader, const char* message) {
    std::fprintf(stderr, "[%s] %s\n", shader ? shader : "?", message ? message : "");
}

const TextureBinding* oracle_bound(const facet_draw* draw, uint32_t slot) {
    const auto& textures = *static_cast<const std::vector<TextureBinding>*>(draw->host_data);
    return slot < textures.size() && textures[slot].texture ? &textures[slot] : nullptr;
}

void oracle_info(const facet_draw* draw, uint32_t slot, facet_texture_info* out) {
    *out = {};
    if (const TextureBinding* b = oracle_bound(draw, slot)) {
        out->kind = b->texture->faces == 6 ? FACET_TEXTURE_CUBE : FACET_TEXTURE_2D;
        out->width = uint32_t(b->texture->width), out->height = uint32_t(b->texture->height);
        out->levels = mipmapped(b->filter) ? uint32_t(b->texture->levels()) : 1u;
    }
}

// Where a texture parameter's `transform:` reads it: KHR_texture_transform's
// matrix, translation * rotation * scale, in double.
glm::dvec2 oracle_placed(const UvTransform& t, double u, double v) {
    const double c = std::cos(double(t.rotation)), s = std::sin(double(t.rotation));
    const glm::dmat3 translation(1, 0, 0, 0, 1, 0, t.offset.x, t.offset.y, 1);  // by columns
    const glm::dmat3 rotation(c, -s, 0, s, c, 0, 0, 0, 1);
    const glm::dmat3 scale(t.scale.x, 0, 0, 0, t.scale.y, 0, 0, 0, 1);
    return glm::dvec2(translation * rotation * scale * glm::dvec3(u, v, 1.0));
}

void oracle_sample(const facet_draw* draw, uint32_t slot, const float* coords, const float* lod,
                   uint32_t count, uint32_t mask, float* rgba) {
    const TextureBinding* b = oracle_bound(draw, slot);
    for (uint32_t i = 0; i < count; ++i) {
        glm::vec4 c(0.0f);
        if (mask >> i & 1u) {
            float l = lod ? lod[i] : 0.0f;
            glm::vec3 at(coords[i], coords[count + i],
                         b && b->texture->faces == 6 ? coords[2 * count + i] : 0.0f);
            if (b && b->texture->faces != 6) {  // the level scales with the transform's area
                at = glm::vec3(oracle_placed(b->transform, at.x, at.y), 0.0f);
                const double area = std::abs(double(b->transform.scale.x) * b->transform.scale.y);
                if (lod && area > 0.0) l += float(0.5 * std::log2(area));
            }
            c = !b                          ? glm::vec4(1.0f)
                : b->texture->faces == 6    ? sample_cube(*b, at, l)
                                            : sample_lod(*b, glm::vec2(at), l);
        }
        for (int k = 0; k < 4; ++k) rgba[uint32_t(k) * count + i] = c[k];
    }
}

// textureGrad: an anisotropic 2D binding over the footprint of the
// derivatives (turned and scaled as the UVs are); the rest as textureLod.
void oracle_sample_grad(const facet_draw* draw, uint32_t slot, const float* coords,
                        const float* lod, const float* grads, uint32_t count, uint32_t mask,
                        float* rgba) {
    const TextureBinding* b = oracle_bound(draw, slot);
    if (!grads || !b || b->filter != Filter::anisotropic || b->texture->faces == 6)
        return oracle_sample(draw, slot, coords, lod, count, mask, rgba);
    const UvTransform& t = b->transform;
    const auto turned = [&](glm::dvec2 d) {  // the linear part of oracle_placed
        return glm::vec2(oracle_placed(t, d.x, d.y) - oracle_placed(t, 0.0, 0.0));
    };
    for (uint32_t i = 0; i < count; ++i) {
        glm::vec4 c(0.0f);
        if (mask >> i & 1u) {
            const glm::vec2 at(oracle_placed(t, coords[i], coords[count + i]));
            const glm::vec2 dx = turned({grads[i], grads[count + i]});
            const glm::vec2 dy = turned({grads[2 * count + i], grads[3 * count + i]});
            c = sample_grad(*b, at, dx, dy);
        }
        for (int k = 0; k < 4; ++k) rgba[uint32_t(k) * count + i] = c[k];
    }
}

const void* oracle_extension(const char* id, uint32_t version) {
    static const facet_textures_service textures = {sizeof(facet_textures_service), &oracle_info,
                                                    &oracle_sample, &oracle_sample_grad};
    if (id && std::strcmp(id, FACET_TEXTURES_EXTENSION) == 0 && version >= 1 &&
        version <= FACET_TEXTURES_VERSION)
        return &textures;
    return nullptr;  // no "facet.pass": the oracle runs no screen passes
}

const facet_host kOracleHost = {FACET_ABI_MAJOR, FACET_ABI_MINOR, sizeof(facet_host),
                                &oracle_log, &oracle_extension};

void copy_matrix(float* out, const glm::mat4& m) { std::memcpy(out, glm::value_ptr(m), 64); }

// What the plugin sees of object `o` drawn with every light in `lights`.
facet_draw make_draw(const Scene& scene, const Object& o, const Material& m,
                     const std::vector<facet_light>& lights,
                     const std::vector<TextureBinding>& textures) {
    alignas(16) static const unsigned char kNoParams[FACET_MAX_PARAMS_SIZE] = {};
    const RenderSettings& s = scene.settings;
    const glm::mat4 model = o.transform.matrix(), view = scene.camera.view();
    const glm::mat4 projection =
        scene.camera.projection(float(s.width) / float(s.height), s.reversed_z);
    facet_draw d{};
    d.host = &kOracleHost;
    d.params = m.block ? m.block->bytes : kNoParams;
    d.host_data = &textures;
    copy_matrix(d.model, model);
    copy_matrix(d.view, view);
    copy_matrix(d.projection, projection);
    copy_matrix(d.view_projection, projection * view);
    copy_matrix(d.model_view_projection, projection * view * model);
    copy_matrix(d.normal_matrix, glm::mat4(normal_matrix(model)));
    for (int i = 0; i < 3; ++i) d.camera_position[i] = scene.camera.position[i];
    d.camera_position[3] = 1.0f;
    if (m.plugin->needs(FACET_NEED_LIGHTS)) {
        d.lights = lights.data();
        d.light_count = uint32_t(lights.size());
    }
    d.viewport_width = uint32_t(s.width);
    d.viewport_height = uint32_t(s.height);
    d.time = float(scene.time);
    return d;
}

void check_supported(const Object& o, const Material& m) {
    // A shader that can discard is fine while its material does not.
    const uint32_t unsupported = FACET_NEED_DERIVATIVES | FACET_NEED_BLENDING;
    if (m.blend != BlendMode::opaque || (m.plugin->needs() & unsupported) || m.discards ||
        m.alpha_to_coverage || m.stencil.enabled || !m.color_write)
        throw std::runtime_error("reference renderer: object '" + o.name + "' (material " +
                                 m.source + ", shader " + m.plugin->name() +
                                 ") blends, discards, takes derivatives, uses the stencil or "
                                 "writes no colour; only opaque, derivative-free materials that "
                                 "write colour have a reference");
}

std::unique_ptr<Prepared> prepare(const Scene& scene, const Object& o, const Material& m,
                                  const std::vector<facet_light>& lights) {
    check_supported(o, m);
    const RenderSettings& s = scene.settings;
    auto p = std::make_unique<Prepared>();
    p->shader = m.plugin.get();
    p->mesh = o.drawn_mesh().get();
    p->textures = m.textures;
    for (TextureBinding& t : p->textures) t.filter = Filter::bilinear;
    p->shadowed = s.shadows && m.uses_shadows;
    p->needs_ao = p->shader->needs(FACET_NEED_AO);
    p->ao_radius = s.ao_radius;

    p->all = make_draw(scene, o, m, lights, p->textures);
    p->none = p->all;
    p->none.light_count = 0;
    for (size_t k = 0; k < lights.size(); ++k) {
        facet_draw d = p->all;
        d.lights = &lights[k];
        d.light_count = 1;
        p->alone.push_back(d);
    }

    // The shader's vertex function, once over the whole mesh (the part's
    // triangles use some of it).
    const Mesh& mesh = *p->mesh;
    const uint32_t floats = p->shader->varying_floats();
    const size_t count = mesh.vertex_count();
    std::vector<glm::vec4> clip(count);
    p->varyings.resize(count * floats + 1);
    auto input = [&](facet_need need, const auto& data) -> const float* {
        return p->shader->needs(need) && !data.empty() ? glm::value_ptr(data[0]) : nullptr;
    };
    const facet_vertex_batch batch{uint32_t(count),
                                   glm::value_ptr(mesh.positions[0]),
                                   input(FACET_NEED_NORMALS, mesh.normals),
                                   input(FACET_NEED_UVS, mesh.uvs),
                                   input(FACET_NEED_COLORS, mesh.colors),
                                   input(FACET_NEED_TANGENTS, mesh.tangents),
                                   glm::value_ptr(clip[0]),
                                   p->varyings.data(),
                                   floats,
                                   input(FACET_NEED_UV1, mesh.uvs1)};
    if (count) p->shader->shader_desc().vertex(&p->all, &batch);

    for (uint32_t k = 0; k < floats; ++k)
        p->has_linear |= p->shader->float_interpolation()[k] == FACET_INTERP_LINEAR;
    if (p->has_linear) {
        const glm::dmat4 mvp = glm::dmat4(glm::make_mat4(p->all.projection)) *
                               glm::dmat4(glm::make_mat4(p->all.view)) *
                               glm::dmat4(glm::make_mat4(p->all.model));
        for (const glm::vec3& v : mesh.positions) {
            const glm::dvec4 c = mvp * glm::dvec4(glm::dvec3(v), 1.0);
            p->window.push_back({(c.x / c.w + 1.0) * 0.5 * s.width,
                                 (1.0 - c.y / c.w) * 0.5 * s.height});
        }
    }
    return p;
}

// What one sample sees.
struct Sample {
    std::optional<Hit> hit;
    glm::dvec2 window;
};

class Shader {
public:
    Shader(const Scene& scene, const std::vector<std::vector<std::unique_ptr<Prepared>>>& objects,
           const RayCaster& rc, const glm::dmat4& view_projection, const RenderOptions& options)
        : scene_(scene), objects_(objects), rc_(rc), view_projection_(view_projection),
          options_(options) {
        for (size_t k = 0; k < scene.lights.size(); ++k) {
            const Light& l = scene.lights[k];
            if (l.casts_shadow) casters_.push_back(k);
        }
    }

    // Shades lanes `mask` of one 4x4 block, all on part `part` of object
    // `object` and on the same side of their triangles; adds each lane's
    // colour to sum. ao_uv[i] is lane i's first point for AO directions.
    void shade(int object, int part, bool front, uint32_t mask, int bx, int by,
               const Sample* samples, const glm::dvec2* ao_uv, glm::dvec4* sum) {
        const Prepared& p = *objects_[size_t(object)][size_t(part)];
        const uint32_t floats = p.shader->varying_floats();
        const uint8_t* interp = p.shader->float_interpolation();
        const int first = std::countr_zero(mask);
        for (int i = 0; i < N; ++i) {
            const Sample& sm = samples[(mask >> i) & 1 ? i : first];
            const Hit& h = *sm.hit;
            const uint32_t* idx = &p.mesh->indices[3 * size_t(h.triangle)];
            double w[3] = {1.0 - h.u - h.v, h.u, h.v};
            double ws[3] = {w[0], w[1], w[2]};
            if (p.has_linear) screen_weights(p, idx, sm.window, ws);
            for (uint32_t k = 0; k < floats; ++k) {
                const float* v0 = &p.varyings[idx[0] * floats + k];
                double value;
                if (interp[k] == FACET_INTERP_FLAT) value = *v0;
                else {
                    const double* ww = interp[k] == FACET_INTERP_LINEAR ? ws : w;
                    value = 0.0;
                    for (int c = 0; c < 3; ++c) value += ww[c] * p.varyings[idx[c] * floats + k];
                }
                varyings_[k * N + i] = float(value);
            }
            const glm::dvec4 clip = view_projection_ * glm::dvec4(h.point, 1.0);
            depth_[i] = float(std::clamp(clip.z / clip.w, 0.0, 1.0));
            ao_[i] = 1.0f;
            if (p.needs_ao && scene_.settings.ao && ((mask >> i) & 1)) {
                int open = 0;
                for (int r = 0; r < options_.ao_rays; ++r) {
                    const glm::dvec2 uv = glm::fract(ao_uv[i] + double(r) * kR2);
                    open += rc_.open(h.point, h.normal, p.ao_radius, uv.x, uv.y);
                }
                ao_[i] = float(open) / float(options_.ao_rays);
            }
        }
        sample_textures(p);

        facet_fragment_batch b{};
        b.x = bx;
        b.y = by;
        b.front_facing = front;
        b.varyings = varyings_;
        b.depth = depth_;
        b.texels = p.shader->texture_count() ? texels_ : nullptr;
        b.ao = p.needs_ao ? ao_ : nullptr;
        float color[4 * N], alone[4 * N], dark[4 * N];
        run(p, p.all, b, mask, color);

        // Remove the share of each light a lane cannot see.
        bool have_dark = false;
        for (size_t k : p.shadowed ? casters_ : std::vector<size_t>{}) {
            uint32_t blocked = 0;
            for (uint32_t m = mask; m; m &= m - 1) {
                const int i = std::countr_zero(m);
                const Hit& h = *samples[i].hit;
                if (!rc_.lit(scene_.lights[k], h.point, h.normal)) blocked |= 1u << i;
            }
            if (!blocked) continue;
            if (!have_dark) run(p, p.none, b, mask, dark);
            have_dark = true;
            run(p, p.alone[k], b, mask, alone);
            for (uint32_t m = blocked; m; m &= m - 1) {
                const int i = std::countr_zero(m);
                for (int c = 0; c < 3; ++c) color[c * N + i] -= alone[c * N + i] - dark[c * N + i];
            }
        }
        for (uint32_t m = mask; m; m &= m - 1) {
            const int i = std::countr_zero(m);
            sum[i] += glm::dvec4(color[i], color[N + i], color[2 * N + i], color[3 * N + i]);
        }
    }

    // Steps of the R2 low-discrepancy sequence (Roberts 2018), which spreads
    // AO directions over a pixel's samples.
    static constexpr glm::dvec2 kR2{0.7548776662466927, 0.5698402909980532};

private:
    static void screen_weights(const Prepared& p, const uint32_t* idx, glm::dvec2 q,
                               double* w) {
        const glm::dvec2 a = p.window[idx[0]], b = p.window[idx[1]], c = p.window[idx[2]];
        auto cross = [](glm::dvec2 e, glm::dvec2 f) { return e.x * f.y - e.y * f.x; };
        const double area = cross(b - a, c - a);
        if (area == 0.0) return;
        w[1] = cross(q - a, c - a) / area;
        w[2] = cross(b - a, q - a) / area;
        w[0] = 1.0 - w[1] - w[2];
    }

    void sample_textures(const Prepared& p) {
        for (int s = 0; s < p.shader->texture_count(); ++s) {
            float* out = texels_ + s * 4 * N;
            const TextureBinding* t = s < int(p.textures.size()) ? &p.textures[size_t(s)] : nullptr;
            if (!t || !t->texture) {
                std::fill(out, out + 4 * N, 1.0f);
                continue;
            }
            const float* u = varyings_ + p.shader->texture_uv_float(s, t->uv_set) * N;
            float placed[2 * N];
            for (int i = 0; i < N; ++i) {
                const glm::dvec2 uv = oracle_placed(t->transform, u[i], u[N + i]);
                placed[i] = float(uv.x), placed[N + i] = float(uv.y);
            }
            sample_many(*t, placed, placed + N, N, out);
        }
    }

    static void run(const Prepared& p, const facet_draw& draw, facet_fragment_batch b,
                    uint32_t mask, float* color) {
        b.mask = mask;
        b.color = color;
        p.shader->fragment_for(Isa::portable)(&draw, &b);
    }

    const Scene& scene_;
    const std::vector<std::vector<std::unique_ptr<Prepared>>>& objects_;  // [object][part]
    const RayCaster& rc_;
    const glm::dmat4 view_projection_;
    const RenderOptions& options_;
    std::vector<size_t> casters_;
    float varyings_[FACET_MAX_VARYING_FLOATS * N] = {};
    float depth_[N] = {}, ao_[N] = {};
    float texels_[FACET_MAX_TEXTURES * 4 * N] = {};
};

}  // namespace

std::vector<glm::dvec4> render(const Scene& scene, const RenderOptions& options) {
    const RenderSettings& s = scene.settings;
    const int grid = std::max(1, options.grid);
    std::vector<facet_light> lights;
    for (const Light& l : scene.lights) lights.push_back(to_abi(l));
    std::vector<std::vector<std::unique_ptr<Prepared>>> objects(scene.objects.size());
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& o = scene.objects[i];
        if (!o.visible || !o.mesh) continue;  // what the ray caster leaves out too
        for (size_t k = 0; k < o.drawn_mesh()->part_count(); ++k) {
            const Material* m = o.material_of(k);
            if (!m || !m->plugin)
                throw std::runtime_error("reference renderer: object '" + o.name +
                                         "' has a part with no bound material");
            objects[i].push_back(prepare(scene, o, *m, lights));
        }
    }
    const RayCaster rc(scene);
    const CameraRays camera(scene);
    const glm::dmat4 view_projection =
        glm::dmat4(scene.camera.projection(float(s.width) / float(s.height), s.reversed_z)) *
        glm::dmat4(scene.camera.view());

    std::vector<glm::dvec4> image(size_t(s.width) * s.height);
    const int blocks_x = (s.width + 3) / 4, blocks_y = (s.height + 3) / 4;
    std::atomic<int> next{0};
    auto worker = [&] {
        Shader shader(scene, objects, rc, view_projection, options);
        Sample samples[N];
        glm::dvec2 ao_uv[N];
        glm::dvec4 sum[N];
        for (int row; (row = next++) < blocks_y;) {
            for (int bx = 0; bx < blocks_x; ++bx) {
                const int x0 = bx * 4, y0 = row * 4;
                std::fill(sum, sum + N, glm::dvec4(0.0));
                glm::dvec2 ao_start[N];
                for (int i = 0; i < N; ++i) {  // a fixed, decorrelated start per pixel
                    std::minstd_rand rng(uint32_t((y0 + i / 4) * s.width + x0 + i % 4 + 1));
                    std::uniform_real_distribution<double> unit(0.0, 1.0);
                    ao_start[i] = {unit(rng), unit(rng)};
                }
                for (int sy = 0; sy < grid; ++sy)
                    for (int sx = 0; sx < grid; ++sx) {
                        const double ox = (sx + 0.5) / grid, oy = (sy + 0.5) / grid;
                        const double k = double((sy * grid + sx) * options.ao_rays);
                        for (int i = 0; i < N; ++i) {
                            const int x = x0 + i % 4, y = y0 + i / 4;
                            samples[i].hit.reset();
                            if (x >= s.width || y >= s.height) continue;
                            samples[i].window = {x + ox, y + oy};
                            glm::dvec3 o, d;
                            camera.ray(x + ox, y + oy, o, d);
                            samples[i].hit = rc.first_hit(o, d, 1.0, true);
                            ao_uv[i] = glm::fract(ao_start[i] + k * Shader::kR2);
                            if (!samples[i].hit) sum[i] += glm::dvec4(s.clear_color);
                        }
                        // Shade the lanes object by object, side by side.
                        uint32_t left = 0;
                        for (int i = 0; i < N; ++i) left |= uint32_t(bool(samples[i].hit)) << i;
                        while (left) {
                            const Hit& h = *samples[std::countr_zero(left)].hit;
                            const bool front = h.ccw == s.front_ccw;
                            uint32_t group = 0;
                            for (uint32_t m = left; m; m &= m - 1) {
                                const int i = std::countr_zero(m);
                                const Hit& g = *samples[i].hit;
                                if (g.object == h.object && g.part == h.part &&
                                    (g.ccw == s.front_ccw) == front)
                                    group |= 1u << i;
                            }
                            shader.shade(h.object, h.part, front, group, x0, y0, samples, ao_uv,
                                         sum);
                            left &= ~group;
                        }
                    }
                for (int i = 0; i < N; ++i) {
                    const int x = x0 + i % 4, y = y0 + i / 4;
                    if (x < s.width && y < s.height)
                        image[size_t(y) * s.width + x] = sum[i] / double(grid * grid);
                }
            }
        }
    };
    int threads = options.threads > 0 ? options.threads
                                      : int(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    return image;
}

}  // namespace facet::reference
