/* A shader plugin in plain C, built in several deliberately broken variants
 * (see tests/CMakeLists.txt, and the hot-reload tests, which compile it
 * while they run) to test that the host refuses each one:
 *   WRONG_MAJOR     built for another ABI major version
 *   SHORT_DESC      descriptor smaller than ABI 2.0's
 *   SHORT_SHADER    shader record smaller than ABI 2.0's
 *   NO_BASELINE     fragment entries with none for FACET_ISA_BASELINE
 *   BOTH_KINDS      a shader and a screen pass at once
 *   NO_ENTRY        exports no facet_plugin_entry
 *   MISSING_SYMBOL  depends on a symbol nothing defines
 * With none of them it is a valid plugin that fills with (FILL_RED, 0.5,
 * 0.25, 1). WITH_GAIN adds a float parameter "gain" that scales red;
 * TOO_MANY_PARAMS with it claims 24 parameters for a table of one.
 * And faults, which the host must name (report_plugin_faults) or outlast:
 *   FAULT_AT_LOAD, FAULT_IN_ENTRY, FAULT_IN_VERTEX, FAULT_IN_FRAGMENT
 *                   an invalid memory access there
 *   ABORT_IN_FRAGMENT  abort() in the fragment function
 *   EXIT_IN_FRAGMENT   exit(0) in the fragment function
 *   QUICK_EXIT_IN_FRAGMENT  _exit(0) there: no atexit handler runs
 *   ALLOC_IN_FRAGMENT  a fragment function that allocates 64 MiB after 64 MiB,
 *                      writing a byte of each, without end (nor a check for
 *                      NULL): address space, not memory, runs out
 *   LOOP_IN_FRAGMENT   a fragment function that never returns
 *   LOOP_AT_LOAD, LOOP_IN_ENTRY, LOOP_IN_VERTEX  code there that never returns
 *   WAIT_IN_FRAGMENT   a fragment function that waits in a system call forever
 *   LOOP_ABOVE_GAIN    with WITH_GAIN: never returns when gain is over 5
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

/* A loop the compiler must keep. */
__attribute__((unused)) static void forever(void) {
    for (volatile int spin = 1; spin;) {}
}

#ifdef LOOP_AT_LOAD
__attribute__((constructor)) static void at_load(void) { forever(); }
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
#ifdef LOOP_IN_VERTEX
    forever();
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
#ifdef EXIT_IN_FRAGMENT
    exit(0);
#endif
#ifdef QUICK_EXIT_IN_FRAGMENT
    _exit(0);
#endif
#ifdef ALLOC_IN_FRAGMENT
    for (;;) *(volatile char*)malloc(64 << 20) = 1;
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
    forever();
#endif
#ifdef WAIT_IN_FRAGMENT
    for (;;) pause();
#endif
#ifdef LOOP_ABOVE_GAIN
    if (GAIN > 5.0f) forever();
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

/* Blocks only: no FACET_SHADER_PACKABLE, one fragment function. */
static const facet_fragment_entry fragments[] = {
#ifdef NO_BASELINE
    {FACET_ISA_X86_64_V3, fragment}
#else
    {FACET_ISA_BASELINE, fragment}
#endif
};

static const facet_shader_desc shader = {
#ifdef SHORT_SHADER
    8,
#else
    sizeof(facet_shader_desc),
#endif
    0, 0,    /* needs, flags */
    0, NULL, /* varyings */
    0, 0,    /* no conditional varyings */
    vertex, 1, fragments,
    0, 0};   /* no second UV set, no second condition */

#ifdef BOTH_KINDS
static void run(const facet_pass_frame* frame) { (void)frame; }
static const facet_pass_desc pass = {sizeof(facet_pass_desc), run};
#define PASS &pass
#else
#define PASS NULL
#endif

static const facet_plugin_desc desc = {
#ifdef WRONG_MAJOR
    FACET_ABI_MAJOR + 1,
#else
    FACET_ABI_MAJOR,
#endif
    FACET_ABI_MINOR,
#ifdef SHORT_DESC
    16,
#else
    sizeof(facet_plugin_desc),
#endif
    PLUGIN_NAME, "1.0",
    {PARAM_COUNT, PARAMS_SIZE, PARAMS, NULL},
    &shader, PASS};

#ifdef NO_ENTRY
FACET_EXPORT const facet_plugin_desc* some_other_symbol(void) { return &desc; }
#else
FACET_EXPORT const facet_plugin_desc* facet_plugin_entry(void) {
#ifdef FAULT_IN_ENTRY
    fault();
#endif
#ifdef LOOP_IN_ENTRY
    forever();
#endif
    return &desc;
}
#endif
