// The host's copy of a plugin's descriptor (shader_abi.h): each record
// copied up to its struct_size, the fields past it zero, so that the host
// reads a plugin of an older minor version as its own, and one of a newer
// minor version up to what it knows.
#pragma once

#include <facet/shader_abi.h>

#include <algorithm>
#include <cstddef>
#include <cstring>

namespace facet {

// ABI 2.0's record sizes: the least a host of ABI 2 accepts, since later
// minor versions only append.
constexpr size_t kPluginDesc20Size = offsetof(facet_plugin_desc, pass) + sizeof(void*);
constexpr size_t kShaderDesc20Size = offsetof(facet_shader_desc, fragments) + sizeof(void*);
constexpr size_t kPassDesc20Size = offsetof(facet_pass_desc, run) + sizeof(void*);

template <class T>
T host_copy(const T& record, uint32_t struct_size) {
    T copy{};
    std::memcpy(&copy, &record, std::min<size_t>(struct_size, sizeof copy));
    return copy;
}

struct DescriptorCopy {
    facet_plugin_desc plugin{};
    facet_shader_desc shader{};  // zeros for a screen pass
    facet_pass_desc pass{};      // zeros for a shader
};

// Copies a descriptor validate_descriptor() accepted.
inline DescriptorCopy copy_descriptor(const facet_plugin_desc& d) {
    DescriptorCopy c;
    c.plugin = host_copy(d, d.struct_size);
    if (d.shader) c.shader = host_copy(*d.shader, d.shader->struct_size);
    if (d.pass) c.pass = host_copy(*d.pass, d.pass->struct_size);
    return c;
}

}  // namespace facet
