/* Compiles the plugin ABI header as strict C (-std=c99 -pedantic -Werror)
 * and reports its layout so the C++ side can compare. */
#include <facet/shader_abi.h>

size_t facet_c_sizeof_shader_desc(void) { return sizeof(facet_shader_desc); }
size_t facet_c_sizeof_fragment_batch(void) { return sizeof(facet_fragment_batch); }
size_t facet_c_sizeof_draw(void) { return sizeof(facet_draw); }
size_t facet_c_sizeof_param_desc(void) { return sizeof(facet_param_desc); }
size_t facet_c_sizeof_light(void) { return sizeof(facet_light); }
size_t facet_c_desc_v1_0_size(void) { return FACET_SHADER_DESC_V1_0_SIZE; }

/* Offsets of the fields a host and a plugin most depend on. */
size_t facet_c_offsets(size_t* out) {
    size_t n = 0;
    out[n++] = offsetof(facet_shader_desc, struct_size);
    out[n++] = offsetof(facet_shader_desc, name);
    out[n++] = offsetof(facet_shader_desc, needs);
    out[n++] = offsetof(facet_shader_desc, varyings);
    out[n++] = offsetof(facet_shader_desc, params);
    out[n++] = offsetof(facet_shader_desc, params_size);
    out[n++] = offsetof(facet_shader_desc, vertex);
    out[n++] = offsetof(facet_shader_desc, fragment);
    out[n++] = offsetof(facet_shader_desc, fragment_avx2);
    out[n++] = offsetof(facet_shader_desc, fragment_avx512);
    out[n++] = offsetof(facet_shader_desc, flags);
    out[n++] = offsetof(facet_fragment_batch, coord);
    out[n++] = offsetof(facet_draw, params);
    out[n++] = offsetof(facet_draw, model_view_projection);
    out[n++] = offsetof(facet_draw, lights);
    out[n++] = offsetof(facet_draw, time);
    out[n++] = offsetof(facet_vertex_batch, clip_position);
    out[n++] = offsetof(facet_vertex_batch, varying_floats);
    out[n++] = offsetof(facet_fragment_batch, mask);
    out[n++] = offsetof(facet_fragment_batch, texels);
    out[n++] = offsetof(facet_fragment_batch, color);
    out[n++] = offsetof(facet_param_desc, uv_varying);
    out[n++] = offsetof(facet_light, spot_cos_outer);
    out[n++] = offsetof(facet_host, sample);
    out[n++] = sizeof(facet_host);
    out[n++] = sizeof(facet_vertex_batch);
    out[n++] = sizeof(facet_varying_desc);
    return n;
}
