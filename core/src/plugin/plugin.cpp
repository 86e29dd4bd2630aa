#include "facet/plugin.hpp"

#include "facet/error.hpp"
#include "facet/paths.hpp"
#include "base/files.hpp"
#include "base/signal_stack.hpp"
#include "plugin/plugin_calls.hpp"

#include <spdlog/spdlog.h>

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>
#include <elf.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

namespace facet {

namespace fs = std::filesystem;

namespace {

std::string to_hex(uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%x", v);
    return buf;
}

[[noreturn]] void refuse(ErrorCode code, const std::string& origin, const std::string& why) {
    throw Error(code, why, origin);
}

bool valid_param_type(uint32_t type) { return type <= FACET_PARAM_CHOICE; }

uint32_t param_bytes(uint32_t type) { return 4u * uint32_t(std::max(1, param_float_count(type))); }

void validate_varyings(const facet_shader_desc& d, const std::string& origin) {
    if (d.varying_count > FACET_MAX_VARYINGS)
        refuse(ErrorCode::plugin_invalid, origin,
               std::to_string(d.varying_count) + " varyings (at most " +
                   std::to_string(FACET_MAX_VARYINGS) + ")");
    if (d.varying_count > 0 && !d.varyings)
        refuse(ErrorCode::plugin_invalid, origin, "varying_count > 0 but no varyings table");
    uint32_t floats = 0;
    for (uint32_t i = 0; i < d.varying_count; ++i) {
        const facet_varying_desc& v = d.varyings[i];
        if (v.components < 1 || v.components > 4 || v.interpolation > FACET_INTERP_FLAT)
            refuse(ErrorCode::plugin_invalid, origin,
                   "varying " + std::to_string(i) + " has " + std::to_string(v.components) +
                       " components and interpolation " + std::to_string(v.interpolation));
        floats += v.components;
    }
    if (floats > FACET_MAX_VARYING_FLOATS)
        refuse(ErrorCode::plugin_invalid, origin,
               std::to_string(floats) + " varying floats (at most " +
                   std::to_string(FACET_MAX_VARYING_FLOATS) + ")");
}

// The shared object `address` lies in, or null (the heap, the stack).
const void* object_of(const void* address) {
    Dl_info info{};
    return address && dladdr(address, &info) ? info.dli_fbase : nullptr;
}

// A table that lives in the plugin's shared object (or the program) keeps
// its entries and their names there too: an entry or a name elsewhere means
// a count that runs past the table, found before a name is read.
void check_in_object(const facet_shader_desc& d, const void* where, const std::string& origin) {
    const void* home = object_of(where);
    // A descriptor or a table built at run time (tests, embedders, generated
    // schemas): nothing to compare with.
    if (!home || d.param_count == 0 || object_of(d.params) != home) return;
    for (uint32_t i = 0; i < d.param_count; ++i) {
        const facet_param_desc* p = d.params + i;
        if (object_of(p) != home || object_of(reinterpret_cast<const char*>(p + 1) - 1) != home ||
            (p->name && object_of(p->name) != home))
            refuse(ErrorCode::plugin_invalid, origin,
                   "parameter " + std::to_string(i) + " lies outside the plugin: param_count (" +
                       std::to_string(d.param_count) + ") runs past the end of its table");
    }
    if (!d.param_choices || object_of(d.param_choices) != home) return;
    for (uint32_t i = 0; i < d.param_count; ++i) {
        const char* const* entry = d.param_choices + i;
        if (object_of(entry) != home ||
            object_of(reinterpret_cast<const char*>(entry + 1) - 1) != home ||
            (*entry && object_of(*entry) != home))
            refuse(ErrorCode::plugin_invalid, origin,
                   "the choices of parameter " + std::to_string(i) +
                       " lie outside the plugin: param_choices is shorter than params");
    }
}

// The range and defaults of a number parameter: min <= max, neither NaN,
// and defaults within them.
void check_param_range(const facet_param_desc& p, const std::string& what,
                       const std::string& origin) {
    const int components = p.type == FACET_PARAM_INT ? 1 : param_float_count(p.type);
    if (components == 0) return;  // BOOL, TEXTURE: no range
    if (!(p.min_value <= p.max_value))
        refuse(ErrorCode::plugin_invalid, origin,
               what + " has the range " + std::to_string(p.min_value) + " .. " +
                   std::to_string(p.max_value) + " (min above max, or NaN)");
    for (int c = 0; c < components; ++c)
        if (!(p.default_value[c] >= p.min_value && p.default_value[c] <= p.max_value))
            refuse(ErrorCode::plugin_invalid, origin,
                   what + " has the default " + std::to_string(p.default_value[c]) +
                       " outside its range " + std::to_string(p.min_value) + " .. " +
                       std::to_string(p.max_value));
}

// The names of CHOICE parameter `p` in `choices` ("a|b|c"): at least one,
// none empty or given twice, and the default one of them.
void check_choices(const facet_param_desc& p, const char* choices, const std::string& what,
                   const std::string& origin) {
    if (!choices)
        refuse(ErrorCode::plugin_invalid, origin,
               what + " is a choice but param_choices gives it no names");
    const std::vector<std::string> names = choice_names(choices);
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i].empty())
            refuse(ErrorCode::plugin_invalid, origin,
                   what + " has an empty name among its choices '" + choices + "'");
        if (std::find(names.begin(), names.begin() + long(i), names[i]) != names.begin() + long(i))
            refuse(ErrorCode::plugin_invalid, origin,
                   what + " names the choice '" + names[i] + "' twice");
    }
    const float d = p.default_value[0];
    if (!(d >= 0.0f && d < float(names.size()) && d == std::floor(d)))
        refuse(ErrorCode::plugin_invalid, origin,
               what + " has the default " + std::to_string(d) + ", not the index of one of '" +
                   choices + "'");
}

// `d` is the host's copy of the descriptor at `where`.
void validate_params(const facet_shader_desc& d, const void* where, const std::string& origin) {
    if (d.param_count > FACET_MAX_PARAMS || d.params_size > FACET_MAX_PARAMS_SIZE)
        refuse(ErrorCode::plugin_invalid, origin,
               "parameter schema too large (" + std::to_string(d.param_count) + " parameters, " +
                   std::to_string(d.params_size) + " bytes)");
    if (d.param_count > 0 && !d.params)
        refuse(ErrorCode::plugin_invalid, origin, "param_count > 0 but no params table");
    check_in_object(d, where, origin);
    int textures = 0;
    for (uint32_t i = 0; i < d.param_count; ++i) {
        const facet_param_desc& p = d.params[i];
        const std::string what = "parameter " + std::to_string(i) + " ('" +
                                 (p.name ? p.name : "(null)") + "')";
        if (!p.name || !*p.name || !valid_param_type(p.type))
            refuse(ErrorCode::plugin_invalid, origin, what + " has no name or an unknown type");
        if (p.offset % 4 != 0 || p.offset > d.params_size ||
            param_bytes(p.type) > d.params_size - p.offset)
            refuse(ErrorCode::plugin_invalid, origin, what + " lies outside the parameter block");
        for (uint32_t j = 0; j < i; ++j) {
            const facet_param_desc& q = d.params[j];
            if (p.offset < q.offset + param_bytes(q.type) && q.offset < p.offset + param_bytes(p.type))
                refuse(ErrorCode::plugin_invalid, origin,
                       what + " overlaps parameter " + std::to_string(j) + " ('" + q.name +
                           "') in the parameter block");
        }
        if (p.type == FACET_PARAM_CHOICE)
            check_choices(p, d.param_choices ? d.param_choices[i] : nullptr, what, origin);
        else if (d.param_choices && d.param_choices[i])
            refuse(ErrorCode::plugin_invalid, origin, what + " has choices but is not a choice");
        else
            check_param_range(p, what, origin);
        if (p.type == FACET_PARAM_TEXTURE && d.kind == FACET_KIND_POST)
            refuse(ErrorCode::plugin_invalid, origin, what + ": a screen pass takes no textures");
        if (p.type == FACET_PARAM_TEXTURE) {
            ++textures;
            // -1: one only the shader samples (ABI 1.7), as a cube map is.
            const bool unsampled = p.uv_varying == -1 && d.abi_minor >= 7;
            if (!unsampled && (p.uv_varying < 0 || uint32_t(p.uv_varying) >= d.varying_count ||
                               d.varyings[p.uv_varying].components < 2))
                refuse(ErrorCode::plugin_invalid, origin,
                       what + " names no 2-component UV varying");
            if ((p.flags & FACET_PARAM_CUBE) && !unsampled)
                refuse(ErrorCode::plugin_invalid, origin,
                       what + " is a cube map: its UV varying must be -1");
        } else if (p.flags & FACET_PARAM_CUBE) {
            refuse(ErrorCode::plugin_invalid, origin, what + " is a cube map but not a texture");
        }
        for (uint32_t j = 0; j < i; ++j)
            if (std::strcmp(d.params[j].name, p.name) == 0)
                refuse(ErrorCode::plugin_invalid, origin, what + " is declared twice");
        // A parameter that says whether a material uses a pass must be one
        // the host can read that way, and say it for a pass the shader needs.
        if ((p.flags & FACET_PARAM_USES_SHADOWS) &&
            (p.type != FACET_PARAM_BOOL || !(d.needs & FACET_NEED_SHADOW_MAP)))
            refuse(ErrorCode::plugin_invalid, origin,
                   what + " says whether shadows are used, but it is not a bool or the shader "
                          "does not need FACET_NEED_SHADOW_MAP");
        if ((p.flags & FACET_PARAM_USES_AO) &&
            ((p.type != FACET_PARAM_BOOL && p.type != FACET_PARAM_FLOAT) ||
             !(d.needs & FACET_NEED_AO)))
            refuse(ErrorCode::plugin_invalid, origin,
                   what + " says whether AO is used, but it is not a bool or a float or the "
                          "shader does not need FACET_NEED_AO");
        if ((p.flags & FACET_PARAM_USES_DISCARD) &&
            ((p.type != FACET_PARAM_BOOL && p.type != FACET_PARAM_FLOAT) ||
             !(d.needs & FACET_NEED_DISCARD)))
            refuse(ErrorCode::plugin_invalid, origin,
                   what + " says whether the material discards, but it is not a bool or a "
                          "float or the shader does not need FACET_NEED_DISCARD");
    }
    if (textures > FACET_MAX_TEXTURES)
        refuse(ErrorCode::plugin_invalid, origin, "too many texture parameters");
}

// Why `path` is not a whole ELF-64 file, or nothing if it is.
std::optional<std::string> elf_incomplete(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    Elf64_Ehdr eh{};
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    if (ec) return "cannot read it: " + ec.message();
    if (!in.read(reinterpret_cast<char*>(&eh), sizeof eh) ||
        std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 || eh.e_ident[EI_CLASS] != ELFCLASS64)
        return "not a 64-bit ELF shared library";
    uint64_t needed = uint64_t(eh.e_shoff) + uint64_t(eh.e_shnum) * eh.e_shentsize;
    needed = std::max<uint64_t>(needed, eh.e_phoff + uint64_t(eh.e_phnum) * eh.e_phentsize);
    for (int i = 0; i < eh.e_phnum && needed <= size; ++i) {
        Elf64_Phdr ph{};
        in.seekg(std::streamoff(eh.e_phoff + uint64_t(i) * eh.e_phentsize));
        if (!in.read(reinterpret_cast<char*>(&ph), sizeof ph)) break;
        if (ph.p_type == PT_LOAD) needed = std::max<uint64_t>(needed, ph.p_offset + ph.p_filesz);
    }
    if (needed > size)
        return "file is truncated (" + std::to_string(size) + " bytes, its headers need " +
               std::to_string(needed) + "); is it still being written?";
    return std::nullopt;
}

// dlopen() maps a library's segments straight from the file; a segment
// that runs past the end of a truncated file (a compiler still writing it)
// faults with SIGBUS on first touch. Refuse such a file before dlopen.
void check_elf_complete(const fs::path& path, const std::string& origin) {
    if (const std::optional<std::string> why = elf_incomplete(path))
        refuse(ErrorCode::plugin_load_failed, origin, *why);
}

// The host's copy of descriptor `d`: the fields its ABI version has, the
// others zero. (A 1.2 or 1.3 descriptor's struct_size covers 4 bytes of
// padding after `flags`, where 1.4 put `kind`: what they hold is not read.)
facet_shader_desc host_copy(const facet_shader_desc* d) {
    facet_shader_desc c{};
    std::memcpy(&c, d, std::min<size_t>(d->struct_size, sizeof c));
    if (d->abi_minor < 4) {
        c.kind = FACET_KIND_SHADER;
        c.post = nullptr;
        c.param_choices = nullptr;
    }
    if (d->abi_minor < 5) c.conditional_varyings = c.varyings_condition = 0;
    return c;
}

}  // namespace

namespace {

// v1.5: the conditional varyings are some of the last ones, their condition
// a TEXTURE or BOOL parameter, and a texture read at one of them is the
// condition itself (else it would be sampled at zeros).
void validate_conditional_varyings(const facet_shader_desc& c, const std::string& origin) {
    if (c.conditional_varyings == 0) return;
    if (c.conditional_varyings > c.varying_count)
        refuse(ErrorCode::plugin_invalid, origin,
               std::to_string(c.conditional_varyings) + " conditional varyings of " +
                   std::to_string(c.varying_count));
    if (c.varyings_condition >= c.param_count ||
        (c.params[c.varyings_condition].type != FACET_PARAM_TEXTURE &&
         c.params[c.varyings_condition].type != FACET_PARAM_BOOL))
        refuse(ErrorCode::plugin_invalid, origin,
               "the conditional varyings' condition is not a texture or bool parameter");
    const uint32_t first = c.varying_count - c.conditional_varyings;
    for (uint32_t i = 0; i < c.param_count; ++i) {
        const facet_param_desc& p = c.params[i];
        if (p.type == FACET_PARAM_TEXTURE && p.uv_varying >= 0 && uint32_t(p.uv_varying) >= first &&
            i != c.varyings_condition)
            refuse(ErrorCode::plugin_invalid, origin,
                   "texture '" + std::string(p.name) + "' reads its UV from a conditional "
                   "varying, and is not their condition");
    }
}

}  // namespace

void validate_descriptor(const facet_shader_desc* d, const std::string& origin) {
    if (!d) refuse(ErrorCode::plugin_invalid, origin, "the entry point returned no descriptor");
    if (d->abi_major != FACET_ABI_MAJOR)
        refuse(ErrorCode::plugin_abi_mismatch, origin,
               "built for ABI " + std::to_string(d->abi_major) + "." +
                   std::to_string(d->abi_minor) + ", this host speaks ABI " +
                   std::to_string(FACET_ABI_MAJOR) + "." + std::to_string(FACET_ABI_MINOR) +
                   "; rebuild the plugin against this facet SDK");
    if (d->struct_size < FACET_SHADER_DESC_V1_0_SIZE)
        refuse(ErrorCode::plugin_struct_size, origin,
               "descriptor is " + std::to_string(d->struct_size) + " bytes, ABI " +
                   std::to_string(FACET_ABI_MAJOR) + ".0 needs at least " +
                   std::to_string(FACET_SHADER_DESC_V1_0_SIZE));
    if (d->abi_minor <= FACET_ABI_MINOR && d->struct_size > sizeof(facet_shader_desc))
        refuse(ErrorCode::plugin_struct_size, origin,
               "descriptor is " + std::to_string(d->struct_size) + " bytes, but ABI " +
                   std::to_string(d->abi_major) + "." + std::to_string(d->abi_minor) +
                   " defines " + std::to_string(sizeof(facet_shader_desc)));
    const facet_shader_desc c = host_copy(d);
    if (!c.name || !*c.name)
        refuse(ErrorCode::plugin_invalid, origin, "the descriptor has no name");
    if (c.kind == FACET_KIND_SHADER) {
        if (!c.vertex || !c.fragment)
            refuse(ErrorCode::plugin_invalid, origin, "missing vertex or fragment function");
        if (c.post)
            refuse(ErrorCode::plugin_invalid, origin, "a shader with a post function");
    } else if (c.kind == FACET_KIND_POST) {
        if (!c.post)
            refuse(ErrorCode::plugin_invalid, origin, "a screen pass without its post function");
        if (c.vertex || c.fragment || c.fragment_avx2 || c.fragment_avx512 || c.varying_count ||
            c.needs || c.flags)
            refuse(ErrorCode::plugin_invalid, origin,
                   "a screen pass has no vertex or fragment functions, varyings, needs or flags");
    } else {
        refuse(ErrorCode::plugin_invalid, origin,
               "unknown plugin kind " + std::to_string(c.kind) + " (this host knows 0, a shader, "
               "and 1, a screen pass)");
    }
    if (c.needs & ~kSupportedNeeds)
        refuse(ErrorCode::plugin_invalid, origin,
               "needs inputs this host cannot provide (needs bits 0x" +
                   to_hex(c.needs & ~kSupportedNeeds) + ")");
    validate_varyings(c, origin);
    validate_params(c, d, origin);
    validate_conditional_varyings(c, origin);
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

// ---- ShaderPlugin ------------------------------------------------------------

std::shared_ptr<ShaderPlugin> ShaderPlugin::load(const fs::path& path,
                                                 std::string_view expected_name,
                                                 const fs::path& private_copy) {
    const std::string origin = path.string();
    require_regular_file(path);
    std::shared_ptr<ShaderPlugin> plugin(new ShaderPlugin);
    plugin->origin_ = origin;
    fs::path file = path;
    if (!private_copy.empty()) {
        std::error_code ec;
        fs::copy_file(path, private_copy, fs::copy_options::overwrite_existing, ec);
        if (ec) refuse(ErrorCode::plugin_load_failed, origin, "cannot copy: " + ec.message());
        plugin->private_copy_ = file = private_copy;  // deleted by the destructor
    }
    check_elf_complete(file, origin);
    // RTLD_LOCAL keeps each plugin's symbols to itself; RTLD_NOW reports a
    // missing symbol here rather than at the first draw.
    {
        const InPlugin loading(plugin.get(), PluginEntry::load);  // its static constructors run
        plugin->handle_ = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    }
    if (!plugin->handle_) refuse(ErrorCode::plugin_load_failed, origin, dlerror());
    void* handle = plugin->handle_;
    auto entry =
        reinterpret_cast<facet_shader_entry_fn>(dlsym(handle, FACET_SHADER_ENTRY_SYMBOL));
    if (!entry)
        refuse(ErrorCode::plugin_no_entry, origin,
               "no exported symbol '" FACET_SHADER_ENTRY_SYMBOL "' (use FACET_SHADER(...))");
    const facet_shader_desc* desc = nullptr;
    {
        const InPlugin in_entry(plugin.get(), PluginEntry::entry_point);
        desc = entry();
    }
    validate_descriptor(desc, origin);
    if (!expected_name.empty() && expected_name != desc->name)
        refuse(ErrorCode::plugin_invalid, origin,
               "file is named '" + std::string(expected_name) + "' but the shader calls itself '" +
                   desc->name + "'");
    plugin->adopt(desc);
    spdlog::debug("loaded {} '{}' {} from {}", plugin->is_post() ? "screen pass" : "shader",
                 plugin->name_,
                 desc->version ? desc->version : "", origin);
    return plugin;
}

std::shared_ptr<ShaderPlugin> ShaderPlugin::from_descriptor(const facet_shader_desc* desc,
                                                            std::string origin) {
    validate_descriptor(desc, origin);
    std::shared_ptr<ShaderPlugin> plugin(new ShaderPlugin);
    plugin->origin_ = std::move(origin);
    plugin->adopt(desc);
    return plugin;
}

// Keeps a host-owned copy of the descriptor (zero past the plugin's
// struct_size) and the per-float tables every draw uses.
void ShaderPlugin::adopt(const facet_shader_desc* desc) {
    desc_ = host_copy(desc);
    name_ = desc_.name;
    int first_float[FACET_MAX_VARYINGS] = {};
    varying_floats_ = 0;
    for (uint32_t v = 0; v < desc_.varying_count; ++v) {
        first_float[v] = int(varying_floats_);
        if (v == desc_.varying_count - desc_.conditional_varyings)
            unconditional_floats_ = varying_floats_;
        for (uint32_t c = 0; c < desc_.varyings[v].components; ++c)
            float_interpolation_[varying_floats_++] = uint8_t(desc_.varyings[v].interpolation);
    }
    if (desc_.conditional_varyings == 0) unconditional_floats_ = varying_floats_;
    texture_count_ = 0;
    for (uint32_t i = 0; i < desc_.param_count; ++i)
        if (desc_.params[i].type == FACET_PARAM_TEXTURE) {
            const int32_t uv = desc_.params[i].uv_varying;  // -1: only the shader samples it
            texture_uv_float_[texture_count_++] = uv >= 0 ? first_float[uv] : -1;
        }
}

ShaderPlugin::~ShaderPlugin() {
    if (handle_) {
        const InPlugin unloading(this, PluginEntry::unload);  // its static destructors run
        dlclose(handle_);
    }
    std::error_code ec;
    if (!private_copy_.empty()) fs::remove(private_copy_, ec);
}

uint32_t ShaderPlugin::read_floats(const void* params) const {
    if (desc_.conditional_varyings == 0 || !params) return varying_floats_;
    int32_t condition;  // TEXTURE and BOOL are both an int32
    std::memcpy(&condition,
                static_cast<const unsigned char*>(params) + desc_.params[desc_.varyings_condition].offset,
                sizeof condition);
    return condition ? varying_floats_ : unconditional_floats_;
}

const facet_param_desc* ShaderPlugin::find_param(std::string_view name) const {
    for (uint32_t i = 0; i < desc_.param_count; ++i)
        if (name == desc_.params[i].name) return &desc_.params[i];
    return nullptr;
}

int ShaderPlugin::texture_slot(const facet_param_desc& param) const {
    int slot = 0;
    for (uint32_t i = 0; i < desc_.param_count; ++i) {
        if (&desc_.params[i] == &param) return param.type == FACET_PARAM_TEXTURE ? slot : -1;
        slot += desc_.params[i].type == FACET_PARAM_TEXTURE;
    }
    return -1;
}

std::string ShaderPlugin::describe_params() const {
    if (desc_.param_count == 0) return "(no parameters)";
    std::string out;
    for (uint32_t i = 0; i < desc_.param_count; ++i) {
        if (i) out += ", ";
        out += desc_.params[i].name;
        out += " (";
        out += param_type_name(desc_.params[i].type);
        out += ")";
    }
    return out;
}

// ---- PluginRegistry ----------------------------------------------------------

namespace {

std::vector<fs::path> env_plugin_path() {
    std::vector<fs::path> out;
    const char* env = std::getenv("FACET_PLUGIN_PATH");
    if (!env) return out;
    std::stringstream ss(env);
    for (std::string item; std::getline(ss, item, ':');)
        if (!item.empty()) out.emplace_back(item);
    return out;
}

std::string join_paths(const std::vector<fs::path>& paths) {
    std::string out;
    for (const fs::path& p : paths) out += (out.empty() ? "" : ", ") + p.string();
    return out.empty() ? "(none)" : out;
}

}  // namespace

PluginRegistry::PluginRegistry()
    : build_paths_(built_in_plugin_dirs()), env_paths_(env_plugin_path()) {}

PluginRegistry::PluginRegistry(std::vector<fs::path> search_path)
    : build_paths_(std::move(search_path)) {}

void PluginRegistry::add_scene_path(const fs::path& folder) {
    for (const fs::path& p : scene_paths_)
        if (p == folder) return;
    scene_paths_.push_back(folder);
}

std::vector<fs::path> PluginRegistry::search_path() const {
    std::vector<fs::path> all = build_paths_;
    all.insert(all.end(), scene_paths_.begin(), scene_paths_.end());
    all.insert(all.end(), env_paths_.begin(), env_paths_.end());
    return all;
}

std::vector<fs::path> PluginRegistry::files_named(const std::string& name) const {
    std::vector<fs::path> found;
    for (const fs::path& dir : search_path()) {
        fs::path candidate = dir / (name + ".so");
        std::error_code ec;
        if (!fs::is_regular_file(candidate, ec)) continue;
        // A folder named twice (FACET_PLUGIN_PATH and the build's) is one file.
        const bool seen = std::any_of(found.begin(), found.end(), [&](const fs::path& f) {
            std::error_code e;
            return fs::equivalent(f, candidate, e);
        });
        if (!seen) found.push_back(std::move(candidate));
    }
    return found;
}

fs::path PluginRegistry::locate(const std::string& name) const {
    std::vector<fs::path> found = files_named(name);
    return found.empty() ? fs::path() : found.front();
}

std::vector<fs::path> PluginRegistry::shadowed(const std::string& name) const {
    std::vector<fs::path> found = files_named(name);
    if (!found.empty()) found.erase(found.begin());  // the one locate() finds
    return found;
}

PluginRegistry::~PluginRegistry() {
    // Loaded copies may outlive the registry; removing their files is safe.
    std::error_code ec;
    if (!private_dir_.empty()) fs::remove_all(private_dir_, ec);
}

namespace {

constexpr std::string_view kPrivatePrefix = "facet-plugins-";

// The process id in a private copies' folder name "facet-plugins-PID-N";
// 0 for any other name.
pid_t private_folder_owner(const std::string& name) {
    unsigned long pid = 0, n = 0;
    int end = 0;
    if (name.rfind(kPrivatePrefix, 0) != 0 ||
        std::sscanf(name.c_str() + kPrivatePrefix.size(), "%lu-%lu%n", &pid, &n, &end) != 2 ||
        size_t(end) != name.size() - kPrivatePrefix.size() || pid == 0 || pid > 0x7fffffff)
        return 0;
    return pid_t(pid);
}

// Removes this user's private copies' folders whose process `matches`;
// errors (a race with another process) leave a folder alone. (A process
// in another PID namespace that shares the temp folder, under the same
// user, would look dead from here: containers should not share /tmp.)
template <class Matches>
void remove_private_folders(Matches&& matches) {
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(fs::temp_directory_path(ec), ec)) {
        const pid_t owner = private_folder_owner(e.path().filename().string());
        struct stat info {};
        if (!owner || lstat(e.path().c_str(), &info) != 0 || info.st_uid != getuid() ||
            !S_ISDIR(info.st_mode) || !matches(owner))
            continue;
        std::error_code ignored;
        fs::remove_all(e.path(), ignored);
    }
}

bool process_runs(pid_t pid) { return kill(pid, 0) == 0 || errno == EPERM; }

}  // namespace

void remove_private_plugin_copies() {
    const pid_t self = getpid();
    remove_private_folders([&](pid_t owner) { return owner == self; });
}

fs::path PluginRegistry::next_private_copy(const std::string& name) {
    if (private_dir_.empty()) {
        static std::atomic<unsigned> registries{0};
        remove_private_folders([](pid_t owner) { return !process_runs(owner); });
        private_dir_ = fs::temp_directory_path() /
                       (std::string(kPrivatePrefix) + std::to_string(getpid()) + "-" +
                        std::to_string(registries++));
        std::error_code ec;
        fs::create_directories(private_dir_, ec);
        if (ec)
            throw Error(ErrorCode::plugin_load_failed,
                        "cannot make a folder for private copies: " + ec.message(),
                        private_dir_.string());
    }
    return private_dir_ / (name + "." + std::to_string(++generation_) + ".so");
}

std::shared_ptr<ShaderPlugin> PluginRegistry::load_fresh(const std::string& name) {
    const bool plain = !name.empty() && name.find_first_of("/\\") == std::string::npos;
    const fs::path file = plain ? locate(name) : fs::path();
    spdlog::debug("shader '{}': searched {}: {}", name, join_paths(search_path()),
                  file.empty() ? "not found" : file.string());
    if (file.empty())
        throw Error(ErrorCode::unknown_shader,
                    "'" + name + "': no " + name + ".so in " + join_paths(search_path()));
    return ShaderPlugin::load(file, name, next_private_copy(name));
}

std::shared_ptr<ShaderPlugin> PluginRegistry::get(const std::string& name) {
    if (auto it = loaded_.find(name); it != loaded_.end()) return it->second;
    std::shared_ptr<ShaderPlugin> plugin = load_fresh(name);
    for (const fs::path& hidden : shadowed(name))
        spdlog::warn("shader '{}': {} is used; {}, of the same name and later on the search "
                     "path, is not",
                     name, plugin->origin(), hidden.string());
    loaded_.emplace(name, plugin);
    return plugin;
}

void PluginRegistry::add(std::shared_ptr<ShaderPlugin> plugin) {
    loaded_[plugin->name()] = std::move(plugin);
}

// ---- fault reports -------------------------------------------------------------

thread_local PluginCall t_plugin_call;

namespace {

constexpr int kFaultSignals[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};
struct sigaction g_before[NSIG];

const char* entry_text(PluginEntry e) {
    switch (e) {
        case PluginEntry::load: return "while loading (its static constructors)";
        case PluginEntry::entry_point: return "in its entry point (" FACET_SHADER_ENTRY_SYMBOL ")";
        case PluginEntry::vertex: return "in its vertex function";
        case PluginEntry::fragment: return "in its fragment function";
        case PluginEntry::post: return "in its post function";
        case PluginEntry::unload: return "while unloading (its static destructors)";
        default: return "";
    }
}

const char* signal_text(int sig) {
    switch (sig) {
        case SIGSEGV: return "SIGSEGV, invalid memory access";
        case SIGBUS: return "SIGBUS, bus error";
        case SIGILL: return "SIGILL, illegal instruction";
        case SIGFPE: return "SIGFPE, arithmetic error";
        case SIGABRT: return "SIGABRT, aborted";
        default: return "a fatal signal";
    }
}

// Only async-signal-safe calls from here on: write(), sigaction(), raise().
void on_fault(int sig, siginfo_t* info, void*) {
    const PluginCall call = t_plugin_call;
    if (call.plugin) {
        char text[1024];
        size_t used = 0;
        auto add = [&](const char* s) {
            while (*s && used + 1 < sizeof text) text[used++] = *s++;
        };
        add("facet: shader plugin ");
        if (call.plugin->name().empty()) {  // not known before its entry point returns
            add(call.plugin->origin().c_str());
        } else {
            add("'");
            add(call.plugin->name().c_str());
            add("' (");
            add(call.plugin->origin().c_str());
            add(")");
        }
        add(" crashed ");
        add(entry_text(call.entry));
        add(": ");
        add(signal_text(sig));
        add("\n");
        for (size_t done = 0; done < used;) {
            const ssize_t n = write(STDERR_FILENO, text + done, used - done);
            if (n <= 0) break;
            done += size_t(n);
        }
    }
    // The earlier handler takes it from here: a fault repeats when its
    // instruction runs again; a signal sent by a call (abort, raise, kill)
    // is sent again, and arrives when this handler returns.
    sigaction(sig, &g_before[sig], nullptr);
    if (info->si_code <= 0) raise(sig);
}

}  // namespace

void report_plugin_faults() {
    // A stack of its own for this thread (the pool's workers make theirs),
    // so that a stack overflow in a plugin can still be reported.
    static const SignalStack stack;
    struct sigaction action {};
    action.sa_sigaction = on_fault;
    action.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&action.sa_mask);
    for (const int sig : kFaultSignals) sigaction(sig, &action, &g_before[sig]);
}

bool plugin_file_complete(const fs::path& path) { return !elf_incomplete(path); }

}  // namespace facet
