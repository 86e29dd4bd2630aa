// Scene files: camera, render settings, lights and objects, checked key by
// key. Meshes and materials named twice in one scene are loaded once.
#include "facet/scene.hpp"

#include "facet/error.hpp"
#include "facet/framebuffer.hpp"
#include "facet/memory.hpp"
#include "facet/paths.hpp"
#include "assets/material_yaml.hpp"
#include "assets/scene_clip.hpp"
#include "assets/scene_environment.hpp"
#include "assets/yaml_util.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <unordered_set>

namespace facet {

namespace fs = std::filesystem;

glm::mat4 Camera::view() const { return look_at(position, target, up); }

glm::mat4 Camera::projection(float aspect, bool reversed_z) const {
    if (orthographic) return facet::orthographic(ortho_height, aspect, near, far, reversed_z);
    return perspective(glm::radians(fov_y), aspect, near, far, reversed_z);
}

fs::path default_scene_path() { return data_dir() / "configs" / "default.yaml"; }

Material* Object::material_of(size_t part) const {
    if (part < part_materials.size()) {
        const PartMaterial& p = part_materials[part];
        if (p.from_scene || (!material && p.material)) return p.material.get();
    }
    return material.get();
}

std::vector<Material*> Object::materials() const {
    std::vector<Material*> out;
    std::unordered_set<Material*> seen;
    const size_t parts = mesh ? mesh->part_count() : 1;
    for (size_t i = 0; i < parts; ++i)
        if (Material* m = material_of(i); m && seen.insert(m).second) out.push_back(m);
    return out;
}

std::vector<Material*> Scene::materials() const {
    std::vector<Material*> out;
    std::unordered_set<Material*> seen;
    for (const Object& o : objects)
        for (Material* m : o.materials())
            if (seen.insert(m).second) out.push_back(m);
    return out;
}

namespace {

// Throws Error(code, detail) at `at` unless `ok`.
using yaml::ensure;
using yaml::where;

bool all_at_least(const glm::vec3& v, float lo) { return v.x >= lo && v.y >= lo && v.z >= lo; }

// How far from the origin an object or a light may be: past it, the
// products of a transform (two such numbers) leave float's range. (The
// camera's view is made in double, and may look from farther.)
constexpr float kMaxCoordinate = 1e15f;
bool within_world(const glm::vec3& v) {
    return std::abs(v.x) <= kMaxCoordinate && std::abs(v.y) <= kMaxCoordinate &&
           std::abs(v.z) <= kMaxCoordinate;
}
const std::string kWorldText = "must lie within 1e15 of the origin, where transforms stay in "
                               "float's range";

// ---- camera and render settings ----------------------------------------------

// v scaled to unit length in double precision, where float's squares would
// overflow (1e20) or underflow (1e-30); zero for a zero vector.
glm::vec3 unit(const glm::vec3& v) {
    const glm::dvec3 d(v);
    const double length = glm::length(d);
    return length > 0.0 && std::isfinite(length) ? glm::vec3(d / length) : glm::vec3(0.0f);
}

void check_camera(const yaml::Context& ctx, const YAML::Node& node, const Camera& c) {
    ensure(c.near >= 1e-9f, ctx, where(node, "near"), ErrorCode::out_of_range,
           "near must be at least 1e-9");
    ensure(c.far > c.near && c.far <= kMaxCoordinate, ctx, where(node, "far"),
           ErrorCode::out_of_range, "far must be greater than near and at most 1e15");
    ensure(c.fov_y >= 1e-3f && c.fov_y < 180.0f, ctx, where(node, "fov_y"),
           ErrorCode::out_of_range, "fov_y must be at least 0.001 and below 180 degrees");
    ensure(c.ortho_height >= 1e-9f && c.ortho_height <= kMaxCoordinate, ctx, where(node, "height"),
           ErrorCode::out_of_range, "height must be 1e-9..1e15");
    // In double: a camera 1e20 away is far, not at its target.
    const glm::vec3 forward = unit(glm::vec3(glm::dvec3(c.target) - glm::dvec3(c.position)));
    ensure(forward != glm::vec3(0.0f), ctx, where(node, "target"), ErrorCode::config_invalid,
           "the camera's target must differ from its position");
    ensure(glm::length(glm::cross(forward, unit(c.up))) > 1e-6f, ctx, where(node, "up"),
           ErrorCode::config_invalid, "up is zero or parallel to the view direction");
}

Camera read_camera(const yaml::Context& ctx, const YAML::Node& node) {
    yaml::check_map(ctx, node, "camera", {"position", "target", "up", "projection", "fov_y",
                                          "height", "near", "far", "animate", "frame"});
    Camera c;
    yaml::read(ctx, node, "position", c.position);
    yaml::read(ctx, node, "target", c.target);
    yaml::read(ctx, node, "up", c.up);
    if (const YAML::Node projection = node["projection"])
        c.orthographic =
            yaml::as_enum<bool>(ctx, projection, {{"perspective", false}, {"orthographic", true}});
    yaml::read(ctx, node, "fov_y", c.fov_y);
    yaml::read(ctx, node, "height", c.ortho_height);
    yaml::read(ctx, node, "near", c.near);
    yaml::read(ctx, node, "far", c.far);
    check_camera(ctx, node, c);
    c.up = unit(c.up);  // an up of length 1e-30 is a direction too, and float's squares lose it
    return c;
}

int read_side(const yaml::Context& ctx, const YAML::Node& node) {
    const int side = yaml::as<int>(ctx, node);
    ensure(side >= 1 && side <= Framebuffer::kMaxSize, ctx, node, ErrorCode::out_of_range,
           "each side must be 1.." + std::to_string(Framebuffer::kMaxSize) + " pixels");
    return side;
}

void read_size(const yaml::Context& ctx, const YAML::Node& node, RenderSettings& s) {
    ensure(node.IsSequence() && node.size() == 2, ctx, node, ErrorCode::wrong_type,
           "size must be [width, height]");
    s.width = read_side(ctx, node[0]);
    s.height = read_side(ctx, node[1]);
}

glm::vec4 read_clear_color(const yaml::Context& ctx, const YAML::Node& node) {
    const std::vector<double> n = yaml::as_numbers(ctx, node, 3, 4);
    const glm::vec4 c(n[0], n[1], n[2], n.size() == 4 ? n[3] : 1.0);
    // 65504: the largest a half-float (rgba16f) target holds.
    ensure(all_at_least(glm::vec3(c), 0.0f) && c.r <= 65504.0f && c.g <= 65504.0f &&
               c.b <= 65504.0f && c.a >= 0.0f && c.a <= 1.0f,
           ctx, node, ErrorCode::out_of_range,
           "clear_color must be 0..65504 in red, green and blue and 0..1 in alpha");
    return c;
}

void read_shadow_settings(const yaml::Context& ctx, const YAML::Node& node, RenderSettings& s) {
    yaml::read(ctx, node, "shadow_map_size", s.shadow_map_size);
    ensure(s.shadow_map_size >= 16 && s.shadow_map_size <= 8192, ctx,
           where(node, "shadow_map_size"), ErrorCode::out_of_range,
           "shadow_map_size must be 16..8192");
    yaml::read(ctx, node, "shadow_distance", s.shadow_distance);
    ensure(s.shadow_distance >= 0.0f, ctx, where(node, "shadow_distance"),
           ErrorCode::out_of_range, "shadow_distance must be >= 0 (0: the camera's far plane)");
}

// Reads a `render:` map over `s`: the keys it names replace their values.
void read_render(const yaml::Context& ctx, const YAML::Node& node, RenderSettings& s) {
    yaml::check_map(ctx, node, "render",
                    {"size", "clear_color", "clear_stencil", "depth", "depth_compare", "cull",
                     "front_face",
                     "shadow_map_size", "shadow_distance", "msaa", "subpixel_bits", "wireframe",
                     "shadows", "ao", "ao_resolution", "ao_radius", "ao_samples", "depth_prepass",
                     "color_format", "post"});
    if (const YAML::Node size = node["size"]) read_size(ctx, size, s);
    if (const YAML::Node clear = node["clear_color"]) s.clear_color = read_clear_color(ctx, clear);
    if (const YAML::Node clear = node["clear_stencil"]) {
        const int v = yaml::as<int>(ctx, clear);
        ensure(v >= 0 && v <= 255, ctx, clear, ErrorCode::out_of_range,
               "clear_stencil is 0 to 255 (the stencil buffer has 8 bits)");
        s.clear_stencil = uint8_t(v);
    }
    if (const YAML::Node depth = node["depth"]) {  // and the compare that goes with it
        s.reversed_z = yaml::as_enum<bool>(ctx, depth, {{"reversed", true}, {"standard", false}});
        s.depth_compare = s.reversed_z ? DepthCompare::greater_equal : DepthCompare::less_equal;
    }
    if (const YAML::Node compare = node["depth_compare"])
        s.depth_compare =
            yaml::as_enum<DepthCompare>(ctx, compare,
                                        {{"never", DepthCompare::never},
                                         {"less", DepthCompare::less},
                                         {"less_equal", DepthCompare::less_equal},
                                         {"greater", DepthCompare::greater},
                                         {"greater_equal", DepthCompare::greater_equal},
                                         {"equal", DepthCompare::equal},
                                         {"always", DepthCompare::always}});
    if (const YAML::Node cull = node["cull"])
        s.cull = yaml::as_enum<CullMode>(
            ctx, cull,
            {{"none", CullMode::none}, {"back", CullMode::back}, {"front", CullMode::front}});
    if (const YAML::Node front = node["front_face"])
        s.front_ccw = yaml::as_enum<bool>(ctx, front, {{"ccw", true}, {"cw", false}});
    read_shadow_settings(ctx, node, s);
    yaml::read(ctx, node, "msaa", s.msaa);
    ensure(s.msaa == 1 || s.msaa == 2 || s.msaa == 4 || s.msaa == 8, ctx, where(node, "msaa"),
           ErrorCode::out_of_range, "msaa must be 1, 2, 4 or 8 samples per pixel");
    yaml::read(ctx, node, "subpixel_bits", s.subpixel_bits);
    ensure(s.subpixel_bits >= 1 && s.subpixel_bits <= 8, ctx, where(node, "subpixel_bits"),
           ErrorCode::out_of_range, "subpixel_bits must be 1..8 (D3D10+ and the default: 8)");
    yaml::read(ctx, node, "wireframe", s.wireframe);
    yaml::read(ctx, node, "shadows", s.shadows);
    yaml::read(ctx, node, "ao", s.ao);
    if (const YAML::Node resolution = node["ao_resolution"])
        s.ao_half_resolution =
            yaml::as_enum<bool>(ctx, resolution, {{"full", false}, {"half", true}});
    yaml::read(ctx, node, "ao_radius", s.ao_radius);
    ensure(s.ao_radius > 0.0f && s.ao_radius <= 1000.0f, ctx, where(node, "ao_radius"),
           ErrorCode::out_of_range, "ao_radius must be > 0 and <= 1000 (world units)");
    yaml::read(ctx, node, "ao_samples", s.ao_samples);
    ensure(s.ao_samples >= 1 && s.ao_samples <= 256, ctx, where(node, "ao_samples"),
           ErrorCode::out_of_range, "ao_samples must be 1..256 (directions per texel)");
    yaml::read(ctx, node, "depth_prepass", s.depth_prepass);
    yaml::read(ctx, node, "post", s.post);
    if (const YAML::Node format = node["color_format"])
        s.color_format = yaml::as_enum<ColorFormat>(ctx, format,
                                                    {{"srgb8", ColorFormat::srgb8},
                                                     {"rgba16f", ColorFormat::rgba16f},
                                                     {"rgba32f", ColorFormat::rgba32f}});
}

// ---- lights --------------------------------------------------------------------

void check_light(const yaml::Context& ctx, const YAML::Node& node, const Light& l) {
    ensure(all_at_least(l.color, 0.0f), ctx, where(node, "color"), ErrorCode::out_of_range,
           "color components must be >= 0");
    ensure(l.intensity >= 0.0f, ctx, where(node, "intensity"), ErrorCode::out_of_range,
           "intensity must be >= 0");
    // Lighting multiplies it by albedos, exposures and 1 / attenuation:
    // beyond this they overflow, and inf x 0 is NaN.
    ensure(std::max({l.color.r, l.color.g, l.color.b}) * l.intensity <= 1e9f, ctx,
           where(node, "intensity"), ErrorCode::out_of_range,
           "color x intensity must be at most 1e9");
    ensure(within_world(l.position), ctx, where(node, "position"), ErrorCode::out_of_range,
           "a light's position " + kWorldText);
    ensure(l.range >= 0.0f, ctx, where(node, "range"), ErrorCode::out_of_range,
           "range must be >= 0 (0: unlimited)");
    const glm::vec3 a = l.attenuation;
    ensure(all_at_least(a, 0.0f) && std::max({a.x, a.y, a.z}) > 0.0f &&
               std::max({a.x, a.y, a.z}) <= 1e6f && (a.x == 0.0f || a.x >= 1e-6f),
           ctx, where(node, "attenuation"), ErrorCode::out_of_range,
           "attenuation [constant, linear, quadratic] must be 0..1e6, not all 0, and a constant "
           "term below 1e-6 is 0 (it would make the light a million times brighter)");
    ensure(l.spot_inner >= 0.0f && l.spot_inner <= l.spot_outer && l.spot_outer <= 90.0f, ctx,
           where(node, "spot_inner"), ErrorCode::out_of_range,
           "spot angles are half-angles in degrees with 0 <= spot_inner <= spot_outer <= 90");
    ensure(l.type != LightType::spot || l.spot_outer >= 0.1f, ctx, where(node, "spot_outer"),
           ErrorCode::out_of_range, "a spot light's spot_outer must be at least 0.1 degrees");
    ensure(l.shadow_map_size == 0 || (l.shadow_map_size >= 16 && l.shadow_map_size <= 8192), ctx,
           where(node, "shadow_map_size"), ErrorCode::out_of_range,
           "a light's shadow_map_size must be 16..8192 (or 0: the scene's)");
}

Light read_light(const yaml::Context& ctx, const YAML::Node& node) {
    yaml::check_map(ctx, node, "light",
                    {"name", "type", "position", "direction", "color", "intensity", "range",
                     "attenuation", "spot_inner", "spot_outer", "casts_shadow", "shadow_map_size"});
    Light l;
    yaml::read(ctx, node, "name", l.name);
    if (const YAML::Node type = node["type"])
        l.type = yaml::as_enum<LightType>(ctx, type,
                                          {{"directional", LightType::directional},
                                           {"point", LightType::point},
                                           {"spot", LightType::spot}});
    yaml::read(ctx, node, "position", l.position);
    yaml::read(ctx, node, "direction", l.direction);
    l.direction = unit(l.direction);
    ensure(l.direction != glm::vec3(0.0f), ctx, where(node, "direction"),
           ErrorCode::config_invalid, "direction must not be zero");
    yaml::read(ctx, node, "color", l.color);
    yaml::read(ctx, node, "intensity", l.intensity);
    yaml::read(ctx, node, "range", l.range);
    yaml::read(ctx, node, "attenuation", l.attenuation);
    yaml::read(ctx, node, "spot_inner", l.spot_inner);
    yaml::read(ctx, node, "spot_outer", l.spot_outer);
    yaml::read(ctx, node, "casts_shadow", l.casts_shadow);
    yaml::read(ctx, node, "shadow_map_size", l.shadow_map_size);
    check_light(ctx, node, l);
    return l;
}

// ---- objects -------------------------------------------------------------------

glm::quat read_rotation(const yaml::Context& ctx, const YAML::Node& node) {
    if (!node.IsMap()) return euler_degrees(yaml::as<glm::vec3>(ctx, node));
    yaml::check_map(ctx, node, "rotation", {"axis", "angle"});
    const glm::vec3 axis = yaml::as<glm::vec3>(ctx, yaml::require(ctx, node, "axis"));
    const float angle = yaml::as<float>(ctx, yaml::require(ctx, node, "angle"));
    ensure(unit(axis) != glm::vec3(0.0f), ctx, node["axis"], ErrorCode::config_invalid,
           "the rotation axis must not be zero");
    return glm::angleAxis(glm::radians(angle), unit(axis));
}

glm::vec3 read_scale(const yaml::Context& ctx, const YAML::Node& node) {
    const glm::vec3 s =
        node.IsSequence() ? yaml::as<glm::vec3>(ctx, node) : glm::vec3(yaml::as<float>(ctx, node));
    ensure(s.x != 0.0f && s.y != 0.0f && s.z != 0.0f, ctx, node, ErrorCode::out_of_range,
           "scale must not be zero");
    // Subnormal factors (below 1.2e-38) flatten every triangle to nothing.
    ensure(std::isnormal(s.x) && std::isnormal(s.y) && std::isnormal(s.z), ctx, node,
           ErrorCode::out_of_range, "scale is below float's normal range (1.2e-38)");
    ensure(std::max({std::abs(s.x), std::abs(s.y), std::abs(s.z)}) <= 1e9f, ctx, node,
           ErrorCode::out_of_range, "scale must be at most 1e9");
    return s;
}

// ---- animation -----------------------------------------------------------------

// Times beyond this are mistakes (31 years), and keep k * fps within a long.
constexpr double kMaxSeconds = 1e9;

// A track: {keys: [{time: T, value: V}, ...], interpolation: linear | step},
// each value read by `value`; times finite, >= 0, strictly increasing.
template <class T, class Read>
Track<T> read_track(const yaml::Context& ctx, const YAML::Node& node, const std::string& what,
                    Read value) {
    yaml::check_map(ctx, node, what, {"keys", "interpolation"});
    Track<T> track;
    if (const YAML::Node i = node["interpolation"])
        track.interpolation = yaml::as_enum<Interpolation>(
            ctx, i, {{"linear", Interpolation::linear}, {"step", Interpolation::step}});
    const YAML::Node keys = yaml::require(ctx, node, "keys");
    yaml::check_sequence(ctx, keys, what + " keys");
    ensure(keys.size() > 0, ctx, keys, ErrorCode::config_invalid, "a track needs a key");
    for (const YAML::Node& key : keys) {
        yaml::check_map(ctx, key, "key", {"time", "value"});
        const YAML::Node time = yaml::require(ctx, key, "time");
        const double t = yaml::as<double>(ctx, time);
        ensure(t >= 0.0 && t <= kMaxSeconds, ctx, time, ErrorCode::out_of_range,
               "a key's time must be 0..1e9 seconds");
        ensure(track.times.empty() || t > track.times.back(), ctx, time,
               ErrorCode::config_invalid, "keys must be in order of time, each later than the "
                                          "one before");
        track.times.push_back(t);
        track.values.push_back(value(yaml::require(ctx, key, "value")));
    }
    return track;
}

// Degrees a second: a finite number, not zero.
// A spin's degrees a second: not 0, and within what frames can show. Past
// a turn a microsecond, every frame's angle is noise; below a turn in 28
// years, the animation would never end (animation_end: one turn).
double read_speed(const yaml::Context& ctx, const YAML::Node& node) {
    const float speed = yaml::as<float>(ctx, node);
    ensure(speed != 0.0f, ctx, node, ErrorCode::out_of_range,
           "a speed of 0 degrees a second does not move; leave the key out");
    ensure(std::abs(speed) <= 3.6e8f, ctx, node, ErrorCode::out_of_range,
           "a speed of " + node.Scalar() +
               " degrees a second turns more than a million times a second, faster than any "
               "frame can show (at most 3.6e8)");
    ensure(std::abs(speed) >= 4e-7f, ctx, node, ErrorCode::out_of_range,
           "a speed of " + node.Scalar() +
               " degrees a second takes more than 28 years a turn (at least 4e-7)");
    return speed;
}

TransformTracks read_transform_tracks(const yaml::Context& ctx, const YAML::Node& node) {
    yaml::check_map(ctx, node, "animate",
                    {"position", "rotation", "scale", "spin", "clip", "weights"});
    TransformTracks a;
    if (const YAML::Node n = node["position"])
        a.position = read_track<glm::vec3>(ctx, n, "position",
                                           [&](const YAML::Node& v) { return yaml::as<glm::vec3>(ctx, v); });
    if (const YAML::Node n = node["rotation"])
        a.rotation = read_track<glm::quat>(ctx, n, "rotation",
                                           [&](const YAML::Node& v) { return read_rotation(ctx, v); });
    if (const YAML::Node n = node["scale"])
        a.scale = read_track<glm::vec3>(ctx, n, "scale",
                                        [&](const YAML::Node& v) { return read_scale(ctx, v); });
    if (const YAML::Node spin = node["spin"]) {
        if (spin.IsMap()) {
            yaml::check_map(ctx, spin, "spin", {"axis", "speed"});
            a.spin = read_speed(ctx, yaml::require(ctx, spin, "speed"));
            if (const YAML::Node axis = spin["axis"]) {
                a.spin_axis = unit(yaml::as<glm::vec3>(ctx, axis));
                ensure(a.spin_axis != glm::vec3(0.0f), ctx, axis, ErrorCode::config_invalid,
                       "the spin axis must not be zero");
            }
        } else {
            a.spin = read_speed(ctx, spin);
        }
    }
    return a;
}

CameraTracks read_camera_tracks(const yaml::Context& ctx, const YAML::Node& node) {
    yaml::check_map(ctx, node, "animate", {"position", "target", "fov_y", "orbit"});
    CameraTracks a;
    const auto vec3 = [&](const YAML::Node& v) { return yaml::as<glm::vec3>(ctx, v); };
    if (const YAML::Node n = node["position"]) a.position = read_track<glm::vec3>(ctx, n, "position", vec3);
    if (const YAML::Node n = node["target"]) a.target = read_track<glm::vec3>(ctx, n, "target", vec3);
    if (const YAML::Node n = node["fov_y"])
        a.fov_y = read_track<float>(ctx, n, "fov_y", [&](const YAML::Node& v) {
            const float fov = yaml::as<float>(ctx, v);
            ensure(fov > 0.0f && fov < 180.0f, ctx, v, ErrorCode::out_of_range,
                   "fov_y must be between 0 and 180 degrees");
            return fov;
        });
    if (const YAML::Node orbit = node["orbit"]) a.orbit = read_speed(ctx, orbit);
    return a;
}

// The camera posed at each key of its tracks, and at 16 times between each
// two, is a camera: its target is not its position, and up is not along the
// view.
void check_camera_tracks(const yaml::Context& ctx, const YAML::Node& node, const Camera& rest,
                         const CameraTracks& tracks) {
    std::vector<double> keys = tracks.position.times;
    keys.insert(keys.end(), tracks.target.times.begin(), tracks.target.times.end());
    std::sort(keys.begin(), keys.end());
    std::vector<double> times = keys;
    for (size_t i = 1; i < keys.size(); ++i)
        for (int k = 1; k < 16; ++k) times.push_back(keys[i - 1] + (keys[i] - keys[i - 1]) * k / 16.0);
    for (double t : times) {
        const Camera c = tracks.at(t, rest);
        const glm::vec3 forward = unit(glm::vec3(glm::dvec3(c.target) - glm::dvec3(c.position)));
        ensure(forward != glm::vec3(0.0f) && glm::length(glm::cross(forward, c.up)) > 1e-6f, ctx,
               node, ErrorCode::config_invalid,
               fmt::format("at {:g} s the camera's target is at its position, or up lies along "
                           "its view", t));
    }
}

Timeline read_timeline(const yaml::Context& ctx, const YAML::Node& node, double end) {
    yaml::check_map(ctx, node, "animation", {"fps", "start", "end", "clip"});
    Timeline t;
    t.end = end;
    if (const YAML::Node fps = node["fps"]) {
        t.fps = yaml::as<double>(ctx, fps);
        ensure(t.fps >= 1e-3 && t.fps <= 1000.0, ctx, fps, ErrorCode::out_of_range,
               "fps must be 0.001..1000");
    }
    if (const YAML::Node start = node["start"]) {
        t.start = yaml::as<double>(ctx, start);
        ensure(t.start >= 0.0 && t.start <= kMaxSeconds, ctx, start, ErrorCode::out_of_range,
               "start must be 0..1e9 seconds");
    }
    if (const YAML::Node e = node["end"]) {
        t.end = yaml::as<double>(ctx, e);
        ensure(t.end > t.start && t.end <= kMaxSeconds, ctx, e, ErrorCode::out_of_range,
               "end must be after start, and at most 1e9 seconds");
    } else {
        ensure(end > t.start || end == 0.0, ctx, where(node, "start"), ErrorCode::out_of_range,
               fmt::format("start is at or after the animation's end ({:g} s); give an end",
                           end));
    }
    return t;
}

std::string cache_key(const fs::path& file) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(file, ec);
    return ec ? file.string() : canonical.string();
}

// load(), with its errors (from another file) reported at `value` in this one.
template <class Load>
auto relocate_errors(const yaml::Context& ctx, const YAML::Node& value, Load load) {
    try {
        return load();
    } catch (const Error& e) {
        throw yaml::relocated(e, ctx, value);
    }
}

// What one load_scene() shares between objects.
class Loader {
public:
    Loader(const fs::path& path, PluginRegistry& registry)
        : ctx{path.string()}, folder_(path.parent_path()), registry_(registry) {}

    const yaml::Context ctx;

    fs::path resolve(const YAML::Node& value) const {
        return (folder_ / yaml::as<std::string>(ctx, value)).lexically_normal();
    }

    std::shared_ptr<const Mesh> mesh(const YAML::Node& value) {
        const fs::path file = resolve(value);
        std::shared_ptr<const Mesh>& slot = meshes_[cache_key(file)];
        if (!slot) slot = relocate_errors(ctx, value, [&] { return load_mesh(file); });
        return slot;
    }

    // A material file (shared), or an inline map (errors already in this file).
    std::shared_ptr<Material> material(const YAML::Node& value) {
        if (value.IsMap())
            return material_from_yaml(ctx, value, folder_,
                                      ctx.file + ":" + std::to_string(yaml::line(value)), registry_,
                                      textures_);
        const fs::path file = resolve(value);
        std::shared_ptr<Material>& slot = materials_[cache_key(file)];
        if (!slot)
            slot = relocate_errors(ctx, value,
                                   [&] { return load_material(file, registry_, textures_); });
        return slot;
    }

    // The file's material `index` of `mesh`, bound; shared by every object
    // drawing `mesh`. Errors name the mesh file and the material.
    std::shared_ptr<Material> imported(const Mesh& mesh, int index) {
        std::shared_ptr<Material>& slot = imported_[{mesh.source, index}];
        if (!slot) {
            const ImportedMaterial& im = mesh.materials[size_t(index)];
            const std::string source = mesh.source + ": material '" + im.name + "'";
            if (!im.problem.empty())
                throw Error(ErrorCode::config_invalid, im.problem, source);
            // Its embedded images, by the names the material gives them.
            if (images_added_.insert(mesh.source).second)
                for (size_t i = 0; i < mesh.images.size(); ++i)
                    if (mesh.images[i])
                        textures_.add_encoded(mesh.source + "#" + std::to_string(i),
                                              mesh.images[i]);
            slot = imported_material(im, source, fs::path(mesh.source).parent_path(), registry_,
                                     textures_);
            std::string notes = im.notes;
            for (size_t end; (end = notes.find('\n')) != std::string::npos; notes.erase(0, end + 1))
                spdlog::warn("{}: {}", source, notes.substr(0, end));
        }
        return slot;
    }

    void add_plugin_path(const YAML::Node& value, Scene& scene) {
        const fs::path folder = fs::absolute(resolve(value)).lexically_normal();
        std::error_code ec;
        ensure(fs::is_directory(folder, ec), ctx, value, ErrorCode::file_not_found,
               "plugin folder " + folder.string());
        registry_.add_scene_path(folder);
        scene.plugin_paths.push_back(folder);
    }

    // A screen pass of the post chain: {pass: NAME, param: value, ...}.
    PostPass post_pass(const YAML::Node& node) {
        yaml::check_map(ctx, node, "post pass");
        PostPass p;
        const YAML::Node name = yaml::require(ctx, node, "pass");
        p.name = yaml::as<std::string>(ctx, name);
        p.file = ctx.file;
        p.line = yaml::line(node);
        for (const auto& entry : node)
            if (entry.first.Scalar() != "pass")
                p.params.push_back(parse_param(ctx, entry.first.Scalar(), entry.second, folder_));
        p.plugin = relocate_errors(ctx, name, [&] { return registry_.get(p.name); });
        ensure(p.plugin->is_post(), ctx, name, ErrorCode::wrong_type,
               "'" + p.name + "' is a shader, not a screen pass: a material names it");
        p.block = bind_params(p.params, *p.plugin, p.file, textures_).block;
        return p;
    }

    // Material files loaded so far, by canonical path.
    const std::map<std::string, std::shared_ptr<Material>>& materials() const { return materials_; }

private:
    fs::path folder_;
    PluginRegistry& registry_;
    TextureCache textures_;
    std::map<std::string, std::shared_ptr<const Mesh>> meshes_;
    std::map<std::string, std::shared_ptr<Material>> materials_;
    std::map<std::pair<std::string, int>, std::shared_ptr<Material>> imported_;
    std::set<std::string> images_added_;  // meshes whose embedded images textures_ knows
};

// Whether any triangle of `mesh`, moved to world space by `model` in float
// as the pipeline does, has a finite, non-zero normal. Stops at the first.
bool any_triangle_survives(const Mesh& mesh, const glm::mat4& model) {
    const auto world = [&](uint32_t i) {
        return glm::vec3(model * glm::vec4(mesh.positions[i], 1.0f));
    };
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const glm::vec3 a = world(mesh.indices[t]);
        const glm::vec3 n =
            glm::cross(world(mesh.indices[t + 1]) - a, world(mesh.indices[t + 2]) - a);
        const bool finite = std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z);
        if (finite && n != glm::vec3(0.0f)) return true;
    }
    return false;
}

std::string quoted_list(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "'" : ", '") + n + "'";
    return out.empty() ? "none" : out;
}

// The scene's `materials:` map: each key names a part of the mesh, or a
// material of its file (then every part drawn with it).
void read_part_materials(Loader& loader, const YAML::Node& map, Object& o) {
    const yaml::Context& ctx = loader.ctx;
    yaml::check_map(ctx, map, "materials");
    const Mesh& mesh = *o.mesh;
    for (const auto& entry : map) {
        if (!entry.first.IsScalar() || entry.first.Scalar().empty())
            throw yaml::error(ctx, entry.first, ErrorCode::wrong_type,
                              "a key of materials: is the name of a part or of a material of "
                              "the mesh file");
        const std::string key = entry.first.Scalar();
        std::vector<size_t> parts;
        if (const int p = mesh.find_part(key); p >= 0) {
            parts.push_back(size_t(p));
        } else {
            for (size_t i = 0; i < mesh.parts.size(); ++i) {
                const int m = mesh.parts[i].material;
                if (m >= 0 && mesh.materials[size_t(m)].name == key) parts.push_back(i);
            }
        }
        if (parts.empty()) {
            std::vector<std::string> part_names, material_names;
            for (const MeshPart& p : mesh.parts) part_names.push_back(p.name);
            for (const ImportedMaterial& m : mesh.materials) material_names.push_back(m.name);
            throw yaml::error(ctx, entry.first, ErrorCode::config_invalid,
                              "'" + key + "' names no part and no material of " + mesh.source +
                                  "; its parts: " + quoted_list(part_names) +
                                  "; its materials: " + quoted_list(material_names));
        }
        const std::shared_ptr<Material> material = loader.material(entry.second);
        for (size_t i : parts) o.part_materials[i] = {material, true};
    }
}

// A part's material when neither its file nor the scene gives one.
constexpr const char* kDefaultMaterial =
    "{shader: phong, params: {diffuse: [0.7, 0.7, 0.7], specular: [0.2, 0.2, 0.2], shininess: 32}}";

// Each part's material: the scene's for it, or else (without a material
// for the whole object) the file's. Every part must end with one.
void resolve_materials(Loader& loader, const YAML::Node& node, Object& o) {
    const yaml::Context& ctx = loader.ctx;
    const Mesh& mesh = *o.mesh;
    o.part_materials.assign(mesh.part_count(), {});
    if (const YAML::Node material = node["material"]) o.material = loader.material(material);
    if (const YAML::Node map = node["materials"]) read_part_materials(loader, map, o);
    std::shared_ptr<Material> grey;  // one for the parts that have none
    for (size_t i = 0; i < mesh.part_count(); ++i) {
        PartMaterial& p = o.part_materials[i];
        if (p.from_scene || o.material) continue;
        const int imported = i < mesh.parts.size() ? mesh.parts[i].material : -1;
        if (imported < 0) {
            spdlog::warn("{}:{}:{}: object '{}': part '{}' of {} has no material in its file; it "
                         "is drawn grey (name one with material: for the whole object, or "
                         "materials: per part)",
                         ctx.file, yaml::line(node), yaml::column(node), o.name, mesh.part(i).name,
                         mesh.source);
            if (!grey) grey = loader.material(YAML::Load(kDefaultMaterial));
            p.material = grey;
            continue;
        }
        p.material = relocate_errors(ctx, yaml::require(ctx, node, "mesh"),
                                     [&] { return loader.imported(mesh, imported); });
    }
}

// `scene_clip`: the scene's `animation: {clip}`, or a null node.
Object read_object(Loader& loader, const YAML::Node& node, size_t index,
                   const YAML::Node& scene_clip) {
    const yaml::Context& ctx = loader.ctx;
    yaml::check_map(ctx, node, "object",
                    {"name", "mesh", "material", "materials", "position", "rotation", "scale",
                     "visible", "animate"});
    Object o;
    o.name = "object " + std::to_string(index);
    yaml::read(ctx, node, "name", o.name);
    o.mesh = loader.mesh(yaml::require(ctx, node, "mesh"));
    resolve_materials(loader, node, o);
    yaml::read(ctx, node, "position", o.transform.translation);
    ensure(within_world(o.transform.translation), ctx, where(node, "position"),
           ErrorCode::out_of_range, "an object's position " + kWorldText);
    if (const YAML::Node rotation = node["rotation"])
        o.transform.rotation = read_rotation(ctx, rotation);
    if (const YAML::Node scale = node["scale"]) o.transform.scale = read_scale(ctx, scale);
    yaml::read(ctx, node, "visible", o.visible);
    o.rest = o.transform;
    const YAML::Node animate = node["animate"];
    if (animate) o.animation = read_transform_tracks(ctx, animate);
    o.clip = choose_clip(ctx, animate, scene_clip, *o.mesh);
    if (animate && animate["weights"]) o.weights = read_weights(ctx, animate["weights"], *o.mesh);
    if (o.mesh->triangle_count() > 0 && !any_triangle_survives(*o.mesh, o.transform.matrix()))
        spdlog::warn("{}:{}:{}: object '{}': none of its {} triangles survives its transform "
                     "(each is degenerate or overflows a float in world space); check its scale",
                     ctx.file, yaml::line(node), yaml::column(node), o.name,
                     o.mesh->triangle_count());
    return o;
}

// Calls `read` on each item of the sequence map[key], if present.
template <class Read>
void for_each_item(const yaml::Context& ctx, const YAML::Node& map, const std::string& key,
                   Read read) {
    const YAML::Node items = map[key];
    if (!items) return;
    yaml::check_sequence(ctx, items, key);
    for (size_t i = 0; i < items.size(); ++i) read(items[i], i);
}

// The camera's tracks and the time line; poses the scene at its start.
void read_animation(const yaml::Context& ctx, const YAML::Node& root, Scene& scene) {
    scene.camera_rest = scene.camera;
    if (const YAML::Node camera = root["camera"]; camera && camera["animate"]) {
        scene.camera_tracks = read_camera_tracks(ctx, camera["animate"]);
        check_camera_tracks(ctx, camera["animate"], scene.camera, scene.camera_tracks);
    }
    double end = scene.camera_tracks.end();
    for (const Object& o : scene.objects) {
        end = std::max(end, o.animation.end());
        if (o.mesh) end = std::max(end, animation_end(*o.mesh, o.clip));
    }
    end = std::min(end, kMaxSeconds);  // a spin of 1e-20 degrees a second ends, in practice
    scene.timeline.end = end;
    if (const YAML::Node animation = root["animation"])
        scene.timeline = read_timeline(ctx, animation, end);
    scene.pose(scene.timeline.start);
}

}  // namespace

void require_frame_within_budget(const RenderSettings& s) {
    const uint64_t bytes = Framebuffer::frame_bytes(s.width, s.height, s.color_format, s.msaa);
    const std::string samples = s.msaa > 1 ? " with " + std::to_string(s.msaa) + " samples" : "";
    require_within_budget(bytes, "a " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                                     " frame" + samples);
}

namespace {

// `camera: {frame: NAME}`: the camera framed on the object of that name.
void frame_named(const yaml::Context& ctx, const YAML::Node& node, Scene& scene) {
    const std::string name = yaml::as<std::string>(ctx, node);
    for (size_t i = 0; i < scene.objects.size(); ++i)
        if (scene.objects[i].name == name) return frame_object(scene, i);
    std::vector<std::string> names;
    for (const Object& o : scene.objects) names.push_back(o.name);
    throw yaml::error(ctx, node, ErrorCode::config_invalid,
                      "'" + name + "' names no object; the objects: " + quoted_list(names));
}

// The scene `root` holds, read as from `path` (its folder resolves the
// files it names, and errors name it).
Scene scene_from(const YAML::Node& root, const fs::path& path, PluginRegistry& registry) {
    Loader loader(path, registry);
    const yaml::Context& ctx = loader.ctx;
    yaml::check_map(ctx, root, "scene",
                    {"camera", "render", "plugin_paths", "lights", "objects", "post", "animation",
                     "environment"});
    Scene scene;
    scene.source = path;
    if (const YAML::Node camera = root["camera"]) scene.camera = read_camera(ctx, camera);
    if (const YAML::Node render = root["render"]) read_render(ctx, render, scene.settings);
    // Plugin folders first: the materials below may need them.
    for_each_item(ctx, root, "plugin_paths",
                  [&](const YAML::Node& item, size_t) { loader.add_plugin_path(item, scene); });
    for_each_item(ctx, root, "lights", [&](const YAML::Node& item, size_t) {
        scene.lights.push_back(read_light(ctx, item));
    });
    const YAML::Node animation = root["animation"];
    const YAML::Node scene_clip = animation && animation.IsMap()
                                      ? animation["clip"]
                                      : YAML::Node(YAML::NodeType::Undefined);
    for_each_item(ctx, root, "objects", [&](const YAML::Node& item, size_t i) {
        scene.objects.push_back(read_object(loader, item, i, scene_clip));
    });
    for_each_item(ctx, root, "post", [&](const YAML::Node& item, size_t) {
        scene.post.push_back(loader.post_pass(item));
    });
    if (const YAML::Node environment = root["environment"])
        scene.environment = read_environment(ctx, environment, path.parent_path());
    for (const auto& [file, material] : loader.materials()) scene.material_files[file] = material;
    read_animation(ctx, root, scene);
    if (const YAML::Node camera = root["camera"]; camera && camera["frame"])
        frame_named(ctx, camera["frame"], scene);
    spdlog::info("scene {}: {} objects, {} lights, {}x{}", ctx.file, scene.objects.size(),
                 scene.lights.size(), scene.settings.width, scene.settings.height);
    return scene;
}

}  // namespace

Scene load_scene(const fs::path& path, PluginRegistry& registry) {
    if (is_model_file(path)) return load_model_scene(path, registry);
    return scene_from(yaml::load_file(path), path, registry);
}

Scene load_scene_text(const std::string& yaml, const fs::path& origin, PluginRegistry& registry) {
    return scene_from(yaml::load_text(yaml, origin.string()), origin, registry);
}

void apply_render_settings(RenderSettings& settings, const std::string& yaml,
                           const std::string& origin) {
    const yaml::Context ctx{origin};
    YAML::Node node;
    try {
        node = YAML::Load(yaml);
    } catch (const YAML::ParserException& e) {
        throw Error(ErrorCode::yaml_syntax, e.msg, origin, e.mark.line + 1, e.mark.column + 1);
    }
    RenderSettings s = settings;  // unchanged when the map is bad
    read_render(ctx, node, s);
    settings = s;
}

}  // namespace facet
