// ShaderPlugin (facet/plugin.hpp): loading a plugin's library, checking its
// descriptor (descriptor.hpp) and keeping host-owned copies of it.
#include "facet/plugin.hpp"

#include "facet/error.hpp"
#include "base/files.hpp"
#include "plugin/descriptor.hpp"
#include "plugin/elf_check.hpp"
#include "plugin/plugin_calls.hpp"

#include <spdlog/spdlog.h>

#include <dlfcn.h>
#include <link.h>

#include <algorithm>
#include <cstring>
#include <tuple>
#include <optional>

namespace facet {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void refuse(ErrorCode code, const std::string& origin, const std::string& why) {
    throw Error(code, why, origin);
}

// Where a loaded library's executable segments are: from its first to the
// end of its last ({0, 0} if not found). The watchdog returns a stalled
// call only from there (watchdog.cpp).
std::pair<uintptr_t, uintptr_t> code_range(void* handle) {
    struct Search {
        const link_map* library = nullptr;
        uintptr_t begin = 0, end = 0;
    } search;
    if (dlinfo(handle, RTLD_DI_LINKMAP, &search.library) != 0 || !search.library) return {0, 0};
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* data) {
            auto& s = *static_cast<Search*>(data);
            if (info->dlpi_addr != s.library->l_addr ||
                std::strcmp(info->dlpi_name, s.library->l_name) != 0)
                return 0;
            for (int i = 0; i < info->dlpi_phnum; ++i) {
                const ElfW(Phdr)& ph = info->dlpi_phdr[i];
                if (ph.p_type != PT_LOAD || !(ph.p_flags & PF_X)) continue;
                const uintptr_t begin = info->dlpi_addr + ph.p_vaddr;
                s.begin = s.begin ? std::min(s.begin, begin) : begin;
                s.end = std::max(s.end, uintptr_t(begin + ph.p_memsz));
            }
            return 1;
        },
        &search);
    return {search.begin, search.end};
}

// dlopen() maps a library's segments straight from the file; a segment
// that runs past the end of a truncated file (a compiler still writing it)
// faults with SIGBUS on first touch. Refuse such a file before dlopen, and
// one built for another machine, or not a shared library, with the cause
// (dlopen's own message for them does not say it).
void check_elf(const fs::path& path, const std::string& origin) {
    if (std::optional<std::string> why = elf_incomplete(path))
        refuse(ErrorCode::plugin_load_failed, origin, *why);
    if (std::optional<std::string> why = elf_foreign(path))
        refuse(ErrorCode::plugin_load_failed, origin, "it is " + *why);
}

// A library with no facet_plugin_entry: an ABI 1 plugin (which exported
// facet_shader_entry, its descriptor starting with the ABI it was built
// for), or no plugin at all.
[[noreturn]] void refuse_without_entry(const ShaderPlugin& plugin, void* handle,
                                       const std::string& origin) {
    using Abi1Entry = const uint16_t* (*)(void);  // abi_major, abi_minor first
    if (auto old = reinterpret_cast<Abi1Entry>(dlsym(handle, FACET_ABI1_ENTRY_SYMBOL))) {
        const uint16_t* version = nullptr;
        {
            const InPlugin in_entry(&plugin, PluginEntry::entry_point);
            version = old();
        }
        const std::string abi = version ? std::to_string(version[0]) + "." +
                                              std::to_string(version[1])
                                        : std::string("1");
        refuse(ErrorCode::plugin_abi_mismatch, origin,
               "built for ABI " + abi + " (it exports '" FACET_ABI1_ENTRY_SYMBOL
               "'); this host speaks ABI " + std::to_string(FACET_ABI_MAJOR) + "." +
                   std::to_string(FACET_ABI_MINOR) +
                   ": rebuild the plugin against this facet SDK (facet_add_shader() in CMake)");
    }
    refuse(ErrorCode::plugin_no_entry, origin,
           "no exported symbol '" FACET_PLUGIN_ENTRY_SYMBOL "' (use FACET_SHADER(...) or "
           "FACET_POST(...))");
}

}  // namespace

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
    check_elf(file, origin);
    // RTLD_LOCAL keeps each plugin's symbols to itself; RTLD_NOW reports a
    // missing symbol here rather than at the first draw.
    {
        const InPlugin loading(plugin.get(), PluginEntry::load);  // its static constructors run
        plugin->handle_ = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    }
    if (!plugin->handle_) refuse(ErrorCode::plugin_load_failed, origin, dlerror());
    void* handle = plugin->handle_;
    std::tie(plugin->code_begin_, plugin->code_end_) = code_range(handle);
    auto entry =
        reinterpret_cast<facet_plugin_entry_fn>(dlsym(handle, FACET_PLUGIN_ENTRY_SYMBOL));
    if (!entry) refuse_without_entry(*plugin, handle, origin);
    const facet_plugin_desc* desc = nullptr;
    {
        const InPlugin in_entry(plugin.get(), PluginEntry::entry_point);
        desc = entry();
    }
    validate_descriptor(desc, origin);
    if (!expected_name.empty() && expected_name != desc->name)
        refuse(ErrorCode::plugin_invalid, origin,
               "file is named '" + std::string(expected_name) + "' but the plugin calls itself '" +
                   desc->name + "'");
    plugin->adopt(desc);
    spdlog::debug("loaded {} '{}' {} from {}", plugin->is_post() ? "screen pass" : "shader",
                 plugin->name_,
                 desc->version ? desc->version : "", origin);
    return plugin;
}

std::shared_ptr<ShaderPlugin> ShaderPlugin::from_descriptor(const facet_plugin_desc* desc,
                                                            std::string origin) {
    validate_descriptor(desc, origin);
    std::shared_ptr<ShaderPlugin> plugin(new ShaderPlugin);
    plugin->origin_ = std::move(origin);
    plugin->adopt(desc);
    return plugin;
}

// Keeps host-owned copies of the descriptor's records (zero past each
// one's struct_size), the fragment function each path calls, and the
// per-float tables every draw uses.
void ShaderPlugin::adopt(const facet_plugin_desc* desc) {
    const DescriptorCopy c = copy_descriptor(*desc);
    desc_ = c.plugin;
    shader_ = c.shader;
    pass_ = c.pass.run;
    name_ = desc_.name;
    adopt_fragments();
    int first_float[FACET_MAX_VARYINGS] = {};
    varying_floats_ = 0;
    for (uint32_t v = 0; v < shader_.varying_count; ++v) {
        first_float[v] = int(varying_floats_);
        if (v == shader_.varying_count - shader_.conditional_varyings)
            unconditional_floats_ = varying_floats_;
        for (uint32_t k = 0; k < shader_.varyings[v].components; ++k)
            float_interpolation_[varying_floats_++] = uint8_t(shader_.varyings[v].interpolation);
    }
    if (shader_.conditional_varyings == 0) unconditional_floats_ = varying_floats_;
    texture_count_ = 0;
    for (uint32_t i = 0; i < schema().param_count; ++i)
        if (schema().params[i].type == FACET_PARAM_TEXTURE) {
            const int32_t uv = schema().params[i].uv_varying;  // -1: only the shader samples it
            texture_uv_float_[texture_count_++] = uv >= 0 ? first_float[uv] : -1;
        }
    second_uv_float_ = shader_.second_uv > 0 ? first_float[shader_.second_uv - 1] : -1;
}

// Each path's fragment function: the entry of the widest instruction set
// the path allows (validate_descriptor made sure of the baseline's).
void ShaderPlugin::adopt_fragments() {
    facet_fragment_fn by_isa[FACET_ISA_X86_64_V4 + 1] = {};
    for (uint32_t i = 0; i < shader_.fragment_count; ++i)
        if (shader_.fragments[i].isa <= FACET_ISA_X86_64_V4)
            by_isa[shader_.fragments[i].isa] = shader_.fragments[i].fragment;
    fragment_[int(Isa::portable)] = by_isa[FACET_ISA_BASELINE];
    fragment_[int(Isa::avx2)] = by_isa[FACET_ISA_X86_64_V3] ? by_isa[FACET_ISA_X86_64_V3]
                                                            : fragment_[int(Isa::portable)];
    fragment_[int(Isa::avx512)] = by_isa[FACET_ISA_X86_64_V4] ? by_isa[FACET_ISA_X86_64_V4]
                                                              : fragment_[int(Isa::avx2)];
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
    if (shader_.conditional_varyings == 0) return varying_floats_;
    if (!params) return unconditional_floats_;  // the plugin sees zeros: no condition holds
    const auto set = [&](uint32_t param) {
        int32_t value;  // TEXTURE and BOOL are both an int32
        std::memcpy(&value, static_cast<const unsigned char*>(params) + schema().params[param].offset,
                    sizeof value);
        return value != 0;
    };
    const bool read = set(shader_.varyings_condition) ||
                      (shader_.varyings_condition_also > 0 && set(shader_.varyings_condition_also - 1));
    return read ? varying_floats_ : unconditional_floats_;
}

const facet_param_desc* ShaderPlugin::find_param(std::string_view name) const {
    for (uint32_t i = 0; i < schema().param_count; ++i)
        if (name == schema().params[i].name) return &schema().params[i];
    return nullptr;
}

int ShaderPlugin::texture_slot(const facet_param_desc& param) const {
    int slot = 0;
    for (uint32_t i = 0; i < schema().param_count; ++i) {
        if (&schema().params[i] == &param) return param.type == FACET_PARAM_TEXTURE ? slot : -1;
        slot += schema().params[i].type == FACET_PARAM_TEXTURE;
    }
    return -1;
}

std::string ShaderPlugin::describe_params() const {
    if (schema().param_count == 0) return "(no parameters)";
    std::string out;
    for (uint32_t i = 0; i < schema().param_count; ++i) {
        if (i) out += ", ";
        out += schema().params[i].name;
        out += " (";
        out += param_type_name(schema().params[i].type);
        out += ")";
    }
    return out;
}

}  // namespace facet
