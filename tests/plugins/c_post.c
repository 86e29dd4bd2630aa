/* A screen pass in plain C, for the tests: RGB times
 * SCALE * gain, row by row on the host's threads, through a scratch copy
 * of the image. Built while the tests run (tests/support.cpp,
 * compile_post_plugin), with -DSCALE=... for a new version, and with
 * -DFAULT_IN_POST for one that crashes on a worker thread. */
#include <facet/shader_abi.h>

#include <string.h>

#ifndef PLUGIN_NAME
#define PLUGIN_NAME "c_post"
#endif
#ifndef SCALE
#define SCALE 0.5f
#endif

typedef struct {
    float gain;
} Params;

static const facet_param_desc params[] = {
    {"gain", FACET_PARAM_FLOAT, 0, {1.0f, 0.0f, 0.0f, 0.0f}, 0.0f, 100.0f, 0, -1,
     "multiplies RGB"}};

typedef struct {
    const facet_pass_frame* frame;
    float* copy;
    float k;
} Job;

static void scale_row(void* context, uint32_t y, uint32_t worker) {
    const Job* job = (const Job*)context;
    const facet_pass_frame* f = job->frame;
    float* row = f->color + (size_t)y * f->stride * 4;
    float* copy = job->copy + (size_t)y * f->width * 4;
    uint32_t x;
    (void)worker;
#ifdef FAULT_IN_POST
    if (y == f->height / 2) *(volatile int*)0 = 1;
#endif
    memcpy(copy, row, sizeof(float) * 4 * f->width);
    for (x = 0; x < f->width; ++x) {
        row[4 * x] = copy[4 * x] * job->k;
        row[4 * x + 1] = copy[4 * x + 1] * job->k;
        row[4 * x + 2] = copy[4 * x + 2] * job->k;
    }
}

static void post(const facet_pass_frame* f) {
    const Params* p = (const Params*)f->params;
    const facet_pass_service* service =
        (const facet_pass_service*)f->host->extension(FACET_PASS_EXTENSION, FACET_PASS_VERSION);
    Job job;
    if (!service) return;
    job.frame = f;
    job.k = SCALE * p->gain;
    job.copy = (float*)service->scratch(f, 0, sizeof(float) * 4 * f->width * f->height);
    if (!job.copy) return;
    service->parallel_for(f, f->height, scale_row, &job);
}

static const facet_pass_desc pass = {sizeof(facet_pass_desc), post};

static const facet_plugin_desc desc = {
    FACET_ABI_MAJOR, FACET_ABI_MINOR, sizeof(facet_plugin_desc), PLUGIN_NAME, "1.0",
    {1, sizeof(Params), params, NULL}, NULL, &pass};

FACET_EXPORT const facet_plugin_desc* facet_plugin_entry(void) { return &desc; }
