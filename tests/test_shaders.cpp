// The unlit, lit, phong, toon and pbr plugins, loaded as the real built .so files,
// against a double-precision reference of the formulas their sources document.
//
// Most tests draw one quad in perspective, through the camera matrices a
// scene uses, with a non-uniform model transform and a different normal at
// each corner, lit by a directional, a point (with a range that cuts it
// off) and a spot light. For each pixel centre well inside the quad the
// reference casts the exact ray, intersects the quad's plane, and takes the
// hit's barycentric coordinates in its triangle as the interpolation
// weights (perspective-correct interpolation is affine interpolation over
// the triangle itself). It evaluates the formula in double, resolves it
// with linear_to_srgb8, and facet's resolved pixel must be within 1 code.
//
// Where a formula has a discontinuity (a light's range, toon's bands and
// thresholds), a pixel within a small margin of it is not compared: float
// rounding and the 1/256-pixel vertex snap may put it on either side, and
// the output jumps by a whole step there. Each test also checks that enough
// pixels were compared and that they were not all black or saturated.
#include "meshes.hpp"
#include "support.hpp"

#include <facet/isa.hpp>
#include <facet/math.hpp>
#include <facet/plugin.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>

using namespace facet;
using namespace facet::test;
using glm::dvec2;
using glm::dvec3;
using glm::dvec4;

namespace {

// ---- parameter blocks, laid out by the plugin's own schema -------------------

using Values = std::map<std::string, std::vector<double>>;

void write_param(ParamBlock& block, const facet_param_desc& p, const std::vector<double>& v) {
    const int floats = param_float_count(p.type);
    if (floats == 0) {  // INT, BOOL, TEXTURE: one int32
        REQUIRE(v.size() == 1);
        const int32_t i = int32_t(v[0]);
        std::memcpy(block.bytes + p.offset, &i, sizeof i);
        return;
    }
    REQUIRE(v.size() == size_t(floats));
    for (int k = 0; k < floats; ++k) {
        const float f = float(v[k]);
        std::memcpy(block.bytes + p.offset + 4 * k, &f, sizeof f);
    }
}

// Every parameter of the schema must be given, and nothing else: a test then
// states all it depends on, and notices when a schema changes.
ParamBlock make_block(const ShaderPlugin& shader, const Values& values) {
    ParamBlock block;
    for (const auto& [name, v] : values) {
        INFO("parameter " << name);
        REQUIRE(shader.find_param(name));
    }
    const facet_schema& d = shader.schema();
    REQUIRE(values.size() == d.param_count);
    for (uint32_t i = 0; i < d.param_count; ++i)
        write_param(block, d.params[i], values.at(d.params[i].name));
    return block;
}

dvec3 rgb(const Values& v, const std::string& name) {
    const std::vector<double>& x = v.at(name);
    return {x.at(0), x.at(1), x.at(2)};
}
dvec4 rgba(const Values& v, const std::string& name) {
    const std::vector<double>& x = v.at(name);
    return {x.at(0), x.at(1), x.at(2), x.at(3)};
}
double num(const Values& v, const std::string& name) { return v.at(name).at(0); }

// ---- lights and their double-precision reference ------------------------------

facet_light directional(glm::vec3 direction, glm::vec3 color, float intensity) {
    Light l;
    l.type = LightType::directional;
    l.direction = glm::normalize(direction);
    l.color = color;
    l.intensity = intensity;
    return to_abi(l);
}

facet_light point(glm::vec3 position, glm::vec3 color, float intensity, glm::vec3 attenuation,
                  float range) {
    Light l;
    l.type = LightType::point;
    l.position = position;
    l.color = color;
    l.intensity = intensity;
    l.attenuation = attenuation;
    l.range = range;
    return to_abi(l);
}

facet_light spot(glm::vec3 position, glm::vec3 target, glm::vec3 color, float intensity,
                 glm::vec3 attenuation, float inner_deg, float outer_deg) {
    Light l;
    l.type = LightType::spot;
    l.position = position;
    l.direction = glm::normalize(target - position);
    l.color = color;
    l.intensity = intensity;
    l.attenuation = attenuation;
    l.spot_inner = inner_deg;
    l.spot_outer = outer_deg;
    return to_abi(l);
}

struct RefLight {
    dvec3 to_light{0.0};
    dvec3 radiance{0.0};
    bool near_range = false;  // within the margin of the range cut-off
};

dvec3 vec(const float* f) { return {f[0], f[1], f[2]}; }

double smoothstep(double e0, double e1, double x) {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

RefLight ref_light(const facet_light& l, const dvec3& p) {
    const dvec3 color = vec(l.color) * double(l.intensity);
    if (l.type == FACET_LIGHT_DIRECTIONAL) return {-vec(l.direction), color};
    const double d = glm::length(vec(l.position) - p);
    RefLight out;
    out.near_range = l.range > 0 && std::abs(d - l.range) < 1e-3;
    if (l.range > 0 && d > l.range) return out;
    out.to_light = (vec(l.position) - p) / d;
    double k = 1.0 / (l.attenuation[0] + l.attenuation[1] * d + l.attenuation[2] * d * d);
    if (l.type == FACET_LIGHT_SPOT)
        k *= smoothstep(l.spot_cos_outer, l.spot_cos_inner,
                        glm::dot(-out.to_light, vec(l.direction)));
    out.radiance = color * k;
    return out;
}

// ---- a draw and the rays through its pixel centres -----------------------------

struct Setup {
    int width = 96, height = 64;
    glm::vec3 eye{0.0f};
    glm::mat4 model{1.0f}, view{1.0f}, projection{1.0f};
    Mesh mesh;
    std::vector<facet_light> lights;
};

Framebuffer draw(const Setup& s, const ShaderPlugin& shader, const ParamBlock& block,
                 const TextureBinding* textures = nullptr, int texture_count = 1) {
    Framebuffer fb(s.width, s.height);
    fb.clear(glm::vec4(0.0f), 0.0f);  // reversed-Z: far is 0
    DrawCall call;
    call.mesh = &s.mesh;
    call.shader = &shader;
    call.params = block.bytes;
    call.textures = textures;
    call.texture_count = textures ? texture_count : 0;
    call.model = s.model;
    call.view = s.view;
    call.projection = s.projection;
    call.camera_position = s.eye;
    call.lights = s.lights.data();
    call.light_count = uint32_t(s.lights.size());
    call.state.cull = CullMode::none;
    FrameStats stats;
    Pipeline().draw(call, fb, stats);
    return fb;
}

struct Ray {
    dvec3 origin, direction;
};

Ray pixel_ray(const Setup& s, int x, int y) {
    const glm::dmat4 inv = glm::inverse(glm::dmat4(s.projection) * glm::dmat4(s.view));
    const double nx = (x + 0.5) / s.width * 2.0 - 1.0, ny = 1.0 - (y + 0.5) / s.height * 2.0;
    const dvec4 a = inv * dvec4(nx, ny, 1.0, 1.0);  // reversed-Z: the near plane
    const dvec4 b = inv * dvec4(nx, ny, 0.5, 1.0);
    const dvec3 origin = dvec3(a) / a.w;
    return {origin, glm::normalize(dvec3(b) / b.w - origin)};
}

Setup perspective_setup(glm::vec3 eye, int width, int height, float fov_deg) {
    Setup s;
    s.width = width;
    s.height = height;
    s.eye = eye;
    s.view = look_at(eye, glm::vec3(0.0f), {0.0f, 1.0f, 0.0f});
    s.projection =
        perspective(glm::radians(fov_deg), float(width) / float(height), 0.1f, 50.0f, true);
    return s;
}

// ---- the quad ----------------------------------------------------------------

// A 2x2 quad in its XY plane, tilted towards the camera, squashed unevenly
// (so normals need the normal matrix and normalising), with bent corner
// normals and UVs 0..1, and three lights of different types.
Setup quad_setup() {
    Setup s = perspective_setup({0.3f, 1.7f, 3.4f}, 96, 64, 50.0f);
    Transform t;
    t.translation = {0.1f, -0.1f, 0.0f};
    t.rotation = euler_degrees({-75.0f, 20.0f, 0.0f});
    t.scale = {2.2f, 1.6f, 0.5f};
    s.model = t.matrix();
    s.mesh = make_mesh({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {0, 1, 2, 0, 2, 3});
    s.mesh.normals = {glm::normalize(glm::vec3(-0.6f, -0.4f, 1.0f)),
                      glm::normalize(glm::vec3(0.5f, -0.6f, 1.0f)),
                      glm::normalize(glm::vec3(0.6f, 0.7f, 1.0f)),
                      glm::normalize(glm::vec3(-0.4f, 0.6f, 1.0f))};
    s.mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    s.lights = {directional({0.4f, -1.0f, -0.3f}, {1.0f, 0.9f, 0.8f}, 0.5f),
                point({0.5f, 0.45f, 0.5f}, {0.9f, 0.95f, 1.0f}, 0.6f, {1.0f, 0.5f, 1.5f}, 1.4f),
                spot({-1.2f, 1.4f, -0.2f}, {-1.0f, -0.2f, -0.6f}, {1.0f, 0.6f, 0.3f}, 1.5f,
                     {1.0f, 0.0f, 0.3f}, 12.0f, 24.0f)};
    return s;
}

// Where the ray of pixel (x, y) meets the quad, with the weights of the
// triangle's three vertices; empty outside the quad or within `margin`
// (in quad units) of its edges.
struct Hit {
    dvec3 world;
    int vertex[3];
    double weight[3];
};

std::optional<Hit> hit_quad(const Setup& s, int x, int y, double margin = 0.04) {
    const Ray r = pixel_ray(s, x, y);
    const glm::dmat4 model(s.model);
    const glm::dmat4 to_local = glm::inverse(model);
    const dvec3 o = dvec3(to_local * dvec4(r.origin, 1.0));
    const dvec3 d = dvec3(to_local * dvec4(r.direction, 0.0));
    const double t = -o.z / d.z;
    const dvec2 q = dvec2(o) + t * dvec2(d);
    if (!(t > 0) || std::abs(q.x) > 1 - margin || std::abs(q.y) > 1 - margin) return std::nullopt;
    Hit h{dvec3(model * dvec4(q, 0.0, 1.0)), {0, 1, 2}, {}};
    if (q.y > q.x) h.vertex[1] = 2, h.vertex[2] = 3;  // triangle (0, 2, 3)
    const dvec2 a(s.mesh.positions[h.vertex[0]]), b(s.mesh.positions[h.vertex[1]]),
        c(s.mesh.positions[h.vertex[2]]);
    auto cross = [](dvec2 u, dvec2 v) { return u.x * v.y - u.y * v.x; };
    const double area = cross(b - a, c - a);
    h.weight[1] = cross(q - a, c - a) / area;
    h.weight[2] = cross(b - a, q - a) / area;
    h.weight[0] = 1.0 - h.weight[1] - h.weight[2];
    return h;
}

template <class T>
T interpolate(const Hit& h, const std::vector<T>& per_vertex) {
    return h.weight[0] * per_vertex[h.vertex[0]] + h.weight[1] * per_vertex[h.vertex[1]] +
           h.weight[2] * per_vertex[h.vertex[2]];
}

std::vector<dvec3> world_positions(const Setup& s) {
    std::vector<dvec3> out;
    for (const glm::vec3& p : s.mesh.positions)
        out.push_back(dvec3(glm::dmat4(s.model) * dvec4(dvec3(p), 1.0)));
    return out;
}

// Vertex normals as the shaders make them: normal matrix, then normalised.
std::vector<dvec3> world_normals(const Setup& s) {
    const glm::dmat3 n = glm::transpose(glm::inverse(glm::dmat3(glm::dmat4(s.model))));
    std::vector<dvec3> out;
    for (const glm::vec3& v : s.mesh.normals) out.push_back(glm::normalize(n * dvec3(v)));
    return out;
}

// ---- comparing an image with a reference ---------------------------------------

struct Match {
    int sampled = 0;
    int midtones = 0;    // reference pixels with a channel neither black nor saturated
    int max_error = 0;   // in 8-bit codes
    std::string worst;
};

// A reference returns the expected linear RGBA at a hit, or nothing to skip it.
using Reference = std::function<std::optional<dvec4>(const Hit&)>;

void compare_pixel(const uint8_t* got, const dvec4& want, int x, int y, Match& m) {
    int err = 0, mid = 0;
    for (int c = 0; c < 3; ++c) {
        const int code = linear_to_srgb8(float(want[c]));
        err = std::max(err, std::abs(int(got[c]) - code));
        mid |= code > 8 && code < 247;
    }
    const int alpha = int(std::lround(std::clamp(want.a, 0.0, 1.0) * 255.0));
    err = std::max(err, std::abs(int(got[3]) - alpha));
    ++m.sampled;
    m.midtones += mid;
    if (err <= m.max_error) return;
    m.max_error = err;
    std::ostringstream o;
    o << "pixel (" << x << ", " << y << "): facet " << int(got[0]) << " " << int(got[1]) << " "
      << int(got[2]) << " " << int(got[3]) << ", reference linear " << want.r << " " << want.g
      << " " << want.b << " " << want.a;
    m.worst = o.str();
}

Match compare(const Setup& s, const Framebuffer& fb, const Reference& reference) {
    const std::vector<uint8_t> px = fb.resolve_srgb8();
    Match m;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const std::optional<Hit> h = hit_quad(s, x, y);
            if (!h) continue;
            if (const std::optional<dvec4> want = reference(*h))
                compare_pixel(&px[4 * (size_t(y) * s.width + x)], *want, x, y, m);
        }
    return m;
}

void require_match(const Match& m, int min_sampled) {
    INFO("worst " << m.worst);
    CHECK(m.sampled >= min_sampled);
    CHECK(m.midtones * 2 >= m.sampled);
    REQUIRE(m.max_error <= 1);
}

// Largest difference, in codes, between two images of the same size.
int max_difference(const Framebuffer& a, const Framebuffer& b) {
    const std::vector<uint8_t> pa = a.resolve_srgb8(), pb = b.resolve_srgb8();
    int d = 0;
    for (size_t i = 0; i < pa.size(); ++i) d = std::max(d, std::abs(int(pa[i]) - int(pb[i])));
    return d;
}

// A 2x2 colour texture read with nearest filtering, and its reference
// texel; empty within a margin of the texel edges.
TextureBinding checker_texture() {
    auto tex = std::make_shared<Texture>();
    tex->width = tex->height = 2;
    // Two texels opaque, two well below the cutouts' 0.5.
    for (const glm::vec4 c : {glm::vec4(1.0, 0.8, 0.6, 1.0), glm::vec4(0.5, 0.9, 1.0, 0.4),
                              glm::vec4(0.9, 0.4, 0.7, 0.9), glm::vec4(0.7, 1.0, 0.5, 0.3)})
        tex->texels.push_back(encode_texel(c, false));
    return {tex, Filter::nearest, Wrap::clamp};
}

std::optional<dvec4> ref_texel(const Setup& s, const TextureBinding* t, const Hit& h) {
    if (!t) return dvec4(1.0);
    std::vector<dvec2> uvs(s.mesh.uvs.begin(), s.mesh.uvs.end());
    const dvec2 uv = interpolate(h, uvs);
    if (std::abs(uv.x - 0.5) < 0.01 || std::abs(uv.y - 0.5) < 0.01) return std::nullopt;
    return dvec4(t->texture->linear((uv.y >= 0.5) * 2 + (uv.x >= 0.5)));
}

// ---- lit -----------------------------------------------------------------------

// ambient + sum of radiance * max(n.L, 0); nothing near a range cut-off.
std::optional<dvec3> ref_irradiance(const Setup& s, const Values& p, const dvec3& pos,
                                    const dvec3& n) {
    dvec3 e = rgb(p, "ambient");
    for (const facet_light& l : s.lights) {
        const RefLight in = ref_light(l, pos);
        if (in.near_range) return std::nullopt;
        e += in.radiance * std::max(glm::dot(n, in.to_light), 0.0);
    }
    return e;
}

std::optional<dvec3> ref_mapped_normal(const Setup& s, const TextureBinding& map, double scale,
                                       const Hit& h, dvec3 n, dvec4 t);
std::vector<dvec4> world_tangents(const Setup& s);

// The interpolated normal at the hit, or with a normal map the one it gives.
std::optional<dvec3> ref_normal(const Setup& s, const std::vector<dvec3>& nrm,
                                const std::vector<dvec4>& tan, const TextureBinding* normal_map,
                                const Values& p, const Hit& h) {
    const dvec3 n = glm::normalize(interpolate(h, nrm));
    if (!normal_map) return n;
    return ref_mapped_normal(s, *normal_map, num(p, "normal_scale"), h, n, interpolate(h, tan));
}

Reference lit_reference(const Setup& s, const Values& p, const TextureBinding* tex,
                        const TextureBinding* normal_map = nullptr) {
    const std::vector<dvec3> pos = world_positions(s), nrm = world_normals(s);
    const std::vector<dvec4> tan = world_tangents(s);
    std::vector<dvec3> vertex_e;  // Gouraud: irradiance of each vertex
    for (size_t i = 0; i < pos.size(); ++i)
        vertex_e.push_back(ref_irradiance(s, p, pos[i], nrm[i]).value());
    const bool per_pixel = num(p, "per_pixel") != 0;
    return [=, &s](const Hit& h) -> std::optional<dvec4> {
        const std::optional<dvec4> texel = ref_texel(s, tex, h);
        const std::optional<dvec3> n = ref_normal(s, nrm, tan, normal_map, p, h);
        if (!texel || !n) return std::nullopt;
        const std::optional<dvec3> e = per_pixel ? ref_irradiance(s, p, h.world, *n)
                                                 : std::optional<dvec3>(interpolate(h, vertex_e));
        if (!e) return std::nullopt;
        const dvec4 albedo = rgba(p, "base_color") * *texel;
        return dvec4(dvec3(albedo) * *e, albedo.a);
    };
}

// The shadow and AO parameters (facet::sdk::Receiving) at their defaults,
// added to a lit shader's own: the setups here have no shadow maps and no AO,
// which the tests in test_shadow_ao.cpp cover.
Values receiving(Values v) {
    v["receive_shadows"] = {1.0};
    v["shadow_kernel"] = {3.0};
    v["shadow_bias"] = {1.0};
    v["shadow_slope_bias"] = {1.5};
    v["ambient_occlusion"] = {0.0};
    return v;
}

Values with_ao(Values v) {
    v["ambient_occlusion"] = {1.0};
    return v;
}

Values cutout(Values v, double alpha_cutoff) {
    v["alpha_cutoff"] = {alpha_cutoff};
    return v;
}

Values unlit_values(double textured, double alpha_cutoff) {
    return {{"base_color", {0.8, 0.5, 0.25, 0.9}}, {"base_texture", {textured}},
            {"ambient_occlusion", {0.0}}, {"alpha_cutoff", {alpha_cutoff}}};
}

Values lit_values(bool per_pixel, bool textured) {
    return receiving({{"base_color", {0.9, 0.75, 0.6, 0.8}},
            {"ambient", {0.05, 0.06, 0.08}},
            {"base_texture", {double(textured)}},
            {"per_pixel", {double(per_pixel)}},
            {"alpha_cutoff", {0.0}},
            {"normal_texture", {0.0}},
            {"normal_scale", {1.0}}});
}

// ---- phong ---------------------------------------------------------------------

double ref_lobe(const dvec3& n, const dvec3& l, const dvec3& v, const Values& p) {
    const double c = num(p, "blinn") != 0 ? glm::dot(n, glm::normalize(l + v))
                                          : glm::dot(2.0 * glm::dot(n, l) * n - l, v);
    return std::pow(std::max(c, 0.0), num(p, "shininess"));
}

// Gouraud: the lights' diffuse and specular sums at a vertex; nothing near
// a range cut-off.
std::optional<std::pair<dvec3, dvec3>> ref_vertex_light(const Setup& s, const Values& p,
                                                        const dvec3& pos, const dvec3& n) {
    const dvec3 v = glm::normalize(dvec3(s.eye) - pos);
    dvec3 diffuse(0.0), specular(0.0);
    for (const facet_light& l : s.lights) {
        const RefLight in = ref_light(l, pos);
        if (in.near_range) return std::nullopt;
        const double n_l = glm::dot(n, in.to_light);
        if (n_l <= 0) continue;
        diffuse += in.radiance * n_l;
        specular += in.radiance * ref_lobe(n, in.to_light, v, p);
    }
    return std::pair{diffuse, specular};
}

Reference phong_reference(const Setup& s, const Values& p, const TextureBinding* tex,
                          const TextureBinding* normal_map = nullptr) {
    const std::vector<dvec3> nrm = world_normals(s), pos = world_positions(s);
    const std::vector<dvec4> tan = world_tangents(s);
    std::vector<dvec3> vertex_diffuse, vertex_specular;  // gouraud
    bool near_edge = false;
    for (size_t i = 0; i < pos.size(); ++i) {
        const auto light = ref_vertex_light(s, p, pos[i], nrm[i]);
        near_edge |= !light;
        vertex_diffuse.push_back(light ? light->first : dvec3(0.0));
        vertex_specular.push_back(light ? light->second : dvec3(0.0));
    }
    const bool gouraud = num(p, "gouraud") != 0;
    return [=, &s](const Hit& h) -> std::optional<dvec4> {
        const std::optional<dvec4> texel = ref_texel(s, tex, h);
        const std::optional<dvec3> mapped = ref_normal(s, nrm, tan, normal_map, p, h);
        if (!texel || !mapped) return std::nullopt;
        const dvec3 n = *mapped;
        const dvec3 v = glm::normalize(dvec3(s.eye) - h.world);
        const dvec3 kd = rgb(p, "diffuse") * dvec3(*texel);
        dvec3 c = rgb(p, "emission") + rgb(p, "ambient");
        if (gouraud) {
            if (near_edge) return std::nullopt;
            c += kd * interpolate(h, vertex_diffuse) + rgb(p, "specular") * interpolate(h, vertex_specular);
            return dvec4(c, texel->a);
        }
        for (const facet_light& l : s.lights) {
            const RefLight in = ref_light(l, h.world);
            if (in.near_range) return std::nullopt;
            const double n_l = glm::dot(n, in.to_light);
            if (n_l <= 0) continue;
            c += in.radiance * (kd * n_l + rgb(p, "specular") * ref_lobe(n, in.to_light, v, p));
        }
        return dvec4(c, texel->a);  // the base texture's alpha (1 without one)
    };
}

Values phong_values(bool blinn, double shininess, bool textured) {
    return receiving({{"ambient", {0.02, 0.02, 0.03}},
            {"diffuse", {0.55, 0.45, 0.35}},
            {"specular", {0.4, 0.4, 0.45}},
            {"emission", {0.03, 0.0, 0.01}},
            {"shininess", {shininess}},
            {"blinn", {double(blinn)}},
            {"gouraud", {0.0}},
            {"base_texture", {double(textured)}},
            {"alpha_cutoff", {0.0}},
            {"normal_texture", {0.0}},
            {"normal_scale", {1.0}}});
}

// ---- toon ----------------------------------------------------------------------

struct ToonRef {
    dvec3 color;
    bool outline = false, rim = false, highlight = false;
    std::vector<double> bands;  // each light's band
};

bool near(double a, double b, double margin) { return std::abs(a - b) < margin; }

// One light's diffuse band and highlight; false if too near an edge.
bool ref_toon_light(const RefLight& in, const dvec3& n, const dvec3& v, const Values& p,
                    ToonRef& out, dvec3& light, dvec3& shine) {
    if (in.near_range) return false;
    if (in.radiance == dvec3(0.0)) {  // out of range or cone: no light, so no edges
        out.bands.push_back(0.0);
        return true;
    }
    const double bands = num(p, "bands"), n_l = glm::dot(n, in.to_light), x = n_l * bands;
    if (x > -0.01 && near(x, std::round(x), 2e-3 * bands)) return false;
    const double band = n_l > 0 ? std::ceil(x) / bands : 0.0;
    light += in.radiance * band;
    out.bands.push_back(band);
    if (n_l <= 0) return true;
    const double s = std::pow(std::max(glm::dot(n, glm::normalize(in.to_light + v)), 0.0),
                              num(p, "shininess"));
    if (near(s, num(p, "specular_threshold"), 0.01)) return false;
    if (s > num(p, "specular_threshold")) {
        shine += in.radiance * rgb(p, "specular_color");
        out.highlight = true;
    }
    return true;
}

std::optional<ToonRef> ref_toon(const Setup& s, const Values& p, const dvec3& pos,
                                const dvec3& n) {
    const dvec3 v = glm::normalize(dvec3(s.eye) - pos);
    const double n_v = glm::dot(n, v), width = num(p, "outline_width");
    ToonRef out;
    if (width > 0 && near(n_v, width, 2e-3)) return std::nullopt;
    if (width > 0 && n_v < width) {
        out.outline = true;
        out.color = rgb(p, "outline_color");
        return out;
    }
    dvec3 light = rgb(p, "ambient"), shine(0.0);
    for (const facet_light& l : s.lights)
        if (!ref_toon_light(ref_light(l, pos), n, v, p, out, light, shine)) return std::nullopt;
    if (near(1 - n_v, num(p, "rim_threshold"), 2e-3)) return std::nullopt;
    out.rim = 1 - n_v > num(p, "rim_threshold");
    const dvec3 rim = out.rim ? rgb(p, "rim_color") : dvec3(0.0);
    out.color = rgb(p, "base_color") * light + shine + rim;
    return out;
}

Values toon_values(int bands, double outline_width) {
    return receiving({{"base_color", {0.8, 0.45, 0.3}},
            {"ambient", {0.06, 0.06, 0.08}},
            {"bands", {double(bands)}},
            {"specular_color", {0.5, 0.5, 0.45}},
            {"shininess", {40.0}},
            {"specular_threshold", {0.5}},
            {"rim_color", {0.1, 0.15, 0.25}},
            {"rim_threshold", {0.45}},
            {"outline_color", {0.02, 0.01, 0.0}},
            {"outline_width", {outline_width}},
            {"normal_texture", {0.0}},
            {"normal_scale", {1.0}}});
}

// ---- normal maps -----------------------------------------------------------------

// The quad's tangents: along +u (its +X), and w = -1, because its V runs
// up the quad (+Y) while the bitangent points to the texture's top (-V).
void add_tangents(Setup& s) { s.mesh.tangents.assign(4, glm::vec4(1.0f, 0.0f, 0.0f, -1.0f)); }

// A 2x2 normal map (linear), read with nearest filtering: four normals
// leaning different ways, as n * 0.5 + 0.5.
TextureBinding normal_texture() {
    auto tex = std::make_shared<Texture>();
    tex->width = tex->height = 2;
    for (const glm::vec3 n : {glm::vec3(0.35f, 0.2f, 1.0f), glm::vec3(-0.45f, 0.1f, 1.0f),
                              glm::vec3(0.1f, -0.5f, 1.0f), glm::vec3(-0.2f, -0.3f, 1.0f)})
        tex->texels.push_back(encode_texel(glm::vec4(glm::normalize(n) * 0.5f + 0.5f, 1.0f), false));
    return {tex, Filter::nearest, Wrap::clamp};
}

// World tangents as the shaders make them (sdk::world_tangent): by the
// model's 3x3, normalised, w turned around where it mirrors.
std::vector<dvec4> world_tangents(const Setup& s) {
    const glm::dmat3 m(glm::dmat4(s.model));
    std::vector<dvec4> out;
    for (const glm::vec4& t : s.mesh.tangents)
        out.push_back(dvec4(glm::normalize(m * dvec3(t)), glm::determinant(m) < 0 ? -t.w : t.w));
    return out;
}

// The normal the map gives at the hit (the glTF convention), from the
// interpolated normal and tangent; empty near a texel edge.
std::optional<dvec3> ref_mapped_normal(const Setup& s, const TextureBinding& map, double scale,
                                       const Hit& h, dvec3 n, dvec4 t) {
    const std::optional<dvec4> texel = ref_texel(s, &map, h);
    if (!texel) return std::nullopt;
    const dvec3 m((texel->x * 2 - 1) * scale, (texel->y * 2 - 1) * scale, texel->z * 2 - 1);
    const dvec3 tangent = glm::normalize(dvec3(t) - n * glm::dot(n, dvec3(t)));
    const dvec3 bitangent = glm::cross(n, tangent) * (t.w < 0 ? -1.0 : 1.0);
    return glm::normalize(tangent * m.x + bitangent * m.y + n * m.z);
}

// ---- pbr -------------------------------------------------------------------------

// A clear coat over a dielectric of another index and a tinted specular.
Values layered(Values v) {
    v["ior"] = {1.8};
    v["specular"] = {0.7};
    v["specular_color"] = {0.9, 1.0, 0.6};
    v["clearcoat"] = {0.8};
    v["clearcoat_roughness"] = {0.2};
    return v;
}

Values pbr_values(double metallic, double roughness, bool base_texture, bool normal_map) {
    return receiving({{"base_color", {0.85, 0.6, 0.4, 0.9}},
                      {"base_texture", {double(base_texture)}},
                      {"metallic", {metallic}},
                      {"roughness", {roughness}},
                      {"metallic_roughness_texture", {0.0}},
                      {"normal_texture", {double(normal_map)}},
                      {"normal_scale", {0.8}},
                      {"occlusion_texture", {0.0}},
                      {"occlusion_strength", {1.0}},
                      {"emissive", {0.02, 0.01, 0.0}},
                      {"emissive_texture", {0.0}},
                      {"ambient", {0.05, 0.05, 0.06}},
                      {"ior", {1.5}},
                      {"specular", {1.0}},
                      {"specular_color", {1.0, 1.0, 1.0}},
                      {"clearcoat", {0.0}},
                      {"clearcoat_roughness", {0.0}},
                      {"clearcoat_texture", {0.0}},
                      {"clearcoat_roughness_texture", {0.0}},
                      {"alpha_cutoff", {0.0}},
                      {"opaque_alpha", {0.0}}});
}

// glTF 2.0's metallic-roughness BRDF (its Appendix B), times pi, in double,
// with KHR_materials_ior, _specular and _clearcoat as their specifications
// write them; the ambient share from Karis's fit, as pbr.cpp documents it.
// n is the shading normal, coat_n the clear coat's (the interpolated one).
struct RefLobe {
    dvec3 c_diff, f0;
    double f90, roughness;
};

// Uniform ambient light reflected by a lobe, at n.v.
dvec3 ref_ambient(const Values& p, const RefLobe& lobe, double n_v) {
    const dvec4 r = lobe.roughness * dvec4(-1, -0.0275, -0.572, 0.022) + dvec4(1, 0.0425, 1.04, -0.04);
    const double a = std::min(r.x * r.x, std::exp2(-9.28 * n_v)) * r.x + r.y;
    return rgb(p, "ambient") * (lobe.c_diff + lobe.f0 * (-1.04 * a + r.z) + lobe.f90 * (1.04 * a + r.w));
}

// A lobe lit from unit direction l, times pi and n.l.
dvec3 ref_lit(const RefLobe& lobe, const dvec3& n, const dvec3& v, const dvec3& l) {
    const double n_l = std::max(glm::dot(n, l), 0.0), n_v = std::max(glm::dot(n, v), 1e-4);
    if (n_l == 0) return dvec3(0);
    const double a2 = std::pow(lobe.roughness, 4);
    const dvec3 h = glm::normalize(l + v);
    const double n_h = std::max(glm::dot(n, h), 0.0), v_h = std::max(glm::dot(v, h), 0.0);
    const dvec3 f = lobe.f0 + (lobe.f90 - lobe.f0) * std::pow(1 - v_h, 5);
    const double d = a2 / (M_PI * std::pow(n_h * n_h * (a2 - 1) + 1, 2));
    const double vis = 0.5 / (n_l * std::sqrt(n_v * n_v * (1 - a2) + a2) +
                              n_v * std::sqrt(n_l * n_l * (1 - a2) + a2));
    return n_l * ((1.0 - f) * lobe.c_diff + M_PI * f * d * vis);
}

dvec3 ref_pbr(const Setup& s, const Values& p, const dvec4& base, const dvec3& pos,
              const dvec3& n, const dvec3& coat_n, bool& near_edge) {
    const double metallic = num(p, "metallic"), weight = num(p, "specular");
    const double r0 = std::pow((num(p, "ior") - 1) / (num(p, "ior") + 1), 2);
    const dvec3 dielectric = glm::min(r0 * rgb(p, "specular_color"), dvec3(1)) * weight;
    const RefLobe lobe{dvec3(base) * (1 - metallic), glm::mix(dielectric, dvec3(base), metallic),
                       weight + (1 - weight) * metallic, std::max(num(p, "roughness"), 0.03)};
    const RefLobe coat{dvec3(0), dvec3(1), 1.0, std::max(num(p, "clearcoat_roughness"), 0.03)};
    const dvec3 v = glm::normalize(dvec3(s.eye) - pos);
    // KHR_materials_clearcoat's fresnel_coat: mix(base, layer, clearcoat * Fr(n_c.v)).
    const double w = num(p, "clearcoat") *
                     (0.04 + 0.96 * std::pow(1 - std::max(glm::dot(coat_n, v), 1e-4), 5));
    dvec3 c = (1 - w) * ref_ambient(p, lobe, std::max(glm::dot(n, v), 1e-4)) +
              w * ref_ambient(p, coat, std::max(glm::dot(coat_n, v), 1e-4));
    for (const facet_light& l : s.lights) {
        const RefLight in = ref_light(l, pos);
        near_edge |= in.near_range;
        if (glm::dot(n, in.to_light) <= 0) continue;  // the base's side of the light
        c += in.radiance * ((1 - w) * ref_lit(lobe, n, v, in.to_light) +
                            w * ref_lit(coat, coat_n, v, in.to_light));
    }
    return (1 - w) * rgb(p, "emissive") + c;  // the coat lies over the emission too
}

// Whether the quad's front faces the camera at the hit (the pipeline's
// counter-clockwise front: its local +Z side).
bool quad_front(const Setup& s, const Hit& h) {
    const dvec3 n = glm::transpose(glm::inverse(glm::dmat3(glm::dmat4(s.model)))) * dvec3(0, 0, 1);
    return glm::dot(n, dvec3(s.eye) - h.world) > 0;
}

Reference pbr_reference(const Setup& s, const Values& p, const TextureBinding* base_tex,
                        const TextureBinding* normal_map) {
    const std::vector<dvec3> nrm = world_normals(s);
    const std::vector<dvec4> tan = world_tangents(s);
    return [=, &s](const Hit& h) -> std::optional<dvec4> {
        const std::optional<dvec4> texel = ref_texel(s, base_tex, h);
        if (!texel) return std::nullopt;
        dvec3 n = glm::normalize(interpolate(h, nrm));
        dvec4 t = interpolate(h, tan);
        if (!quad_front(s, h)) n = -n, t = -t;
        const dvec3 geometric = n;
        if (normal_map) {
            const std::optional<dvec3> mapped =
                ref_mapped_normal(s, *normal_map, num(p, "normal_scale"), h, n, t);
            if (!mapped) return std::nullopt;
            n = *mapped;
        }
        const dvec4 base = rgba(p, "base_color") * *texel;
        bool near_edge = false;
        const dvec3 c = ref_pbr(s, p, base, h.world, n, geometric, near_edge);
        if (near_edge) return std::nullopt;
        return dvec4(c, num(p, "opaque_alpha") != 0 ? 1.0 : base.a);
    };
}

// ---- a sphere ------------------------------------------------------------------

Setup sphere_setup(const std::vector<facet_light>& lights) {
    Setup s = perspective_setup({0.0f, 0.0f, 4.0f}, 96, 96, 40.0f);
    s.mesh = uv_sphere(48);  // exact unit normals
    s.lights = lights;
    return s;
}

// Where pixel (x, y)'s ray meets the exact unit sphere.
std::optional<dvec3> hit_sphere(const Setup& s, int x, int y) {
    const Ray r = pixel_ray(s, x, y);
    const double b = glm::dot(r.origin, r.direction), c = glm::dot(r.origin, r.origin) - 1.0;
    if (b * b - c < 0) return std::nullopt;
    return r.origin + (-b - std::sqrt(b * b - c)) * r.direction;
}

bool covered(const Framebuffer& fb, int x, int y) { return fb.depth_at(x, y) > 0.0f; }

}  // namespace

// ---- the tests -----------------------------------------------------------------

TEST_CASE("lit.so matches Lambert plus ambient, per pixel and per vertex", "[shader][lit]") {
    PluginRegistry registry;
    const auto lit = registry.get("lit");
    const Setup s = quad_setup();
    const TextureBinding texture = checker_texture();
    Framebuffer images[2];
    for (bool per_pixel : {true, false})
        for (bool textured : {false, true}) {
            INFO("per_pixel " << per_pixel << ", textured " << textured);
            const Values p = lit_values(per_pixel, textured);
            const TextureBinding* tex = textured ? &texture : nullptr;
            const Framebuffer fb = draw(s, *lit, make_block(*lit, p), tex);
            require_match(compare(s, fb, lit_reference(s, p, tex)), 1500);
            if (!textured) images[per_pixel] = fb;
        }
    // The point light is close: lighting only the vertices misses its peak.
    CHECK(max_difference(images[0], images[1]) > 10);
}

TEST_CASE("phong.so matches Phong and Blinn-Phong with directional, point and spot lights",
          "[shader][phong]") {
    PluginRegistry registry;
    const auto phong = registry.get("phong");
    const Setup s = quad_setup();
    const TextureBinding texture = checker_texture();
    struct Case {
        bool blinn;
        double shininess;
        bool textured;
    };
    for (const Case c : {Case{false, 24, false}, Case{true, 24, false}, Case{true, 400, false},
                         Case{false, 1, true}, Case{false, 6000, true}}) {
        INFO("blinn " << c.blinn << ", shininess " << c.shininess << ", textured " << c.textured);
        const Values p = phong_values(c.blinn, c.shininess, c.textured);
        const TextureBinding* tex = c.textured ? &texture : nullptr;
        const Framebuffer fb = draw(s, *phong, make_block(*phong, p), tex);
        require_match(compare(s, fb, phong_reference(s, p, tex)), 1500);
    }
    // Gouraud with specular: each light's terms at the vertices, interpolated.
    for (const Case c : {Case{false, 24, false}, Case{true, 8, true}}) {
        INFO("gouraud, blinn " << c.blinn << ", shininess " << c.shininess << ", textured " << c.textured);
        Values p = phong_values(c.blinn, c.shininess, c.textured);
        p["gouraud"] = {1.0};
        const TextureBinding* tex = c.textured ? &texture : nullptr;
        const Framebuffer fb = draw(s, *phong, make_block(*phong, p), tex);
        require_match(compare(s, fb, phong_reference(s, p, tex)), 1500);
        CHECK(max_difference(fb, draw(s, *phong, make_block(*phong, phong_values(c.blinn, c.shininess,
                                                                               c.textured)),
                                      tex)) > 10);  // not the per-pixel image
    }
    // The choice of lobe and the exponent both show.
    auto image = [&](bool blinn, double shininess) {
        return draw(s, *phong, make_block(*phong, phong_values(blinn, shininess, false)));
    };
    CHECK(max_difference(image(false, 24), image(true, 24)) > 10);
    CHECK(max_difference(image(true, 24), image(true, 400)) > 10);
}

// Largest difference between two images, over every pixel and channel.
float max_abs_difference(const Framebuffer& a, const Framebuffer& b) {
    float worst = 0.0f;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            for (int c = 0; c < 4; ++c)
                worst = std::max(worst, std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c]));
    return worst;
}

// Pixels of two same-sized float images whose channels differ by more
// than `tolerance`.
int pixels_differing(const Framebuffer& a, const Framebuffer& b, float tolerance) {
    int n = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            for (int c = 0; c < 4; ++c)
                if (!(std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c]) <= tolerance)) {
                    ++n;
                    break;
                }
    return n;
}

TEST_CASE("fragment_wide matches the shader's own scalar fragment (phong, unlit, lit, toon, pbr)",
          "[shader][wide]") {
    PluginRegistry registry;
    Setup s = quad_setup();
    add_tangents(s);
    const TextureBinding texture = checker_texture(), normals = normal_texture();
    struct Case {
        std::string shader;
        Values values;
        bool textured;
        int normal_slot = -1;  // with a normal map in this texture slot
    };
    auto mapped = [](Values v) {
        v["normal_texture"] = {1.0};
        v["normal_scale"] = {1.3};
        return v;
    };
    const Case cases[] = {
        {"phong", phong_values(false, 24, false), false},
        {"phong", phong_values(true, 400, false), false},
        {"phong", phong_values(false, 1, true), true},
        {"phong", phong_values(true, 6000, true), true},
        {"unlit", unlit_values(0.0, 0.0), false},
        {"unlit", unlit_values(1.0, 0.0), true},
        {"lit", lit_values(true, false), false},
        {"lit", lit_values(false, false), false},
        {"lit", lit_values(true, true), true},
        {"toon", toon_values(3, 0.42), false},
        {"toon", toon_values(7, 0.0), false},
        // The version that receives shadows and AO (none here: AO reads 1).
        {"phong", with_ao(phong_values(true, 40, true)), true},
        {"lit", with_ao(lit_values(false, false)), false},
        {"toon", with_ao(toon_values(3, 0.42)), false},
        // Cutouts, where the texture's alpha (or the base colour's) falls
        // below the cutoff.
        {"unlit", unlit_values(1.0, 0.5), true},
        {"lit", cutout(lit_values(true, true), 0.5), true},
        {"phong", cutout(phong_values(false, 24, true), 0.5), true},
        {"pbr", pbr_values(0.0, 0.5, false, false), false},
        {"pbr", pbr_values(1.0, 0.25, true, false), true},
        {"pbr", with_ao(pbr_values(0.3, 0.7, true, false)), true},
        {"pbr", cutout(pbr_values(0.0, 0.6, true, false), 0.5), true},
        {"pbr", layered(pbr_values(0.2, 0.5, true, false)), true},
        // Normal maps.
        {"pbr", pbr_values(0.5, 0.4, true, true), true, 2},
        {"lit", mapped(lit_values(true, true)), true, 1},
        {"phong", mapped(phong_values(false, 40, false)), false, 1},
        {"toon", mapped(toon_values(4, 0.3)), false, 0}};
    for (const Case& c : cases) {
        INFO(c.shader << ", textured " << c.textured);
        const auto wide = registry.get(c.shader);
        const auto scalar = ShaderPlugin::load(
            std::string(FACET_TEST_PLUGIN_DIR) + "/" + c.shader + "_reference.so", c.shader);
        std::vector<TextureBinding> slots(size_t(std::max(1, c.normal_slot + 1)));
        if (c.textured) slots[0] = texture;
        if (c.normal_slot >= 0) slots[size_t(c.normal_slot)] = normals;
        const Framebuffer a =
            draw(s, *wide, make_block(*wide, c.values), slots.data(), int(slots.size()));
        const Framebuffer b =
            draw(s, *scalar, make_block(*scalar, c.values), slots.data(), int(slots.size()));
        // Not a blank image on both sides.
        float brightest = 0.0f;
        for (int y = 0; y < b.height(); ++y)
            for (int x = 0; x < b.width(); ++x) brightest = std::max(brightest, b.pixel(x, y).g);
        CHECK(brightest > 0.2f);
        // wide::pow is within 1e-6 relative of std::pow where it matters;
        // the rest differs by rounding. Toon's bands and thresholds are
        // steps: a pixel within rounding of one may fall on either side.
        // pbr's specular peaks reach several times 1, where the same
        // relative rounding is a larger absolute difference.
        if (c.shader == "toon")
            CHECK(pixels_differing(a, b, 2e-5f) <= a.width() * a.height() / 1000);
        else
            CHECK(max_abs_difference(a, b) < (c.shader == "pbr" ? 1e-4f : 2e-5f));
    }
}

TEST_CASE("every shipped shader's fragment_wide draws its demo scene as its scalar fragment "
          "does, shadow maps and AO included, on every path",
          "[shader][wide][isa]") {
    PluginRegistry registry;
    for (const char* name : kDemoScenes) {
        Scene scene = small_demo_scene(registry, name);
        scene.settings.color_format = ColorFormat::rgba32f;  // compare before rounding
        // Each material's plugin, and the same shader built with FACET_SDK_REFERENCE.
        PluginSwap scalar_build(scene, [](const Material& m) {
            const std::string shader = m.plugin->name();
            return ShaderPlugin::load(
                std::string(FACET_TEST_PLUGIN_DIR) + "/" + shader + "_reference.so", shader);
        });
        REQUIRE_FALSE(scalar_build.empty());
        for (Isa isa : supported_isas()) {
            INFO(name << ", path " << isa_name(isa));
            Renderer renderer(2, isa);
            Framebuffer wide, scalar;
            renderer.render(scene, wide);
            scalar_build.swap();
            renderer.render(scene, scalar);
            scalar_build.swap();
            // A PCF tap or a toon threshold within rounding may go either way.
            CHECK(pixels_differing(wide, scalar, 2e-5f) <= wide.width() * wide.height() / 1000);
            CHECK(max_abs_difference(wide, scalar) < 0.5f);
        }
    }
}

TEST_CASE("pbr.so matches glTF's metallic-roughness BRDF with directional, point and spot lights",
          "[shader][pbr]") {
    PluginRegistry registry;
    const auto pbr = registry.get("pbr");
    Setup s = quad_setup();
    add_tangents(s);
    const TextureBinding checker = checker_texture(), normals = normal_texture();
    struct Case {
        double metallic, roughness;
        bool textured, mapped;
    };
    for (const Case c : {Case{0.0, 0.5, false, false}, Case{1.0, 0.3, false, false},
                         Case{0.4, 0.8, false, false}, Case{0.0, 1.0, true, false},
                         Case{1.0, 0.45, false, true}, Case{0.0, 0.35, true, true}}) {
        INFO("metallic " << c.metallic << ", roughness " << c.roughness << ", textured "
                         << c.textured << ", normal map " << c.mapped);
        Values p = pbr_values(c.metallic, c.roughness, c.textured, c.mapped);
        p["opaque_alpha"] = {double(c.textured)};  // alpha 1, where the texture's is below
        std::vector<TextureBinding> slots(5);  // base, metallic-roughness, normal, occlusion, emissive
        if (c.textured) slots[0] = checker;
        if (c.mapped) slots[2] = normals;
        const Framebuffer fb = draw(s, *pbr, make_block(*pbr, p), slots.data(), 5);
        require_match(compare(s, fb, pbr_reference(s, p, c.textured ? &checker : nullptr,
                                                   c.mapped ? &normals : nullptr)),
                      1500);
    }
    // An index of refraction, a tinted and weakened specular, and clear
    // coats, over a dielectric and a metal, with and without a normal map
    // (the coat keeps the interpolated normal).
    struct Layered {
        double metallic, ior, specular, clearcoat, coat_roughness;
        bool mapped;
    };
    for (const Layered c : {Layered{0.0, 1.9, 0.6, 0.0, 0.0, false}, Layered{0.0, 1.5, 1.0, 1.0, 0.1, false},
                            Layered{1.0, 1.5, 1.0, 0.7, 0.5, true}, Layered{0.2, 2.4, 0.8, 0.5, 0.3, true}}) {
        INFO("metallic " << c.metallic << ", ior " << c.ior << ", specular " << c.specular
                         << ", clearcoat " << c.clearcoat << " of roughness " << c.coat_roughness
                         << ", normal map " << c.mapped);
        Values p = pbr_values(c.metallic, 0.4, false, c.mapped);
        p["ior"] = {c.ior};
        p["specular"] = {c.specular};
        p["specular_color"] = {1.0, 0.7, 0.4};
        p["clearcoat"] = {c.clearcoat};
        p["clearcoat_roughness"] = {c.coat_roughness};
        std::vector<TextureBinding> slots(7);
        if (c.mapped) slots[2] = normals;
        const Framebuffer fb = draw(s, *pbr, make_block(*pbr, p), slots.data(), 7);
        require_match(compare(s, fb, pbr_reference(s, p, nullptr, c.mapped ? &normals : nullptr)), 1500);
    }
    // Metal and roughness both show.
    auto image = [&](double metallic, double roughness) {
        return draw(s, *pbr, make_block(*pbr, pbr_values(metallic, roughness, false, false)));
    };
    CHECK(max_difference(image(0.0, 0.4), image(1.0, 0.4)) > 10);
    CHECK(max_difference(image(1.0, 0.2), image(1.0, 0.7)) > 10);
    // So do a coat and a weaker specular.
    Values coated = pbr_values(0.0, 0.6, false, false), dull = pbr_values(0.0, 0.2, false, false);
    coated["clearcoat"] = {1.0};
    dull["specular"] = {0.0};
    CHECK(max_difference(draw(s, *pbr, make_block(*pbr, coated)), image(0.0, 0.6)) > 10);
    CHECK(max_difference(draw(s, *pbr, make_block(*pbr, dull)), image(0.0, 0.2)) > 10);
}

TEST_CASE("lit, phong and toon bend their normal by a normal map in the glTF convention",
          "[shader][normal]") {
    PluginRegistry registry;
    Setup s = quad_setup();
    add_tangents(s);
    const TextureBinding normals = normal_texture();
    const TextureBinding none;
    // lit and phong read the map in slot 1 (after base_texture), toon in slot 0.
    const TextureBinding two[2] = {none, normals};
    auto mapped = [](Values v) {
        v["normal_texture"] = {1.0};
        v["normal_scale"] = {0.8};
        return v;
    };
    {
        const auto lit = registry.get("lit");
        const Values p = mapped(lit_values(true, false));
        const Framebuffer fb = draw(s, *lit, make_block(*lit, p), two, 2);
        require_match(compare(s, fb, lit_reference(s, p, nullptr, &normals)), 1500);
        const Framebuffer flat = draw(s, *lit, make_block(*lit, lit_values(true, false)));
        CHECK(max_difference(fb, flat) > 10);  // the map shows
    }
    {
        const auto phong = registry.get("phong");
        const Values p = mapped(phong_values(true, 24, false));
        const Framebuffer fb = draw(s, *phong, make_block(*phong, p), two, 2);
        require_match(compare(s, fb, phong_reference(s, p, nullptr, &normals)), 1500);
    }
    {
        const auto toon = registry.get("toon");
        const Values p = mapped(toon_values(3, 0.0));
        const Framebuffer fb = draw(s, *toon, make_block(*toon, p), &normals, 1);
        const std::vector<dvec3> nrm = world_normals(s);
        const std::vector<dvec4> tan = world_tangents(s);
        const Match m = compare(s, fb, [&](const Hit& h) -> std::optional<dvec4> {
            const std::optional<dvec3> n = ref_normal(s, nrm, tan, &normals, p, h);
            if (!n) return std::nullopt;
            const std::optional<ToonRef> t = ref_toon(s, p, h.world, *n);
            if (!t) return std::nullopt;
            return dvec4(t->color, 1.0);
        });
        require_match(m, 1000);
    }
}

TEST_CASE("toon.so matches its formula away from band and threshold edges", "[shader][toon]") {
    PluginRegistry registry;
    const auto toon = registry.get("toon");
    const Setup s = quad_setup();
    const std::vector<dvec3> nrm = world_normals(s);
    for (int bands : {1, 3, 5}) {
        INFO("bands " << bands);
        const Values p = toon_values(bands, 0.42);
        const Framebuffer fb = draw(s, *toon, make_block(*toon, p));
        int outline = 0, rim = 0, highlight = 0;
        std::set<std::vector<double>> levels;
        const Match m = compare(s, fb, [&](const Hit& h) -> std::optional<dvec4> {
            const auto r = ref_toon(s, p, h.world, glm::normalize(interpolate(h, nrm)));
            if (!r) return std::nullopt;
            outline += r->outline, rim += r->rim, highlight += r->highlight;
            if (!r->outline) levels.insert(r->bands);
            return dvec4(r->color, 1.0);
        });
        require_match(m, 1000);
        // Every feature is on the quad somewhere, so each is compared.
        CHECK(outline > 20);
        CHECK(rim > 20);
        CHECK(highlight > 20);
        CHECK(levels.size() >= size_t(std::min(bands + 1, 4)));  // combinations of bands
    }
}

TEST_CASE("toon bands set the number of diffuse levels on a sphere", "[shader][toon]") {
    PluginRegistry registry;
    const auto toon = registry.get("toon");
    const Setup s = sphere_setup({directional({-1.0f, -0.2f, -0.6f}, {1, 1, 1}, 0.9f)});
    for (int bands : {1, 2, 4, 7, 10}) {
        Values p = toon_values(bands, 0.0);  // no outline
        p["specular_color"] = p["rim_color"] = {0, 0, 0};
        const Framebuffer fb = draw(s, *toon, make_block(*toon, p));
        std::set<float> levels;
        for (int y = 0; y < s.height; ++y)
            for (int x = 0; x < s.width; ++x)
                if (covered(fb, x, y)) levels.insert(fb.pixel(x, y).r);
        // The lit levels 1/bands .. 1, and the unlit side.
        CHECK(levels.size() == size_t(bands + 1));
    }
}

TEST_CASE("toon outlines cover exactly where the sphere turns away from the viewer",
          "[shader][toon]") {
    PluginRegistry registry;
    const auto toon = registry.get("toon");
    const Setup s = sphere_setup({directional({-0.3f, -0.5f, -1.0f}, {1, 1, 1}, 1.0f)});
    const glm::vec4 magenta(1.0f, 0.0f, 1.0f, 1.0f);
    for (double width : {0.0, 0.3, 0.6}) {
        INFO("outline_width " << width);
        Values p = toon_values(3, width);
        p["outline_color"] = {1, 0, 1};
        const Framebuffer fb = draw(s, *toon, make_block(*toon, p));
        int inside = 0, outline = 0;
        for (int y = 0; y < s.height; ++y)
            for (int x = 0; x < s.width; ++x) {
                const std::optional<dvec3> h = hit_sphere(s, x, y);
                if (!covered(fb, x, y) || !h) continue;
                // The mesh is a polygon: its normals are the sphere's to ~0.01.
                const double n_v = glm::dot(*h, glm::normalize(dvec3(s.eye) - *h));
                if (width > 0 && near(n_v, width, 0.02)) continue;
                const bool is_outline = fb.pixel(x, y) == magenta;
                INFO("pixel " << x << ", " << y << ", n.v " << n_v);
                REQUIRE(is_outline == (width > 0 && n_v < width));
                (is_outline ? outline : inside) += 1;
            }
        CHECK(inside > 500);
        if (width > 0) CHECK(outline > 100);
    }
}

TEST_CASE("unlit.so computes vertex colour x base colour x texture", "[shader][unlit]") {
    PluginRegistry registry;
    auto unlit = registry.get("unlit");
    // A 2x2 texture, sampled with nearest filtering at texel centres.
    auto tex = std::make_shared<Texture>();
    tex->width = tex->height = 2;
    tex->texels = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {128, 128, 128, 128}};
    const TextureBinding bindings[1] = {{tex, Filter::nearest, Wrap::clamp}};
    const glm::vec4 base_color(1.0f, 0.5f, 0.25f, 1.0f);
    const glm::vec4 vertex_color(0.5f, 1.0f, 1.0f, 1.0f);
    // A full-screen quad whose UVs run 0..1 across it.
    Mesh quad = make_mesh({{-1, -1, 0.5f}, {1, -1, 0.5f}, {1, 1, 0.5f}, {-1, 1, 0.5f}},
                          {0, 1, 2, 0, 2, 3}, std::vector<glm::vec4>(4, vertex_color));
    quad.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    for (bool textured : {false, true}) {
        const ParamBlock params = test::param_block(
            *unlit, {{"base_color", base_color}, {"base_texture", glm::vec4(textured)}});
        Framebuffer fb(8, 8);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call = clip_space_call(quad, *unlit);
        call.params = params.bytes;
        call.textures = textured ? bindings : nullptr;
        call.texture_count = textured ? 1 : 0;
        FrameStats stats;
        Pipeline().draw(call, fb, stats);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const glm::vec4 texel = textured ? tex->linear((y / 4) * 2 + x / 4) : glm::vec4(1);
                const glm::vec4 expected = vertex_color * base_color * texel;
                REQUIRE(glm::all(glm::equal(fb.pixel(x, y), expected)));
            }
    }
}

// ---- the mirror: a cube map sampled where the shader says ----------------------

namespace {

// Six 32x32 faces, each its own colour under stripes 4 texels wide that
// the mip levels blur away: what a pixel reads shows which face, where on
// it, and at which level.
TextureBinding stripe_cube(Filter filter) {
    auto t = std::make_shared<Texture>();
    t->width = t->height = 32;
    t->faces = 6;
    t->srgb = true;
    const glm::vec3 colour[6] = {{1, 0.3f, 0.2f}, {0.2f, 1, 0.3f}, {0.3f, 0.2f, 1},
                                 {1, 1, 0.2f},    {0.2f, 1, 1},    {1, 0.2f, 1}};
    for (int f = 0; f < 6; ++f)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                const float stripe = ((x / 4 + y / 4) % 2) ? 1.0f : 0.25f;
                t->texels.push_back(encode_texel(glm::vec4(colour[f] * stripe, 1.0f), true));
            }
    generate_mipmaps(*t);
    return {t, filter, Wrap::repeat};
}

// The cube's level l of face f at (u, v), bilinear and clamped, in double.
dvec4 ref_face_level(const Texture& t, int f, int l, dvec2 uv) {
    const int n = l == 0 ? t.width : t.mips[size_t(l - 1)].width;
    const std::vector<Texel8>& texels = l == 0 ? t.texels : t.mips[size_t(l - 1)].texels;
    const auto at = [&](int x, int y) {
        x = std::clamp(x, 0, n - 1), y = std::clamp(y, 0, n - 1);
        return dvec4(decode_texel(texels[size_t(f) * size_t(n * n) + size_t(y * n + x)], true));
    };
    const double x = uv.x * n - 0.5, y = uv.y * n - 0.5;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx),
                    glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

// The cube in direction d at level of detail lod, trilinear, in double;
// nothing where d's two largest components are within `margin` (the face
// could go either way: facet's vertices, snapped to 1/256 pixel, move d a
// little).
std::optional<dvec4> ref_cube(const Texture& t, dvec3 d, double lod, double margin) {
    const dvec3 a = glm::abs(d);
    const double top = std::max({a.x, a.y, a.z});
    const double second = a.x == top ? std::max(a.y, a.z) : a.y == top ? std::max(a.x, a.z)
                                                                       : std::max(a.x, a.y);
    if (top - second < margin) return std::nullopt;
    int f;
    double sc, tc;
    if (a.x == top) f = d.x > 0 ? 0 : 1, sc = d.x > 0 ? -d.z : d.z, tc = -d.y;
    else if (a.y == top) f = d.y > 0 ? 2 : 3, sc = d.x, tc = d.y > 0 ? d.z : -d.z;
    else f = d.z > 0 ? 4 : 5, sc = d.z > 0 ? d.x : -d.x, tc = -d.y;
    const dvec2 uv((sc / top + 1) / 2, (tc / top + 1) / 2);
    const double l = std::clamp(lod, 0.0, double(t.levels() - 1));
    const int lo = int(l);
    const dvec4 a0 = ref_face_level(t, f, lo, uv);
    if (lo + 1 >= t.levels()) return a0;
    return glm::mix(a0, ref_face_level(t, f, lo + 1, uv), l - lo);
}

// Where pixel (x, y)'s ray meets the quad's plane, in the quad's own XY.
dvec2 quad_point(const Setup& s, int x, int y) {
    const Ray r = pixel_ray(s, x, y);
    const glm::dmat4 to_local = glm::inverse(glm::dmat4(s.model));
    const dvec3 o = dvec3(to_local * dvec4(r.origin, 1.0));
    const dvec3 d = dvec3(to_local * dvec4(r.direction, 0.0));
    return dvec2(o) - (o.z / d.z) * dvec2(d);
}

// The reflected direction at pixel (x, y) as mirror.cpp makes it, from the
// varyings of hit h's triangle there (beyond the triangle too, as a quad's
// lanes off it are).
dvec3 ref_reflection(const Setup& s, const Hit& h, int x, int y) {
    const dvec2 q = quad_point(s, x, y);
    Hit at = h;
    const dvec2 a(s.mesh.positions[h.vertex[0]]), b(s.mesh.positions[h.vertex[1]]),
        c(s.mesh.positions[h.vertex[2]]);
    const auto cross = [](dvec2 u, dvec2 v) { return u.x * v.y - u.y * v.x; };
    const double area = cross(b - a, c - a);
    at.weight[1] = cross(q - a, c - a) / area;
    at.weight[2] = cross(b - a, q - a) / area;
    at.weight[0] = 1.0 - at.weight[1] - at.weight[2];
    const dvec3 p = interpolate(at, world_positions(s));
    const dvec3 n = glm::normalize(interpolate(at, world_normals(s)));
    return glm::reflect(glm::normalize(p - dvec3(s.eye)), n);
}

}  // namespace

TEST_CASE("mirror.so reflects its cube map at the level of detail its reflection's "
          "derivatives give, on every path",
          "[shader][mirror][cube][isa]") {
    PluginRegistry registry;
    const auto mirror = registry.get("mirror");
    // Large, the reflection magnified; small, minified down the mip levels.
    for (const int width : {160, 40})
    for (const double blur : {0.0, 1.5})
        for (const Filter filter : {Filter::trilinear, Filter::bilinear}) {
            INFO("width " << width << ", blur " << blur << ", filter " << int(filter));
            Setup s = quad_setup();
            s.width = width, s.height = width * 7 / 10;
            const TextureBinding cube = stripe_cube(filter);
            const Values v = {{"environment", {1.0}}, {"tint", {0.9, 1.0, 0.8}}, {"blur", {blur}}};
            for (const Isa isa : supported_isas()) {
                INFO("path " << isa_name(isa));
                Framebuffer fb(s.width, s.height);
                fb.clear(glm::vec4(0.0f), 0.0f);
                DrawCall call;
                const ParamBlock block = make_block(*mirror, v);
                call.mesh = &s.mesh, call.shader = mirror.get(), call.params = block.bytes;
                call.textures = &cube, call.texture_count = 1;
                call.model = s.model, call.view = s.view, call.projection = s.projection;
                call.camera_position = s.eye, call.state.cull = CullMode::none;
                FrameStats stats;
                Pipeline(1, isa).draw(call, fb, stats);
                const std::vector<uint8_t> px = fb.resolve_srgb8();
                if (std::getenv("MIRROR_PNG")) fb.write_png(std::getenv("MIRROR_PNG"));
                Match m;
                std::set<int> faces;
                int minified = 0;
                for (int y = 0; y < s.height; ++y)
                    for (int x = 0; x < s.width; ++x) {
                        const std::optional<Hit> h = hit_quad(s, x, y);
                        if (!h) continue;
                        // The quad of pixels this one shades with: its top-left,
                        // top-right and bottom-left lanes.
                        const int qx = x & ~1, qy = y & ~1;
                        const dvec3 r = ref_reflection(s, *h, x, y);
                        const dvec3 tl = ref_reflection(s, *h, qx, qy);
                        const dvec3 dx = ref_reflection(s, *h, qx + 1, qy) - tl;
                        const dvec3 dy = ref_reflection(s, *h, qx, qy + 1) - tl;
                        const dvec3 a = glm::abs(r);
                        const double major = std::max({a.x, a.y, a.z}), half = 16.0;
                        const double lod =
                            filter == Filter::trilinear
                                ? 0.5 * std::log2(std::max(glm::dot(dx, dx), glm::dot(dy, dy)) *
                                                  half * half / (major * major)) +
                                      blur
                                : 0.0;
                        // A hundredth of a pixel's turn of r: far more than the snap moves it.
                        const double margin = 0.01 * (glm::length(dx) + glm::length(dy)) + 1e-6;
                        const std::optional<dvec4> c = ref_cube(*cube.texture, r, lod, margin);
                        if (!c) continue;
                        minified += lod - blur > 0.5;
                        faces.insert(a.x == major ? (r.x > 0 ? 0 : 1)
                                                  : a.y == major ? (r.y > 0 ? 2 : 3)
                                                                 : (r.z > 0 ? 4 : 5));
                        const dvec4 want(dvec3(*c) * dvec3(0.9, 1.0, 0.8), 1.0);
                        compare_pixel(&px[4 * (size_t(y) * size_t(s.width) + size_t(x))], want, x,
                                      y, m);
                    }
                CHECK(faces.size() >= 2);  // the reflection crosses a face's edge
                if (filter == Filter::trilinear && width == 40) CHECK(minified > m.sampled / 4);
                require_match(m, width * width / 8);
            }
        }
}

namespace {

// Two in-process shaders over one texture: the host samples `tex` at the UV
// before the call; the shader samples `img` itself, where it wants, with
// the level of detail from the UV's screen derivatives.
struct Presampled {
    static constexpr const char* name = "test_presampled";
    static constexpr const char* version = "test";
    static constexpr uint32_t needs = FACET_NEED_UVS | FACET_NEED_TEXTURES;
    FACET_VARYINGS((sdk::Vec2, uv))
    FACET_PARAMS((texture, tex, "uv", sdk::srgb))
    static Varyings vertex(const sdk::VertexIn& in, const sdk::Draw& d, const Params&,
                           sdk::Vec4& clip) {
        clip = d.model_view_projection() * sdk::Vec4(in.position, 1.0f);
        return {in.uv};
    }
    static sdk::Vec4 fragment(const Varyings&, sdk::Fragment& f, const sdk::Draw&,
                              const Params& p) {
        return f.texture(p.tex);
    }
};

struct SelfSampled {
    static constexpr const char* name = "test_self_sampled";
    static constexpr const char* version = "test";
    static constexpr uint32_t needs = FACET_NEED_UVS | FACET_NEED_TEXTURES | FACET_NEED_DERIVATIVES;
    FACET_VARYINGS((sdk::Vec2, uv))
    FACET_PARAMS((image, img, sdk::srgb))
    static Varyings vertex(const sdk::VertexIn& in, const sdk::Draw& d, const Params&,
                           sdk::Vec4& clip) {
        clip = d.model_view_projection() * sdk::Vec4(in.position, 1.0f);
        return {in.uv};
    }
    static sdk::Vec4 fragment(const Varyings& v, sdk::Fragment& f, const sdk::Draw&,
                              const Params& p) {
        return f.sample(p.img, v.uv);
    }
};

}  // namespace

TEST_CASE("a shader samples a texture where it wants as the host samples it for the shader",
          "[shader][texture][isa]") {
    // Stripes 2 texels wide on a 64x64 texture, repeated 4 times over the
    // quad at a slant: every level of the chain shows.
    auto t = std::make_shared<Texture>();
    t->width = t->height = 64;
    t->srgb = true;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            t->texels.push_back(((x / 2 + y / 4) % 2) ? Texel8{230, 180, 40, 255}
                                                      : Texel8{20, 60, 200, 255});
    generate_mipmaps(*t);
    Setup s = quad_setup();
    for (glm::vec2& uv : s.mesh.uvs) uv *= 4.0f;
    // And the same placed by a transform (`transform:`, KHR_texture_transform):
    // an equal scale, whose level of detail the host shifts exactly for a
    // shader that samples itself.
    UvTransform placed;
    placed.offset = {0.3f, -0.2f};
    placed.rotation = 0.5f;
    placed.scale = {0.35f, 0.35f};
    const auto presampled = test::plugin<Presampled>(), sampled = test::plugin<SelfSampled>();
    const ParamBlock a = make_block(*presampled, {{"tex", {1.0}}});
    const ParamBlock b = make_block(*sampled, {{"img", {1.0}}});
    const auto render = [&](const ShaderPlugin& shader, const ParamBlock& block,
                            const TextureBinding& binding, Isa isa) {
        Framebuffer fb(s.width, s.height);
        fb.clear(glm::vec4(0.0f), 0.0f);
        DrawCall call;
        call.mesh = &s.mesh, call.shader = &shader, call.params = block.bytes;
        call.textures = &binding, call.texture_count = 1;
        call.model = s.model, call.view = s.view, call.projection = s.projection;
        call.state.cull = CullMode::none;
        FrameStats stats;
        Pipeline(1, isa).draw(call, fb, stats);
        return fb;
    };
    // Anisotropic filtering reads the derivatives too: the shader's through
    // the service's sample_grad, turned by the transform as the UVs are.
    Framebuffer plain, trilinear;
    for (const Filter filter : {Filter::trilinear, Filter::anisotropic})
        for (const UvTransform& transform : {UvTransform{}, placed}) {
            const TextureBinding binding{t, filter, Wrap::repeat, transform};
            for (const Isa isa : supported_isas()) {
                INFO("path " << isa_name(isa) << ", filter " << int(filter) << ", transformed "
                             << !transform.identity());
                const Framebuffer host = render(*presampled, a, binding, isa),
                                  own = render(*sampled, b, binding, isa);
                CHECK(max_difference(host, own) <= 1);
                if (transform.identity() && filter == Filter::trilinear) trilinear = host;
                if (transform.identity()) plain = host;
                else CHECK(max_difference(host, plain) > 50);  // the transform shows
                if (filter == Filter::anisotropic && transform.identity())
                    CHECK(max_difference(host, trilinear) > 20);  // sharper at the slant
                // The stripes show, blurred where the levels of detail rise.
                std::set<int> codes;
                for (const uint8_t c : own.resolve_srgb8()) codes.insert(c);
                CHECK(codes.size() > 60);
            }
        }
}
