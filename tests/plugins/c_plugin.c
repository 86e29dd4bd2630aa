/* A shader plugin in plain C, built in several deliberately broken variants
 * (see tests/CMakeLists.txt, and the hot-reload tests, which compile it
 * while they run) to test that the host refuses each one:
 *   WRONG_MAJOR     built for another ABI major version
 *   SHORT_DESC      descriptor smaller than ABI 1.0's
 *   NO_ENTRY        exports no facet_shader_entry
 *   MISSING_SYMBOL  depends on a symbol nothing defines
 * With none of them it is a valid plugin that fills with (FILL_RED, 0.5,
 * 0.25, 1). WITH_GAIN adds a float parameter "gain" that scales red;
 * TOO_MANY_PARAMS with it claims 24 parameters for a table of one.
 * And faults, which the host must name (report_plugin_faults) or outlast:
 *   FAULT_AT_LOAD, FAULT_IN_ENTRY, FAULT_IN_VERTEX, FAULT_IN_FRAGMENT
 *                   an invalid memory access there
 *   ABORT_IN_FRAGMENT  abort() in the fragment function
 *   LOOP_IN_FRAGMENT   a fragment function that never returns
 *   SLOW_FRAGMENT      a fragment function that spins ~20 us per call
 *   TIME_AND_ROW       green is facet_draw.time, blue the pixel's window y / 1024
 * The last two write "probe: shading" to stderr at their first call. */
#include <facet/shader_abi.h>

#include <stdlib.h>
#include <unistd.h>

/* An invalid write the compiler must keep. */
__attribute__((unused)) static void fault(void) { *(volatile int*)(uintptr_t)16 = 1; }

#ifdef FAULT_AT_LOAD
__attribute__((constructor)) static void at_load(void) { fault(); }
#endif

#ifdef MISSING_SYMBOL
extern float facet_test_symbol_nobody_defines(void);
#define FILL_RED facet_test_symbol_nobody_defines()
#endif
#ifndef FILL_RED
#define FILL_RED 1.0f
#endif

static void vertex(const facet_draw* draw, const facet_vertex_batch* b) {
#ifdef FAULT_IN_VERTEX
    fault();
#endif
    const float* m = draw->model_view_projection;
    for (uint32_t i = 0; i < b->count; ++i) {
        const float* p = b->position + 3 * i;
        for (int r = 0; r < 4; ++r)
            b->clip_position[4 * i + r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    }
}

#ifdef WITH_GAIN
static const facet_param_desc params[] = {
    {"gain", FACET_PARAM_FLOAT, 0, {1, 0, 0, 0}, 0, 10, 0, -1, "scales red"}};
#ifdef TOO_MANY_PARAMS
#define PARAM_COUNT 24
#else
#define PARAM_COUNT 1
#endif
#define PARAMS params
#define PARAMS_SIZE 4
#define GAIN (*(const float*)draw->params)
#else
#define PARAM_COUNT 0
#define PARAMS NULL
#define PARAMS_SIZE 0
#define GAIN 1.0f
#endif

static void fragment(const facet_draw* draw, facet_fragment_batch* b) {
    (void)draw;
#ifdef FAULT_IN_FRAGMENT
    fault();
#endif
#ifdef ABORT_IN_FRAGMENT
    abort();
#endif
#if defined(LOOP_IN_FRAGMENT) || defined(SLOW_FRAGMENT)
    static volatile int said = 0; /* a benign race: it may be said twice */
    if (!said) {
        said = 1;
        ssize_t written = write(STDERR_FILENO, "probe: shading\n", 15);
        (void)written;
    }
#endif
#ifdef LOOP_IN_FRAGMENT
    for (volatile int forever = 1; forever;) {}
#endif
#ifdef SLOW_FRAGMENT
    for (volatile int spin = 0; spin < 20000; ++spin) {}
#endif
    for (int i = 0; i < FACET_BLOCK_LANES; ++i) {
        b->color[i] = FILL_RED * GAIN;
#ifdef TIME_AND_ROW
        b->color[FACET_BLOCK_LANES + i] = draw->time;
        b->color[2 * FACET_BLOCK_LANES + i] =
            (b->coord ? b->coord[FACET_BLOCK_LANES + i] : (float)(b->y + i / 4) + 0.5f) / 1024.0f;
#else
        b->color[FACET_BLOCK_LANES + i] = 0.5f;
        b->color[2 * FACET_BLOCK_LANES + i] = 0.25f;
#endif
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
    PLUGIN_NAME, "1.0", 0, 0, NULL, PARAM_COUNT, PARAMS, PARAMS_SIZE, vertex, fragment,
    NULL, NULL, 0, /* v1.2: no per-path loops; blocks only (not FACET_SHADER_PACKABLE) */
    FACET_KIND_SHADER, NULL, NULL, /* v1.4: a shader; no choices */
    0, 0};                         /* v1.5: no conditional varyings */

#ifdef NO_ENTRY
FACET_EXPORT const facet_shader_desc* some_other_symbol(void) { return &desc; }
#else
FACET_EXPORT const facet_shader_desc* facet_shader_entry(void) {
#ifdef FAULT_IN_ENTRY
    fault();
#endif
    return &desc;
}
#endif
