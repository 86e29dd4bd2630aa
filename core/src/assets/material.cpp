// Materials: parsing parameter values as written, and binding them to a
// shader's schema (type and range checks, parameter block, textures).
#include "facet/material.hpp"

#include "facet/error.hpp"
#include "assets/material_yaml.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace facet {

namespace {

// ---- parsing -----------------------------------------------------------------

// A 2D texture's `transform: {offset: [u, v], rotation: radians, scale:
// [u, v]}` (UvTransform), each part optional; within 1e6 of the UVs' own
// scale, past which float UVs have no precision left to place a texel.
UvTransform parse_uv_transform(const yaml::Context& ctx, const YAML::Node& node) {
    yaml::check_map(ctx, node, "a texture's transform", {"offset", "rotation", "scale"});
    UvTransform t;
    const auto within = [&](const YAML::Node& at, float v, const char* what) {
        yaml::ensure(std::abs(v) <= 1e6f, ctx, at, ErrorCode::out_of_range,
                     std::string(what) + " " + at.Scalar() + " is past 1e6");
        return v;
    };
    for (const char* key : {"offset", "scale"}) {
        const YAML::Node pair = node[key];
        if (!pair) continue;
        const glm::vec2 v = yaml::as<glm::vec2>(ctx, pair);
        const YAML::Node u = pair[0], w = pair[1];  // named: a temporary's Scalar() outlived it
        const glm::vec2 checked(within(u, v.x, key), within(w, v.y, key));
        (key[0] == 'o' ? t.offset : t.scale) = checked;
    }
    if (const YAML::Node r = node["rotation"]) t.rotation = within(r, yaml::as<float>(ctx, r), "rotation");
    return t;
}

// {file: ...} or, for a cube map, {faces: [six files]}; filter, wrap, and
// a 2D texture's transform and UV set.
void parse_texture_map(const yaml::Context& ctx, const YAML::Node& node, MaterialParam& p) {
    yaml::check_map(ctx, node, "texture",
                    {"file", "faces", "filter", "anisotropy", "wrap", "transform", "uv_set"});
    if (const YAML::Node set = node["uv_set"]) {
        p.uv_set = yaml::as<int>(ctx, set);
        yaml::ensure(p.uv_set == 0 || p.uv_set == 1, ctx, set, ErrorCode::out_of_range,
                     "uv_set is 0 (the first set of texture coordinates) or 1 (the second)");
    }
    if (const YAML::Node transform = node["transform"]) {
        if (node["faces"])
            throw yaml::error(ctx, transform, ErrorCode::config_invalid,
                              "a cube map is read by direction: it has no UVs to transform");
        p.transform = parse_uv_transform(ctx, transform);
    }
    if (const YAML::Node faces = node["faces"]) {
        if (node["file"])
            throw yaml::error(ctx, node, ErrorCode::config_invalid,
                              "a texture is a file or a cube map's faces, not both");
        if (!faces.IsSequence() || faces.size() != 6)
            throw yaml::error(ctx, faces, ErrorCode::wrong_type,
                              "faces: six files, +X, -X, +Y, -Y, +Z, -Z");
        for (const YAML::Node& f : faces) p.cube_faces.emplace_back(yaml::as<std::string>(ctx, f));
    } else {
        p.texture_file = yaml::as<std::string>(ctx, yaml::require(ctx, node, "file"));
    }
    if (const YAML::Node filter = node["filter"])
        p.filter = yaml::as_enum<Filter>(ctx, filter,
                                         {{"nearest", Filter::nearest},
                                          {"bilinear", Filter::bilinear},
                                          {"trilinear", Filter::trilinear},
                                          {"anisotropic", Filter::anisotropic}});
    if (const YAML::Node most = node["anisotropy"]) {
        yaml::ensure(p.filter == Filter::anisotropic, ctx, most, ErrorCode::config_invalid,
                     "anisotropy is the most samples of 'filter: anisotropic', which this "
                     "texture does not use");
        p.anisotropy = yaml::as<int>(ctx, most);
        yaml::ensure(p.anisotropy >= 2 && p.anisotropy <= kMaxAnisotropy, ctx, most,
                     ErrorCode::out_of_range, "anisotropy is 2 to 16 samples a pixel");
    }
    if (const YAML::Node wrap = node["wrap"])
        p.wrap = yaml::as_enum<Wrap>(
            ctx, wrap,
            {{"repeat", Wrap::repeat}, {"clamp", Wrap::clamp}, {"mirror", Wrap::mirror}});
}

}  // namespace

MaterialParam parse_param(const yaml::Context& ctx, const std::string& name,
                          const YAML::Node& value, const std::filesystem::path& folder) {
    MaterialParam p;
    p.name = name;
    p.line = yaml::line(value);
    p.column = yaml::column(value);
    if (value.IsMap()) {
        p.kind = MaterialParam::Kind::texture;
        parse_texture_map(ctx, value, p);
    } else if (value.IsSequence()) {
        p.kind = MaterialParam::Kind::vector;
        p.numbers = yaml::as_numbers(ctx, value, 1, 4);
    } else if (const std::optional<double> number = yaml::parse_number(value)) {
        p.numbers = {*number};
        p.is_integer = yaml::is_integer_text(value.Scalar());
    } else if (const std::optional<bool> flag = yaml::parse_bool(value)) {
        p.kind = MaterialParam::Kind::boolean;
        p.flag = *flag;
    } else if (value.IsScalar() && !value.Scalar().empty()) {
        p.kind = MaterialParam::Kind::word;
        p.word = value.Scalar();
        p.texture_file = p.word;
    } else {
        throw yaml::error(ctx, value, ErrorCode::wrong_type,
                          "'" + name + "' needs a number, true/false, 1 to 4 numbers, a name or "
                          "a texture");
    }
    if (!p.texture_file.empty()) p.texture_file = (folder / p.texture_file).lexically_normal();
    for (std::filesystem::path& f : p.cube_faces) f = (folder / f).lexically_normal();
    return p;
}

namespace {

std::vector<MaterialParam> parse_params(const yaml::Context& ctx, const YAML::Node& node,
                                        const std::filesystem::path& folder) {
    yaml::check_map(ctx, node, "params");
    std::vector<MaterialParam> params;
    for (const auto& entry : node)
        params.push_back(parse_param(ctx, entry.first.Scalar(), entry.second, folder));
    return params;
}

// `draw:` and the width or size that goes with it.
void parse_topology(const yaml::Context& ctx, const YAML::Node& node, Material& m) {
    if (const YAML::Node draw = node["draw"])
        m.draw = yaml::as_enum<Topology>(ctx, draw,
                                         {{"triangles", Topology::triangles},
                                          {"lines", Topology::lines},
                                          {"points", Topology::points}});
    const auto pixels = [&](const char* key, Topology needs, float& out) {
        const YAML::Node n = node[key];
        if (!n) return;
        yaml::ensure(m.draw == needs, ctx, n, ErrorCode::config_invalid,
                     std::string(key) + " is for 'draw: " +
                         (needs == Topology::lines ? "lines" : "points") + "'");
        out = yaml::as<float>(ctx, n);
        yaml::ensure(out > 0.0f && out <= 256.0f, ctx, n, ErrorCode::out_of_range,
                     std::string(key) + " is more than 0 and at most 256 pixels");
    };
    pixels("line_width", Topology::lines, m.line_width);
    pixels("point_size", Topology::points, m.point_size);
}

Material parse_material(const yaml::Context& ctx, const YAML::Node& node,
                        const std::filesystem::path& folder, std::string source) {
    yaml::check_map(ctx, node, "material",
                    {"shader", "blend", "cull", "depth_write", "color_write", "stencil", "draw",
                     "line_width", "point_size", "alpha_to_coverage", "params"});
    Material m;
    m.source = std::move(source);
    m.file = ctx.file;
    m.shader = yaml::as<std::string>(ctx, yaml::require(ctx, node, "shader"));
    if (const YAML::Node blend = node["blend"]) parse_blend(ctx, blend, m);
    if (const YAML::Node cull = node["cull"])
        m.cull = yaml::as_enum<CullMode>(
            ctx, cull,
            {{"none", CullMode::none}, {"back", CullMode::back}, {"front", CullMode::front}});
    if (const YAML::Node depth_write = node["depth_write"])
        m.depth_write = yaml::as<bool>(ctx, depth_write);
    yaml::read(ctx, node, "color_write", m.color_write);
    if (const YAML::Node stencil = node["stencil"]) parse_stencil(ctx, stencil, m);
    parse_topology(ctx, node, m);
    yaml::read(ctx, node, "alpha_to_coverage", m.alpha_to_coverage);
    if (const YAML::Node params = node["params"]) m.params = parse_params(ctx, params, folder);
    return m;
}

// registry.get(), with an unknown name reported where the material names it.
std::shared_ptr<ShaderPlugin> find_shader(const yaml::Context& ctx, const YAML::Node& at,
                                          const std::string& name, PluginRegistry& registry) {
    std::shared_ptr<ShaderPlugin> plugin;
    try {
        plugin = registry.get(name);
    } catch (const Error& e) {
        if (e.code() != ErrorCode::unknown_shader) throw;
        throw yaml::error(ctx, at, e.code(), e.detail());
    }
    if (plugin->is_post())
        throw yaml::error(ctx, at, ErrorCode::wrong_type,
                          "'" + name + "' is a screen pass, not a shader: name it in the "
                          "scene's post: list");
    return plugin;
}

// ---- binding -----------------------------------------------------------------

bool fits(const MaterialParam& p, uint32_t type) {
    using Kind = MaterialParam::Kind;
    const size_t n = p.numbers.size();
    switch (type) {
        case FACET_PARAM_FLOAT: return p.kind == Kind::number;
        case FACET_PARAM_INT: return p.kind == Kind::number && p.is_integer;
        case FACET_PARAM_BOOL: return p.kind == Kind::boolean;
        case FACET_PARAM_COLOR4: return p.kind == Kind::vector && (n == 3 || n == 4);
        case FACET_PARAM_TEXTURE: return p.kind == Kind::texture || p.kind == Kind::word;
        case FACET_PARAM_CHOICE: return p.kind == Kind::word;
        default: return p.kind == Kind::vector && n == size_t(param_float_count(type));
    }
}

std::string expected_text(uint32_t type) {
    switch (type) {
        case FACET_PARAM_FLOAT: return "a number";
        case FACET_PARAM_INT: return "an integer";
        case FACET_PARAM_BOOL: return "true or false";
        case FACET_PARAM_COLOR4: return "3 or 4 numbers";
        case FACET_PARAM_TEXTURE: return "a texture file";
        case FACET_PARAM_CHOICE: return "one of its names";
        default: return std::to_string(param_float_count(type)) + " numbers";
    }
}

std::string value_text(const MaterialParam& p) {
    switch (p.kind) {
        case MaterialParam::Kind::number: return p.is_integer ? "an integer" : "a number";
        case MaterialParam::Kind::boolean: return "a boolean";
        case MaterialParam::Kind::texture: return "a texture";
        case MaterialParam::Kind::word: return "'" + p.word + "'";
        case MaterialParam::Kind::vector: break;
    }
    return std::to_string(p.numbers.size()) + (p.numbers.size() == 1 ? " number" : " numbers");
}

std::string number_text(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

// Errors name `file`, where the parameters were written, and the line.
Error param_error(const std::string& file, const MaterialParam& p, ErrorCode code,
                  std::string detail) {
    return Error(code, "'" + p.name + "'" + detail, file, p.line, p.column);
}

void check_type(const std::string& m, const MaterialParam& p, const facet_param_desc& d) {
    if (!fits(p, d.type))
        throw param_error(m, p, ErrorCode::param_type,
                          " is " + std::string(param_type_name(d.type)) + " and needs " +
                              expected_text(d.type) + ", got " + value_text(p));
}

// The index of a CHOICE parameter's word among `choices`.
int32_t choice_index(const std::string& m, const MaterialParam& p, const char* choices) {
    const std::vector<std::string> names = choice_names(choices);
    for (size_t i = 0; i < names.size(); ++i)
        if (names[i] == p.word) return int32_t(i);
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw param_error(m, p, ErrorCode::param_range,
                      " is '" + p.word + "', which is not one of: " + list);
}

void check_range(const std::string& m, const MaterialParam& p, const facet_param_desc& d) {
    if (d.type == FACET_PARAM_BOOL || d.type == FACET_PARAM_TEXTURE || d.type == FACET_PARAM_CHOICE)
        return;
    // What the block stores holds the number: an int32, else a finite
    // float (beyond 3.4e38 a colour would be infinite, and inf x 0 NaN).
    double lo = d.min_value, hi = d.max_value;
    if (d.type == FACET_PARAM_INT) {
        lo = std::max(lo, double(std::numeric_limits<int32_t>::min()));
        hi = std::min(hi, double(std::numeric_limits<int32_t>::max()));
    } else {
        lo = std::max(lo, double(-std::numeric_limits<float>::max()));
        hi = std::min(hi, double(std::numeric_limits<float>::max()));
    }
    for (size_t i = 0; i < p.numbers.size(); ++i) {
        if (p.numbers[i] >= lo && p.numbers[i] <= hi) continue;
        const std::string which = p.numbers.size() > 1 ? " component " + std::to_string(i) : "";
        throw param_error(m, p, ErrorCode::param_range,
                          which + " is " + number_text(p.numbers[i]) + ", outside " +
                              number_text(lo) + " .. " + number_text(hi));
    }
}

void write_floats(ParamBlock& block, uint32_t offset, const float* values, int count) {
    std::memcpy(block.bytes + offset, values, sizeof(float) * count);
}

void write_int(ParamBlock& block, uint32_t offset, int32_t value) {
    std::memcpy(block.bytes + offset, &value, sizeof value);
}

void write_default(ParamBlock& block, const facet_param_desc& d) {
    if (const int n = param_float_count(d.type))
        write_floats(block, d.offset, d.default_value, n);
    else if (d.type == FACET_PARAM_TEXTURE)
        write_int(block, d.offset, 0);
    else
        write_int(block, d.offset, static_cast<int32_t>(std::lround(d.default_value[0])));
}

// A value that passed check_type() and check_range() (a choice: its index).
void write_value(ParamBlock& block, const facet_param_desc& d, const MaterialParam& p,
                 int32_t choice) {
    if (const int n = param_float_count(d.type)) {
        float values[4] = {0.0f, 0.0f, 0.0f, 1.0f};  // a 3-number color4 is opaque
        for (size_t i = 0; i < p.numbers.size(); ++i) values[i] = static_cast<float>(p.numbers[i]);
        write_floats(block, d.offset, values, n);
    } else if (d.type == FACET_PARAM_BOOL) {
        write_int(block, d.offset, p.flag ? 1 : 0);
    } else if (d.type == FACET_PARAM_INT) {
        write_int(block, d.offset, static_cast<int32_t>(p.numbers[0]));
    } else if (d.type == FACET_PARAM_CHOICE) {
        write_int(block, d.offset, choice);
    } else {
        write_int(block, d.offset, 1);  // a texture is bound
    }
}

// A cube map parameter (FACET_PARAM_CUBE) takes six faces or one
// equirectangular file; any other texture one file.
TextureBinding load_binding(const std::string& m, const MaterialParam& p,
                            const facet_param_desc& d, TextureCache& cache) {
    const bool srgb = (d.flags & FACET_PARAM_SRGB) != 0;
    if (!(d.flags & FACET_PARAM_CUBE) && !p.cube_faces.empty())
        throw Error(ErrorCode::param_type,
                    "'" + p.name + "' is a 2D texture: give it a file, not a cube map's faces", m,
                    p.line, p.column);
    if ((d.flags & FACET_PARAM_CUBE) && (!p.transform.identity() || p.uv_set != 0))
        throw Error(ErrorCode::param_type,
                    "'" + p.name + "' is a cube map, read by direction: it has no UVs to transform "
                    "or choose",
                    m, p.line, p.column);
    if ((d.flags & FACET_PARAM_CUBE) && p.filter == Filter::anisotropic)
        spdlog::warn("{}:{}: '{}' is a cube map: anisotropic filtering is for 2D textures, so it "
                     "is filtered trilinear",
                     m, p.line, p.name);
    try {
        if (d.flags & FACET_PARAM_CUBE)
            return {cache.get_cube(p.cube_faces.empty() ? std::vector{p.texture_file} : p.cube_faces,
                                   srgb),
                    p.filter, p.wrap};
        return {cache.get(p.texture_file, srgb), p.filter, p.wrap, p.transform, p.uv_set,
                p.anisotropy};
    } catch (const Error& e) {
        throw yaml::relocated(e, m, p.line, p.column);
    }
}

}  // namespace

BoundParams bind_params(const std::vector<MaterialParam>& params, const ShaderPlugin& plugin,
                        const std::string& file, TextureCache& cache) {
    const facet_schema& desc = plugin.schema();
    BoundParams out;
    out.block = std::make_shared<ParamBlock>();
    ParamBlock& block = *out.block;
    for (uint32_t i = 0; i < desc.param_count; ++i) write_default(block, desc.params[i]);
    out.textures.resize(size_t(plugin.texture_count()));
    const char* kind = plugin.is_post() ? "; pass '" : "; shader '";
    for (const MaterialParam& p : params) {
        const facet_param_desc* d = plugin.find_param(p.name);
        if (!d)
            throw param_error(file, p, ErrorCode::param_unknown,
                              kind + plugin.name() + "' expects: " + plugin.describe_params());
        check_type(file, p, *d);
        check_range(file, p, *d);
        const int32_t choice =
            d->type == FACET_PARAM_CHOICE
                ? choice_index(file, p, desc.choices[d - desc.params])
                : 0;
        write_value(block, *d, p, choice);
        if (d->type != FACET_PARAM_TEXTURE) continue;
        const int slot = plugin.texture_slot(*d);
        if (p.uv_set == 1 && plugin.texture_uv_float(slot, 1) < 0)
            throw param_error(file, p, ErrorCode::config_invalid,
                              " reads the second set of texture coordinates (uv_set: 1), and " +
                                  std::string(d->uv_varying < 0 ? "the shader samples it itself"
                                                                : "shader '" + plugin.name() +
                                                                      "' has no second set"));
        out.textures[size_t(slot)] = load_binding(file, p, *d, cache);
    }
    return out;
}

void bind(Material& material, std::shared_ptr<ShaderPlugin> plugin, TextureCache& cache) {
    const facet_schema& desc = plugin->schema();
    if (plugin->is_post())
        throw Error(ErrorCode::wrong_type,
                    "'" + plugin->name() + "' is a screen pass, not a shader: name it in the "
                    "scene's post: list",
                    material.file);
    BoundParams bound = bind_params(material.params, *plugin, material.file, cache);
    std::shared_ptr<ParamBlock> block = std::move(bound.block);
    std::vector<TextureBinding> textures = std::move(bound.textures);
    // Whether it uses the passes its shader can read.
    const auto uses = [&](uint32_t need, uint32_t flag) {
        if (!plugin->needs(facet_need(need))) return false;
        for (uint32_t i = 0; i < desc.param_count; ++i) {
            const facet_param_desc& d = desc.params[i];
            if (!(d.flags & flag)) continue;
            if (d.type == FACET_PARAM_FLOAT) {
                float v;
                std::memcpy(&v, block->bytes + d.offset, sizeof v);
                return v != 0.0f;
            }
            int32_t v;
            std::memcpy(&v, block->bytes + d.offset, sizeof v);
            return v != 0;
        }
        return true;
    };
    const bool shadows = uses(FACET_NEED_SHADOW_MAP, FACET_PARAM_USES_SHADOWS);
    const bool ao = uses(FACET_NEED_AO, FACET_PARAM_USES_AO);
    const bool discards = uses(FACET_NEED_DISCARD, FACET_PARAM_USES_DISCARD);
    material.plugin = std::move(plugin);
    material.block = std::move(block);
    material.textures = std::move(textures);
    material.uses_shadows = shadows;
    material.uses_ao = ao;
    material.discards = discards;
}

std::shared_ptr<Material> material_from_yaml(const yaml::Context& ctx, const YAML::Node& node,
                                             const std::filesystem::path& folder,
                                             std::string source, PluginRegistry& registry,
                                             TextureCache& cache) {
    auto material =
        std::make_shared<Material>(parse_material(ctx, node, folder, std::move(source)));
    bind(*material, find_shader(ctx, node["shader"], material->shader, registry), cache);
    return material;
}

std::shared_ptr<Material> imported_material(const ImportedMaterial& imported,
                                            const std::string& source,
                                            const std::filesystem::path& folder,
                                            PluginRegistry& registry, TextureCache& cache) {
    const yaml::Context ctx{source};
    YAML::Node node;
    try {
        node = YAML::Load(imported.yaml);
        auto material = std::make_shared<Material>(parse_material(ctx, node, folder, source));
        for (MaterialParam& p : material->params) p.line = p.column = 0;
        std::shared_ptr<ShaderPlugin> plugin;
        try {
            plugin = registry.get(material->shader);
        } catch (const Error& e) {
            throw Error(e.code(), e.detail(), source);
        }
        bind(*material, std::move(plugin), cache);
        return material;
    } catch (const YAML::Exception& e) {  // facet's own YAML: a bug, said as one
        throw Error(ErrorCode::config_invalid, "facet mapped it to YAML it cannot read (" +
                                                   std::string(e.what()) + "):\n" + imported.yaml,
                    source);
    }
}

std::shared_ptr<Material> load_material(const std::filesystem::path& path, PluginRegistry& registry,
                                        TextureCache& cache) {
    const yaml::Context ctx{path.string()};
    return material_from_yaml(ctx, yaml::load_file(path), path.parent_path(), path.string(),
                              registry, cache);
}

}  // namespace facet
