// Fuzz target: the material loader, load_material() (core/src/assets/material.cpp,
// yaml_util.cpp, texture.cpp), against the build's real shader plugins.
//
// The input is a material file, written to configs/materials/ in the
// sandbox (support.hpp), next to copies of the repository's materials, so
// their texture paths (../../assets/spot/spot_texture.png) resolve.
//
// Checks:
//  - load_material() returns a material or throws facet::Error naming a
//    file; any other exception is a finding;
//  - a material that loaded is bound (check_bound below): its shader is the
//    one it names, and the parameter block holds exactly the values the file
//    gives, or the schema's defaults, within the declared ranges.
#include "support.hpp"

#include <facet/error.hpp>

#include <cmath>
#include <cstring>

namespace facet::fuzz {

namespace {

const MaterialParam* given(const Material& m, const char* name) {
    for (const MaterialParam& p : m.params)
        if (p.name == name) return &p;
    return nullptr;
}

// The floats of a float-typed parameter (param_float_count() of them) as
// bind() must write them: the given numbers, and a 3-number colour4 opaque.
void check_floats(const Material& m, const facet_param_desc& d, const MaterialParam* p) {
    const int n = param_float_count(d.type);
    float expected[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    for (int i = 0; i < n; ++i) {
        if (!p) expected[i] = d.default_value[i];
        else if (size_t(i) < p->numbers.size()) expected[i] = float(p->numbers[size_t(i)]);
    }
    float stored[4];
    std::memcpy(stored, m.block->bytes + d.offset, sizeof(float) * size_t(n));
    for (int i = 0; i < n; ++i) {
        check(stored[i] == expected[i] || (std::isnan(stored[i]) && std::isnan(expected[i])),
              std::string("parameter '") + d.name + "' holds a value the material did not give");
        if (p)
            check(stored[i] >= d.min_value && stored[i] <= d.max_value,
                  std::string("parameter '") + d.name + "' was accepted outside its range");
    }
}

// An int32 parameter: INT, BOOL, or TEXTURE (1 when bound).
void check_int(const Material& m, const facet_param_desc& d, const MaterialParam* p) {
    double expected = 0.0;  // an INT's number, exactly as written
    if (d.type == FACET_PARAM_TEXTURE) expected = p ? 1.0 : 0.0;
    else if (!p) expected = double(std::lround(d.default_value[0]));
    else if (d.type == FACET_PARAM_BOOL) expected = p->flag ? 1.0 : 0.0;
    else expected = p->numbers.at(0);
    int32_t stored = 0;
    std::memcpy(&stored, m.block->bytes + d.offset, sizeof stored);
    check(double(stored) == expected,
          std::string("parameter '") + d.name + "' holds a value the material did not give");
    if (d.type == FACET_PARAM_INT && p)
        check(stored >= d.min_value && stored <= d.max_value,
              std::string("parameter '") + d.name + "' was accepted outside its range");
}

}  // namespace

void check_bound(const Material& m) {
    check(m.plugin && m.block, "a loaded material is not bound");
    check(m.plugin->name() == m.shader, "bound to shader '" + m.plugin->name() + "', named '" +
                                            m.shader + "'");
    check(m.textures.size() == size_t(m.plugin->texture_count()),
          "texture bindings do not match the shader's texture slots");
    for (const MaterialParam& p : m.params)
        check(m.plugin->find_param(p.name) != nullptr,
              "parameter '" + p.name + "' is not in the shader's schema but was accepted");
    const facet_schema& desc = m.plugin->schema();
    for (uint32_t i = 0; i < desc.param_count; ++i) {
        const facet_param_desc& d = desc.params[i];
        const MaterialParam* p = given(m, d.name);
        if (param_float_count(d.type) > 0) check_floats(m, d, p);
        else check_int(m, d, p);
        if (d.type == FACET_PARAM_TEXTURE && p)
            check(m.textures[size_t(m.plugin->texture_slot(d))].texture != nullptr,
                  std::string("texture '") + d.name + "' is named but not bound");
    }
}

void material_yaml(const uint8_t* data, size_t size) {
    const InputFile input(sandbox() / "configs" / "materials" / "fuzz-input.yaml", data, size);
    PluginRegistry registry{std::vector<std::filesystem::path>{}};
    add_shaders(registry);
    TextureCache textures;
    std::shared_ptr<Material> material;
    try {
        material = load_material(input.path(), registry, textures);
    } catch (const Error& e) {
        check(!e.file().empty(), std::string("an error names no file: ") + e.what());
        return;
    } catch (const std::exception& e) {
        unexpected("load_material", e);
    }
    check(material != nullptr, "load_material returned no material");
    check_bound(*material);
}

}  // namespace facet::fuzz
