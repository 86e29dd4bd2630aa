// Materials: a shader plugin plus the values of its parameters.
//
// A material file (YAML) names a shader and gives parameter values:
//
//     shader: unlit
//     blend: opaque            # opaque | alpha | additive
//     params:
//       base_color: [1, 0.5, 0.2, 1]
//       base_texture: {file: ../../assets/spot/spot_texture.png, filter: trilinear, wrap: repeat}
//
// The values are kept as written (MaterialParam), so they can be checked
// again and re-laid-out when the plugin is reloaded. bind() validates them
// against the plugin's schema and builds the parameter block the shader
// reads: unknown names, wrong types and out-of-range values are errors
// naming the file, the line and the parameters the plugin expects.
#pragma once

#include "facet/plugin.hpp"
#include "facet/render_state.hpp"
#include "facet/texture.hpp"

#include <glm/glm.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace facet {

// One parameter value as written in YAML.
struct MaterialParam {
    enum class Kind { number, boolean, vector, texture };
    std::string name;
    Kind kind = Kind::number;
    std::vector<double> numbers;  // number: 1 value; vector: 1..4 values
    bool is_integer = false;      // number written without a fraction
    bool flag = false;            // boolean
    std::filesystem::path texture_file;  // texture: resolved against the material's folder
    Filter filter = Filter::trilinear;   // texture: nearest | bilinear | trilinear
    Wrap wrap = Wrap::repeat;            // texture
    int line = 0;                 // 1-based position in the file
    int column = 0;
};

// 16-byte aligned parameter block, laid out by the plugin's schema.
struct ParamBlock {
    alignas(16) unsigned char bytes[FACET_MAX_PARAMS_SIZE] = {};
};

struct Material {
    std::string source;    // file, or "<scene>:<line>" for an inline material
    std::string file;      // file the params' line and column refer to
    std::string shader;    // plugin name
    BlendMode blend = BlendMode::opaque;
    std::optional<CullMode> cull;       // overrides the scene's setting
    std::optional<bool> depth_write;    // default: true unless blended
    std::vector<MaterialParam> params;  // as written

    // Set by bind():
    std::shared_ptr<ShaderPlugin> plugin;
    std::shared_ptr<const ParamBlock> block;
    std::vector<TextureBinding> textures;  // by texture slot
    // Whether the material uses the shadow maps and the AO its shader can
    // read: the shader needs them, and its parameter that says so
    // (FACET_PARAM_USES_SHADOWS, _USES_AO), if it has one, is on.
    bool uses_shadows = false;
    bool uses_ao = false;

    bool writes_depth() const { return depth_write.value_or(blend == BlendMode::opaque); }
};

// Validates `material.params` against `plugin`'s schema, loads its textures
// through `cache`, and sets plugin, block and textures. On error, throws and
// leaves `material` unchanged.
void bind(Material& material, std::shared_ptr<ShaderPlugin> plugin, TextureCache& cache);

// Parses a material file and binds it to its plugin from `registry`.
// Throws Error naming file:line:column.
std::shared_ptr<Material> load_material(const std::filesystem::path& path,
                                        PluginRegistry& registry, TextureCache& cache);

}  // namespace facet
