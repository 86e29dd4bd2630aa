// Materials: a shader plugin plus the values of its parameters.
//
// A material file (YAML) names a shader and gives parameter values:
//
//     shader: unlit
//     blend: opaque            # opaque | alpha | additive | premultiplied | multiply,
//                              # or GL's {src, dst, op, ...} (docs/scenes.md)
//     alpha_to_coverage: false # MSAA: alpha picks the samples covered
//     color_write: true        # false: only depth and stencil are written
//     draw: triangles          # or lines (line_width: px) or points (point_size: px)
//     stencil: {test: equal, ref: 1, pass: keep}  # GL's stencil test (docs/scenes.md)
//     params:
//       base_color: [1, 0.5, 0.2, 1]
//       base_texture: {file: ../../assets/spot/spot_texture.png, filter: trilinear, wrap: repeat}
//
// A cube map parameter (a shader's `cube` kind: mirror's `environment`)
// takes six square faces of one size, +X, -X, +Y, -Y, +Z, -Z, or one
// equirectangular image (facet/texture.hpp, load_cube):
//
//       environment: {faces: [px.png, nx.png, py.png, ny.png, pz.png, nz.png]}
//       environment: {file: sky.png, filter: trilinear}
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
    // word: a bare name, for a choice ("aces") or a texture file
    enum class Kind { number, boolean, vector, texture, word };
    std::string name;
    Kind kind = Kind::number;
    std::string word;             // word: as written
    std::vector<double> numbers;  // number: 1 value; vector: 1..4 values
    bool is_integer = false;      // number written without a fraction
    bool flag = false;            // boolean
    std::filesystem::path texture_file;  // texture, word: resolved against the material's folder
    // texture: a cube map's six faces (+X, -X, +Y, -Y, +Z, -Z), resolved so
    // too; empty for one file (a cube map's then equirectangular)
    std::vector<std::filesystem::path> cube_faces;
    Filter filter = Filter::trilinear;   // texture: nearest | bilinear | trilinear | anisotropic
    int anisotropy = kMaxAnisotropy;     // texture: anisotropic's most samples (2 to 16)
    Wrap wrap = Wrap::repeat;            // texture
    UvTransform transform;               // texture: a 2D one's placement on its UVs
    int uv_set = 0;                      // texture: the UV set it reads (0 or 1)
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
    BlendFunc blend_func;                // blend == custom: the factors and equations
    std::optional<CullMode> cull;       // overrides the scene's setting
    std::optional<bool> depth_write;    // default: true unless blended
    bool color_write = true;            // false: depth and stencil only (GL's colour mask)
    Topology draw = Topology::triangles;  // `draw:` triangles, lines (its edges) or points
    float line_width = 1.0f;            // pixels, lines
    float point_size = 1.0f;            // pixels, points
    StencilState stencil;               // `stencil:`; off unless given
    // With MSAA, the shader's alpha chooses how many of a pixel's samples it
    // covers (alpha to coverage: PipelineState::alpha_to_coverage).
    bool alpha_to_coverage = false;
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
    // Whether its fragments may be discarded: the shader needs
    // FACET_NEED_DISCARD, and its FACET_PARAM_USES_DISCARD parameter (an
    // alpha cutoff), if it has one, is not 0.
    bool discards = false;

    bool writes_depth() const { return depth_write.value_or(blend == BlendMode::opaque); }
};

// A parameter block and its textures, from values checked against a schema.
struct BoundParams {
    std::shared_ptr<ParamBlock> block;
    std::vector<TextureBinding> textures;  // by texture slot
};

// Checks `params` (written in `file`) against `plugin`'s schema: unknown
// names, wrong types, out-of-range values and choices that are not among
// its names are errors naming file:line:column. Loads their textures
// through `cache`. Materials and screen passes (post chains) alike.
BoundParams bind_params(const std::vector<MaterialParam>& params, const ShaderPlugin& plugin,
                        const std::string& file, TextureCache& cache);

// Validates `material.params` against `plugin`'s schema, loads its textures
// through `cache`, and sets plugin, block and textures. On error, throws and
// leaves `material` unchanged.
void bind(Material& material, std::shared_ptr<ShaderPlugin> plugin, TextureCache& cache);

// Parses a material file and binds it to its plugin from `registry`.
// Throws Error naming file:line:column.
std::shared_ptr<Material> load_material(const std::filesystem::path& path,
                                        PluginRegistry& registry, TextureCache& cache);

}  // namespace facet
