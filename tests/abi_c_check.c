/* Compiles the plugin ABI header as strict C (-std=c99 -pedantic -Werror)
 * and reports its layout so the C++ side can compare. */
#include <facet/shader_abi.h>

size_t facet_c_sizeof_shader_desc(void) { return sizeof(facet_shader_desc); }
size_t facet_c_sizeof_fragment_batch(void) { return sizeof(facet_fragment_batch); }
size_t facet_c_sizeof_draw(void) { return sizeof(facet_draw); }
size_t facet_c_sizeof_param_desc(void) { return sizeof(facet_param_desc); }
size_t facet_c_sizeof_light(void) { return sizeof(facet_light); }
size_t facet_c_desc_v1_0_size(void) { return FACET_SHADER_DESC_V1_0_SIZE; }
