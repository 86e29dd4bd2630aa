// A plugin's descriptor checked against this host's ABI and limits
// (validate_descriptor in facet/plugin.hpp), before the host reads any of
// it to draw: every count within its table, every name there, every value
// a schema or a varying can hold.
#include "facet/plugin.hpp"

#include "facet/error.hpp"
#include "plugin/descriptor.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace facet {

namespace {

[[noreturn]] void reject(ErrorCode code, const std::string& origin, const std::string& why) {
    throw Error(code, why, origin);
}

std::string to_hex(uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%x", v);
    return buf;
}

bool valid_param_type(uint32_t type) { return type <= FACET_PARAM_CHOICE; }

uint32_t param_bytes(uint32_t type) { return 4u * uint32_t(std::max(1, param_float_count(type))); }

// The parts of a descriptor, as the host copies them (fields past a
// record's struct_size zero).
struct Parts {
    const facet_plugin_desc& plugin;
    const facet_shader_desc& shader;  // zeros for a screen pass
    bool pass;
    const std::string& origin;
    const facet_plugin_desc* original;  // where the plugin keeps it
    const facet_schema& schema() const { return plugin.schema; }
};

void validate_varyings(const Parts& d) {
    const facet_shader_desc& s = d.shader;
    if (s.varying_count > FACET_MAX_VARYINGS)
        reject(ErrorCode::plugin_invalid, d.origin,
               std::to_string(s.varying_count) + " varyings (at most " +
                   std::to_string(FACET_MAX_VARYINGS) + ")");
    if (s.varying_count > 0 && !s.varyings)
        reject(ErrorCode::plugin_invalid, d.origin, "varying_count > 0 but no varyings table");
    uint32_t floats = 0;
    for (uint32_t i = 0; i < s.varying_count; ++i) {
        const facet_varying_desc& v = s.varyings[i];
        if (v.components < 1 || v.components > 4 || v.interpolation > FACET_INTERP_FLAT)
            reject(ErrorCode::plugin_invalid, d.origin,
                   "varying " + std::to_string(i) + " has " + std::to_string(v.components) +
                       " components and interpolation " + std::to_string(v.interpolation));
        floats += v.components;
    }
    if (floats > FACET_MAX_VARYING_FLOATS)
        reject(ErrorCode::plugin_invalid, d.origin,
               std::to_string(floats) + " varying floats (at most " +
                   std::to_string(FACET_MAX_VARYING_FLOATS) + ")");
}

// The shared object `address` lies in, or null (the heap, the stack).
const void* object_of(const void* address) {
    Dl_info info{};
    return address && dladdr(address, &info) ? info.dli_fbase : nullptr;
}

// Whether the bytes [first, first + bytes) lie in shared object `home`.
bool within(const void* home, const void* first, size_t bytes) {
    return object_of(first) == home &&
           object_of(static_cast<const char*>(first) + bytes - 1) == home;
}

// A table that lives in the plugin's shared object (or the program) keeps
// its entries and their names there too: an entry or a name elsewhere means
// a count that runs past the table, found before a name is read.
void check_in_object(const Parts& d) {
    const facet_schema& s = d.schema();
    const void* home = object_of(d.original);
    // A descriptor or a table built at run time (tests, embedders, generated
    // schemas): nothing to compare with.
    if (!home || s.param_count == 0 || object_of(s.params) != home) return;
    for (uint32_t i = 0; i < s.param_count; ++i) {
        const facet_param_desc* p = s.params + i;
        if (!within(home, p, sizeof *p) || (p->name && object_of(p->name) != home))
            reject(ErrorCode::plugin_invalid, d.origin,
                   "parameter " + std::to_string(i) + " lies outside the plugin: param_count (" +
                       std::to_string(s.param_count) + ") runs past the end of its table");
    }
    if (!s.choices || object_of(s.choices) != home) return;
    for (uint32_t i = 0; i < s.param_count; ++i) {
        const char* const* entry = s.choices + i;
        if (!within(home, entry, sizeof *entry) || (*entry && object_of(*entry) != home))
            reject(ErrorCode::plugin_invalid, d.origin,
                   "the choices of parameter " + std::to_string(i) +
                       " lie outside the plugin: the choices table is shorter than params");
    }
}

// The range and defaults of a number parameter: min <= max, neither NaN,
// and defaults within them.
void check_param_range(const facet_param_desc& p, const std::string& what,
                       const std::string& origin) {
    const int components = p.type == FACET_PARAM_INT ? 1 : param_float_count(p.type);
    if (components == 0) return;  // BOOL, TEXTURE: no range
    if (!(p.min_value <= p.max_value))
        reject(ErrorCode::plugin_invalid, origin,
               what + " has the range " + std::to_string(p.min_value) + " .. " +
                   std::to_string(p.max_value) + " (min above max, or NaN)");
    for (int c = 0; c < components; ++c)
        if (!(p.default_value[c] >= p.min_value && p.default_value[c] <= p.max_value))
            reject(ErrorCode::plugin_invalid, origin,
                   what + " has the default " + std::to_string(p.default_value[c]) +
                       " outside its range " + std::to_string(p.min_value) + " .. " +
                       std::to_string(p.max_value));
}

// The names of CHOICE parameter `p` in `choices` ("a|b|c"): at least one,
// none empty or given twice, and the default one of them.
void check_choices(const facet_param_desc& p, const char* choices, const std::string& what,
                   const std::string& origin) {
    if (!choices)
        reject(ErrorCode::plugin_invalid, origin,
               what + " is a choice but the schema's choices give it no names");
    const std::vector<std::string> names = choice_names(choices);
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i].empty())
            reject(ErrorCode::plugin_invalid, origin,
                   what + " has an empty name among its choices '" + choices + "'");
        if (std::find(names.begin(), names.begin() + long(i), names[i]) != names.begin() + long(i))
            reject(ErrorCode::plugin_invalid, origin,
                   what + " names the choice '" + names[i] + "' twice");
    }
    const float d = p.default_value[0];
    if (!(d >= 0.0f && d < float(names.size()) && d == std::floor(d)))
        reject(ErrorCode::plugin_invalid, origin,
               what + " has the default " + std::to_string(d) + ", not the index of one of '" +
                   choices + "'");
}

// A texture parameter: a shader's, with a 2-component UV varying or -1,
// and -1 for a cube map.
void check_texture(const Parts& d, const facet_param_desc& p, const std::string& what) {
    if (d.pass) reject(ErrorCode::plugin_invalid, d.origin, what + ": a screen pass takes no textures");
    const bool unsampled = p.uv_varying == -1;  // only the shader samples it
    if (!unsampled && (p.uv_varying < 0 || uint32_t(p.uv_varying) >= d.shader.varying_count ||
                       d.shader.varyings[p.uv_varying].components < 2))
        reject(ErrorCode::plugin_invalid, d.origin, what + " names no 2-component UV varying");
    if ((p.flags & FACET_PARAM_CUBE) && !unsampled)
        reject(ErrorCode::plugin_invalid, d.origin,
               what + " is a cube map: its UV varying must be -1");
}

// A parameter that says whether a material uses a pass must be one the
// host can read that way, and say it for a pass the shader needs.
void check_uses_flags(const Parts& d, const facet_param_desc& p, const std::string& what) {
    const uint32_t needs = d.shader.needs;
    const bool flag_type = p.type == FACET_PARAM_BOOL || p.type == FACET_PARAM_FLOAT;
    if ((p.flags & FACET_PARAM_USES_SHADOWS) &&
        (p.type != FACET_PARAM_BOOL || !(needs & FACET_NEED_SHADOW_MAP)))
        reject(ErrorCode::plugin_invalid, d.origin,
               what + " says whether shadows are used, but it is not a bool or the shader "
                      "does not need FACET_NEED_SHADOW_MAP");
    if ((p.flags & FACET_PARAM_USES_AO) && (!flag_type || !(needs & FACET_NEED_AO)))
        reject(ErrorCode::plugin_invalid, d.origin,
               what + " says whether AO is used, but it is not a bool or a float or the "
                      "shader does not need FACET_NEED_AO");
    if ((p.flags & FACET_PARAM_USES_DISCARD) && (!flag_type || !(needs & FACET_NEED_DISCARD)))
        reject(ErrorCode::plugin_invalid, d.origin,
               what + " says whether the material discards, but it is not a bool or a "
                      "float or the shader does not need FACET_NEED_DISCARD");
}

// Parameter i: named, typed, inside the block and overlapping no other,
// declared once, with a valid range or choices.
void check_param(const Parts& d, uint32_t i) {
    const facet_schema& s = d.schema();
    const facet_param_desc& p = s.params[i];
    const std::string what =
        "parameter " + std::to_string(i) + " ('" + (p.name ? p.name : "(null)") + "')";
    if (!p.name || !*p.name || !valid_param_type(p.type))
        reject(ErrorCode::plugin_invalid, d.origin, what + " has no name or an unknown type");
    if (p.offset % 4 != 0 || p.offset > s.params_size ||
        param_bytes(p.type) > s.params_size - p.offset)
        reject(ErrorCode::plugin_invalid, d.origin, what + " lies outside the parameter block");
    for (uint32_t j = 0; j < i; ++j) {
        const facet_param_desc& q = s.params[j];
        if (p.offset < q.offset + param_bytes(q.type) && q.offset < p.offset + param_bytes(p.type))
            reject(ErrorCode::plugin_invalid, d.origin,
                   what + " overlaps parameter " + std::to_string(j) + " ('" + q.name +
                       "') in the parameter block");
        if (std::strcmp(q.name, p.name) == 0)
            reject(ErrorCode::plugin_invalid, d.origin, what + " is declared twice");
    }
    if (p.type == FACET_PARAM_CHOICE)
        check_choices(p, s.choices ? s.choices[i] : nullptr, what, d.origin);
    else if (s.choices && s.choices[i])
        reject(ErrorCode::plugin_invalid, d.origin, what + " has choices but is not a choice");
    else
        check_param_range(p, what, d.origin);
    if (p.type == FACET_PARAM_TEXTURE)
        check_texture(d, p, what);
    else if (p.flags & FACET_PARAM_CUBE)
        reject(ErrorCode::plugin_invalid, d.origin, what + " is a cube map but not a texture");
    check_uses_flags(d, p, what);
}

void validate_params(const Parts& d) {
    const facet_schema& s = d.schema();
    if (s.param_count > FACET_MAX_PARAMS || s.params_size > FACET_MAX_PARAMS_SIZE)
        reject(ErrorCode::plugin_invalid, d.origin,
               "parameter schema too large (" + std::to_string(s.param_count) + " parameters, " +
                   std::to_string(s.params_size) + " bytes)");
    if (s.param_count > 0 && !s.params)
        reject(ErrorCode::plugin_invalid, d.origin, "param_count > 0 but no params table");
    check_in_object(d);
    int textures = 0;
    for (uint32_t i = 0; i < s.param_count; ++i) {
        check_param(d, i);
        textures += s.params[i].type == FACET_PARAM_TEXTURE;
    }
    if (textures > FACET_MAX_TEXTURES)
        reject(ErrorCode::plugin_invalid, d.origin,
               std::to_string(textures) + " texture parameters (at most " +
                   std::to_string(FACET_MAX_TEXTURES) + ")");
}

// The conditional varyings are some of the last ones, their condition a
// TEXTURE or BOOL parameter, and a texture read at one of them is the
// condition itself (else it would be sampled at zeros).
void validate_conditional_varyings(const Parts& d) {
    const facet_shader_desc& c = d.shader;
    const facet_schema& s = d.schema();
    if (c.conditional_varyings == 0) return;
    if (c.conditional_varyings > c.varying_count)
        reject(ErrorCode::plugin_invalid, d.origin,
               std::to_string(c.conditional_varyings) + " conditional varyings of " +
                   std::to_string(c.varying_count));
    const auto is_condition = [&](uint32_t i) {
        return i < s.param_count &&
               (s.params[i].type == FACET_PARAM_TEXTURE || s.params[i].type == FACET_PARAM_BOOL);
    };
    if (!is_condition(c.varyings_condition))
        reject(ErrorCode::plugin_invalid, d.origin,
               "the conditional varyings' condition is not a texture or bool parameter");
    if (c.varyings_condition_also > 0 && !is_condition(c.varyings_condition_also - 1))
        reject(ErrorCode::plugin_invalid, d.origin,
               "the conditional varyings' second condition is not a texture or bool parameter");
    const uint32_t first = c.varying_count - c.conditional_varyings;
    for (uint32_t i = 0; i < s.param_count; ++i) {
        const facet_param_desc& p = s.params[i];
        if (p.type == FACET_PARAM_TEXTURE && p.uv_varying >= 0 && uint32_t(p.uv_varying) >= first &&
            i != c.varyings_condition && i + 1 != c.varyings_condition_also)
            reject(ErrorCode::plugin_invalid, d.origin,
                   "texture '" + std::string(p.name) + "' reads its UV from a conditional "
                   "varying, and is not their condition");
    }
}

// The second UV set's varying (ABI 2.1): one of two components or more,
// not conditional, filled from FACET_NEED_UV1.
void validate_second_uv(const Parts& d) {
    const facet_shader_desc& c = d.shader;
    if (c.second_uv == 0) return;
    const uint32_t v = c.second_uv - 1;
    if (v >= c.varying_count || c.varyings[v].components < 2)
        reject(ErrorCode::plugin_invalid, d.origin,
               "second_uv names no varying of two components or more");
    if (v >= c.varying_count - c.conditional_varyings)
        reject(ErrorCode::plugin_invalid, d.origin, "second_uv names a conditional varying");
    if (!(c.needs & FACET_NEED_UV1))
        reject(ErrorCode::plugin_invalid, d.origin,
               "second_uv is set, and the shader does not need FACET_NEED_UV1");
}

// The fragment entries: at least the baseline's, each instruction set
// once, every function there. Entries for instruction sets this host does
// not know are allowed (a later minor version's), and never called.
void validate_fragments(const Parts& d) {
    const facet_shader_desc& s = d.shader;
    if (s.fragment_count == 0 || !s.fragments || s.fragment_count > 64)
        reject(ErrorCode::plugin_invalid, d.origin,
               "the shader has " + std::to_string(s.fragment_count) +
                   " fragment entries; it needs one for each instruction set it was built "
                   "for, FACET_ISA_BASELINE among them");
    bool seen[FACET_ISA_X86_64_V4 + 1] = {};
    for (uint32_t i = 0; i < s.fragment_count; ++i) {
        const facet_fragment_entry& e = s.fragments[i];
        if (!e.fragment)
            reject(ErrorCode::plugin_invalid, d.origin,
                   "fragment entry " + std::to_string(i) + " has no function");
        if (e.isa > FACET_ISA_X86_64_V4) continue;
        if (seen[e.isa])
            reject(ErrorCode::plugin_invalid, d.origin,
                   "two fragment entries for instruction set " + std::to_string(e.isa));
        seen[e.isa] = true;
    }
    if (!seen[FACET_ISA_BASELINE])
        reject(ErrorCode::plugin_invalid, d.origin,
               "no fragment entry for FACET_ISA_BASELINE, which every host can call");
}

// A record of the plugin's that starts with its struct_size: at least ABI
// 2.0's, and no larger than this host's unless the plugin is newer.
void check_record_size(uint32_t size, size_t least, size_t ours, const facet_plugin_desc& d,
                       const char* what, const std::string& origin) {
    if (size < least)
        reject(ErrorCode::plugin_struct_size, origin,
               std::string(what) + " is " + std::to_string(size) + " bytes, ABI " +
                   std::to_string(FACET_ABI_MAJOR) + ".0 needs at least " + std::to_string(least));
    if (size > ours && d.abi_minor <= FACET_ABI_MINOR)
        reject(ErrorCode::plugin_struct_size, origin,
               std::string(what) + " is " + std::to_string(size) + " bytes, but ABI " +
                   std::to_string(FACET_ABI_MAJOR) + "." + std::to_string(d.abi_minor) +
                   " defines " + std::to_string(ours));
}

// The descriptor's first record: its ABI, its size, its name, and what it is.
void validate_header(const facet_plugin_desc* d, const std::string& origin) {
    if (!d) reject(ErrorCode::plugin_invalid, origin, "the entry point returned no descriptor");
    if (d->abi_major != FACET_ABI_MAJOR)
        reject(ErrorCode::plugin_abi_mismatch, origin,
               "built for ABI " + std::to_string(d->abi_major) + "." +
                   std::to_string(d->abi_minor) + ", this host speaks ABI " +
                   std::to_string(FACET_ABI_MAJOR) + "." + std::to_string(FACET_ABI_MINOR) +
                   "; rebuild the plugin against this facet SDK");
    check_record_size(d->struct_size, kPluginDesc20Size, sizeof(facet_plugin_desc), *d,
                      "the descriptor", origin);
    if (!d->name || !*d->name)
        reject(ErrorCode::plugin_invalid, origin, "the descriptor has no name");
    if (!d->shader == !d->pass)
        reject(ErrorCode::plugin_invalid, origin,
               d->shader ? "the descriptor is both a shader and a screen pass"
                         : "the descriptor is neither a shader nor a screen pass");
}

}  // namespace

void validate_descriptor(const facet_plugin_desc* d, const std::string& origin) {
    validate_header(d, origin);
    if (d->shader)
        check_record_size(d->shader->struct_size, kShaderDesc20Size, sizeof(facet_shader_desc),
                          *d, "the shader record", origin);
    else
        check_record_size(d->pass->struct_size, kPassDesc20Size, sizeof(facet_pass_desc), *d,
                          "the screen pass record", origin);
    const DescriptorCopy c = copy_descriptor(*d);
    if (d->shader && !c.shader.vertex)
        reject(ErrorCode::plugin_invalid, origin, "the shader has no vertex function");
    if (d->pass && !c.pass.run)
        reject(ErrorCode::plugin_invalid, origin, "the screen pass has no function");
    const Parts parts{c.plugin, c.shader, d->pass != nullptr, origin, d};
    if (d->shader) validate_fragments(parts);
    if (c.shader.needs & ~kSupportedNeeds)
        reject(ErrorCode::plugin_invalid, origin,
               "needs inputs this host cannot provide (needs bits 0x" +
                   to_hex(c.shader.needs & ~kSupportedNeeds) + ")");
    validate_varyings(parts);
    validate_params(parts);
    validate_conditional_varyings(parts);
    validate_second_uv(parts);
}

std::vector<std::string> choice_names(std::string_view choices) {
    std::vector<std::string> names;
    for (size_t start = 0;;) {
        const size_t bar = choices.find('|', start);
        names.emplace_back(choices.substr(start, bar - start));
        if (bar == std::string_view::npos) return names;
        start = bar + 1;
    }
}

int param_float_count(uint32_t type) {
    switch (type) {
        case FACET_PARAM_FLOAT: return 1;
        case FACET_PARAM_VEC2: return 2;
        case FACET_PARAM_VEC3:
        case FACET_PARAM_COLOR3: return 3;
        case FACET_PARAM_VEC4:
        case FACET_PARAM_COLOR4: return 4;
        default: return 0;
    }
}

std::string_view param_type_name(uint32_t type) {
    static constexpr std::string_view names[] = {"float",  "int",    "bool",    "vec2",
                                                 "vec3",   "vec4",   "color3",  "color4",
                                                 "texture", "choice"};
    return valid_param_type(type) ? names[type] : "unknown";
}

}  // namespace facet
