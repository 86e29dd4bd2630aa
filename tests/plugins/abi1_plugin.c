/* A plugin as facet's ABI 1.6 laid it out, for the test that a host of ABI
 * 2 refuses it by name: it exports facet_shader_entry, whose descriptor
 * starts with the ABI it was built for. Its own copy of ABI 1.6's
 * descriptor, since the SDK's header now describes ABI 2; the functions
 * are never called. */
#include <stddef.h>
#include <stdint.h>

typedef void (*abi1_fn)(const void* draw, void* batch);

typedef struct abi1_shader_desc {
    uint16_t abi_major, abi_minor;
    uint32_t struct_size;
    const char* name;
    const char* version;
    uint32_t needs;
    uint32_t varying_count;
    const void* varyings;
    uint32_t param_count;
    const void* params;
    uint32_t params_size;
    abi1_fn vertex, fragment, fragment_avx2, fragment_avx512;
    uint32_t flags;
    uint32_t kind;
    void (*post)(const void* frame);
    const char* const* param_choices;
    uint32_t conditional_varyings, varyings_condition;
} abi1_shader_desc;

static void nothing(const void* draw, void* batch) {
    (void)draw;
    (void)batch;
}

static const abi1_shader_desc desc = {1, 6, sizeof(abi1_shader_desc), "abi1_plugin", "1.0",
                                      0, 0, NULL, 0, NULL, 0, nothing, nothing, NULL, NULL,
                                      0, 0, NULL, NULL, 0, 0};

__attribute__((visibility("default"))) const abi1_shader_desc* facet_shader_entry(void) {
    return &desc;
}
