/* A shader plugin in plain C, built in several deliberately broken variants
 * (see tests/CMakeLists.txt) to test that the host refuses each one:
 *   WRONG_MAJOR     built for another ABI major version
 *   SHORT_DESC      descriptor smaller than ABI 1.0's
 *   NO_ENTRY        exports no facet_shader_entry
 *   MISSING_SYMBOL  depends on a symbol nothing defines
 * With none of them it is a valid plugin that fills with its colour. */
#include <facet/shader_abi.h>

#ifdef MISSING_SYMBOL
extern float facet_test_symbol_nobody_defines(void);
#define FILL_RED facet_test_symbol_nobody_defines()
#else
#define FILL_RED 1.0f
#endif

static void vertex(const facet_draw* draw, const facet_vertex_batch* b) {
    const float* m = draw->model_view_projection;
    for (uint32_t i = 0; i < b->count; ++i) {
        const float* p = b->position + 3 * i;
        for (int r = 0; r < 4; ++r)
            b->clip_position[4 * i + r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    }
}

static void fragment(const facet_draw* draw, facet_fragment_batch* b) {
    (void)draw;
    for (int i = 0; i < FACET_BLOCK_LANES; ++i) {
        b->color[i] = FILL_RED;
        b->color[FACET_BLOCK_LANES + i] = 0.5f;
        b->color[2 * FACET_BLOCK_LANES + i] = 0.25f;
        b->color[3 * FACET_BLOCK_LANES + i] = 1.0f;
    }
}

#ifndef PLUGIN_NAME
#define PLUGIN_NAME "c_plugin"
#endif

static const facet_shader_desc desc = {
#ifdef WRONG_MAJOR
    FACET_ABI_MAJOR + 1,
#else
    FACET_ABI_MAJOR,
#endif
    FACET_ABI_MINOR,
#ifdef SHORT_DESC
    16,
#else
    sizeof(facet_shader_desc),
#endif
    PLUGIN_NAME, "1.0", 0, 0, NULL, 0, NULL, 0, vertex, fragment};

#ifdef NO_ENTRY
FACET_EXPORT const facet_shader_desc* some_other_symbol(void) { return &desc; }
#else
FACET_EXPORT const facet_shader_desc* facet_shader_entry(void) { return &desc; }
#endif
