/* The layout of the plugin ABI's records, which tests/abi_c_check.c
 * reports as a C compiler sees it and tests/test_plugin.cpp compares with
 * what the C++ compiler sees. */
#ifndef FACET_TEST_ABI_LAYOUT_H
#define FACET_TEST_ABI_LAYOUT_H

#include <facet/shader_abi.h>

/* Sizes and offsets of every record: X(value) for each. */
#define FACET_ABI_LAYOUT(X)                                                        \
    X(sizeof(facet_plugin_desc)) X(offsetof(facet_plugin_desc, struct_size))       \
    X(offsetof(facet_plugin_desc, name)) X(offsetof(facet_plugin_desc, schema))    \
    X(offsetof(facet_plugin_desc, shader)) X(offsetof(facet_plugin_desc, pass))    \
    X(sizeof(facet_schema)) X(offsetof(facet_schema, params))                      \
    X(offsetof(facet_schema, choices)) X(sizeof(facet_param_desc))                 \
    X(offsetof(facet_param_desc, uv_varying)) X(offsetof(facet_param_desc, doc))   \
    X(sizeof(facet_shader_desc)) X(offsetof(facet_shader_desc, varyings))          \
    X(offsetof(facet_shader_desc, vertex)) X(offsetof(facet_shader_desc, fragments)) \
    X(sizeof(facet_fragment_entry)) X(offsetof(facet_fragment_entry, fragment))    \
    X(sizeof(facet_varying_desc)) X(sizeof(facet_light))                           \
    X(offsetof(facet_light, spot_cos_outer)) X(sizeof(facet_shadow_map))           \
    X(offsetof(facet_shadow_map, texel_size)) X(offsetof(facet_shadow_map, texels)) \
    X(offsetof(facet_shadow_map, tiles)) X(sizeof(facet_shadow))                   \
    X(offsetof(facet_shadow, maps)) X(sizeof(facet_draw))                          \
    X(offsetof(facet_draw, model_view_projection)) X(offsetof(facet_draw, time))   \
    X(offsetof(facet_draw, lights)) X(offsetof(facet_draw, shadows))               \
    X(sizeof(facet_vertex_batch)) X(offsetof(facet_vertex_batch, clip_position))   \
    X(offsetof(facet_vertex_batch, varying_floats)) X(sizeof(facet_fragment_batch)) \
    X(offsetof(facet_fragment_batch, coord)) X(offsetof(facet_fragment_batch, mask)) \
    X(offsetof(facet_fragment_batch, texels)) X(offsetof(facet_fragment_batch, color)) \
    X(sizeof(facet_pass_frame)) X(offsetof(facet_pass_frame, color))               \
    X(offsetof(facet_pass_frame, time)) X(sizeof(facet_pass_desc))                 \
    X(sizeof(facet_host)) X(offsetof(facet_host, extension))                       \
    X(sizeof(facet_textures_service)) X(offsetof(facet_textures_service, sample))  \
    X(sizeof(facet_pass_service)) X(offsetof(facet_pass_service, scratch))

#endif
