/*
 * facet shader-plugin ABI (plain C).
 *
 * WHAT THIS IS
 *   The contract between the facet core (the host) and a shader plugin (a
 *   shared library). A plugin exports exactly one function,
 *
 *       const facet_shader_desc* facet_shader_entry(void);
 *
 *   which returns a pointer to a constant descriptor that lives as long as the
 *   library is loaded. A plugin is one of two kinds (facet_shader_desc.kind,
 *   v1.4): a material shader or a screen pass (POST-PROCESSING below).
 *   A material shader's descriptor names the shader, declares its varyings,
 *   what it needs from the core, its parameter schema, and its two batch
 *   functions: one shades a batch of vertices, one a batch of 16 fragments
 *   (a 4x4 block, or packed pixels: FACET_SHADER_PACKABLE). The host pays one indirect call per batch, never per pixel.
 *
 * WHAT THIS IS NOT
 *   Not a C++ API: only C types cross the boundary, so a plugin built by a
 *   different compiler (or compiler version) still loads. Shader authors
 *   normally do not use this header directly; <facet/shader.hpp> generates the
 *   descriptor and the batch loops from plain per-vertex and per-fragment
 *   functions.
 *
 * VERSIONING RULES
 *   - facet_shader_desc starts with abi_major, abi_minor and struct_size. The
 *     host refuses a plugin whose abi_major differs from its own, and never
 *     reads past struct_size. Fields are only ever appended, with a minor bump.
 *   - facet_host (the host's service table) follows the same rule in the
 *     other direction: a plugin checks host->struct_size before using a field
 *     appended after v1.0.
 *   - Structs the host builds and passes in one at a time (facet_draw, the
 *     batches) may also grow at their end in a minor version; a plugin
 *     reads a field added after v1.0 only if host->abi_minor says it exists.
 *   - Structs that come as arrays are frozen for a major version, since a
 *     plugin indexes them with the size it was built with: the tables the
 *     plugin provides (facet_varying_desc, facet_param_desc) and those the
 *     host passes (facet_light, facet_shadow_map). Anything new about a
 *     light or a map comes in a new struct.
 *
 * THREADING
 *   Shaders are stateless and reentrant: the host calls the batch functions
 *   from several threads at once. Material parameters live in the host and
 *   reach the shader as a read-only block (facet_draw.params).
 *
 * CONVENTIONS
 *   Matrices are 4x4, column-major (GLM layout). Colours are linear RGBA.
 *   Clip space is right-handed with depth 0..w (D3D/Vulkan style, as the
 *   projection matrices of the host produce, reversed-Z by default).
 */
#ifndef FACET_SHADER_ABI_H
#define FACET_SHADER_ABI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FACET_ABI_MAJOR 1
#define FACET_ABI_MINOR 7

/* The one symbol a plugin exports. */
#define FACET_SHADER_ENTRY_SYMBOL "facet_shader_entry"

#if defined(_WIN32)
#define FACET_EXPORT __declspec(dllexport)
#else
#define FACET_EXPORT __attribute__((visibility("default")))
#endif

/* A fragment batch is one 4x4 block of pixels, lane i pixel
 * (x + i % 4, y + i / 4), or, for a FACET_SHADER_PACKABLE shader, 16
 * pixels from anywhere (facet_fragment_batch.coord). In a block the 2x2
 * quads are lanes {0,1,4,5}, {2,3,6,7}, {8,9,12,13}, {10,11,14,15}, so
 * derivatives are differences within a quad. */
#define FACET_BLOCK_SIZE 4
#define FACET_BLOCK_LANES 16

/* Limits a host guarantees to support. */
#define FACET_MAX_VARYINGS 8        /* declared varyings                    */
#define FACET_MAX_VARYING_FLOATS 32 /* sum of their components              */
#define FACET_MAX_PARAMS 32         /* parameters in a schema               */
#define FACET_MAX_TEXTURES 8        /* texture parameters in a schema       */
#define FACET_MAX_PARAMS_SIZE 1024  /* bytes in the parameter block         */

/* ------------------------------------------------------------------------ */
/* What a shader needs from the core. The core provides only what is asked. */

/* A host refuses a plugin that needs something it cannot provide. A host
 * of ABI 1.5 or later provides them all; before 1.5, all but TANGENTS. */
enum facet_need {
    FACET_NEED_NORMALS = 1u << 0,     /* vertex normals (else NULL)              */
    FACET_NEED_UVS = 1u << 1,         /* vertex texture coordinates              */
    FACET_NEED_COLORS = 1u << 2,      /* vertex colours                          */
    FACET_NEED_TANGENTS = 1u << 3,    /* vertex tangents (v1.5): facet_vertex_batch */
    FACET_NEED_LIGHTS = 1u << 4,      /* facet_draw.lights                       */
    FACET_NEED_TEXTURES = 1u << 5,    /* texels of texture parameters            */
    FACET_NEED_SHADOW_MAP = 1u << 6,  /* facet_draw.shadow_maps (ABI 1.1)        */
    FACET_NEED_AO = 1u << 7,          /* facet_fragment_batch.ao; the host's AO  */
                                      /*   pass takes its radius and sample count */
                                      /*   from the scene's render settings       */
                                      /*   (ao_radius, ao_samples)                */
    FACET_NEED_DERIVATIVES = 1u << 8, /* differences across quads: the host must */
                                      /*   keep every lane interpolated (it does) */
    FACET_NEED_BLENDING = 1u << 9,    /* output alpha is meant for blending      */
    FACET_NEED_DISCARD = 1u << 10     /* the fragment function clears mask bits   */
                                      /*   (v1.4: a material whose USES_DISCARD */
                                      /*   parameter is 0 is drawn as if not)   */
};

/* v1.2: how a shader's fragment function may be called (facet_shader_desc.flags). */
enum facet_shader_flag {
    /* Lanes of one fragment batch may come from different blocks and
     * triangles of one draw (all front-facing or all back-facing): the host
     * then shades only covered pixels, packed into as few batches as it
     * can. In a packed batch each lane's pixel is in
     * facet_fragment_batch.coord, and x and y say nothing; a block whose
     * every lane is covered and passes still comes as a 4x4 block (coord
     * NULL), as does everything the host does not pack. For shaders that
     * compute nothing across lanes. <facet/shader.hpp> sets it unless the
     * shader says packable = false. The host packs only opaque,
     * single-sample, filled draws that write colour, and never a shader
     * that needs FACET_NEED_DERIVATIVES or FACET_NEED_DISCARD. */
    FACET_SHADER_PACKABLE = 1u << 0
};

/* How a varying is interpolated across a triangle. */
enum facet_interpolation {
    FACET_INTERP_PERSPECTIVE = 0, /* perspective-correct, through 1/w          */
    FACET_INTERP_LINEAR = 1,      /* affine in screen space (noperspective)    */
    FACET_INTERP_FLAT = 2         /* value of the triangle's first vertex      */
};

typedef struct facet_varying_desc {
    const char* name;
    uint32_t components;    /* 1..4 floats                                  */
    uint32_t interpolation; /* enum facet_interpolation                     */
} facet_varying_desc;

/* ------------------------------------------------------------------------ */
/* Parameter schema. The host validates YAML materials against it and lays
 * out the parameter block: each value is stored at `offset` in the block. */

enum facet_param_type {
    FACET_PARAM_FLOAT = 0,  /* float                                          */
    FACET_PARAM_INT = 1,    /* int32_t                                        */
    FACET_PARAM_BOOL = 2,   /* int32_t, 0 or 1                                */
    FACET_PARAM_VEC2 = 3,   /* float[2]                                       */
    FACET_PARAM_VEC3 = 4,   /* float[3]                                       */
    FACET_PARAM_VEC4 = 5,   /* float[4]                                       */
    FACET_PARAM_COLOR3 = 6, /* float[3], linear RGB                           */
    FACET_PARAM_COLOR4 = 7, /* float[4], linear RGBA                          */
    FACET_PARAM_TEXTURE = 8, /* int32_t: 1 if a texture is bound, else 0      */
    FACET_PARAM_CHOICE = 9   /* v1.4: int32_t, the index of a name among the  */
                             /*   parameter's choices (facet_shader_desc.     */
                             /*   param_choices); YAML gives the name          */
};

enum facet_param_flag {
    FACET_PARAM_SRGB = 1u << 0, /* texture holds colour: decode sRGB to linear */
    /* v1.3: a parameter that says whether a material uses a service its
     * shader can use. A host runs a pass only for the visible materials
     * that use it: */
    FACET_PARAM_USES_SHADOWS = 1u << 1, /* BOOL: false, and the material      */
                                        /*   needs no shadow map              */
    FACET_PARAM_USES_AO = 1u << 2,      /* FLOAT or BOOL: 0, and the material  */
                                        /*   needs no AO                      */
    /* v1.4 */
    FACET_PARAM_USES_DISCARD = 1u << 3, /* FLOAT or BOOL: 0, and the material  */
                                        /*   never discards (an alpha cutoff  */
                                        /*   of 0): the host may pack its     */
                                        /*   fragments and draw its depth     */
                                        /*   with no shader call              */
    /* v1.7 */
    FACET_PARAM_CUBE = 1u << 4          /* TEXTURE: a cube map (six faces, or  */
                                        /*   an equirectangular image), which */
                                        /*   the shader samples by direction  */
                                        /*   (facet_textures_service); its    */
                                        /*   uv_varying is -1                 */
};

typedef struct facet_param_desc {
    const char* name;
    uint32_t type;            /* enum facet_param_type                          */
    uint32_t offset;          /* byte offset in the parameter block             */
    float default_value[4];   /* used where the material gives no value         */
    float min_value;          /* inclusive range, per component; ignored for    */
    float max_value;          /*   BOOL and TEXTURE                             */
    uint32_t flags;           /* enum facet_param_flag                          */
    int32_t uv_varying;       /* TEXTURE: index of the varying whose first two  */
                              /*   components are its UV; the host samples the  */
                              /*   texture per block before calling fragment.   */
                              /*   v1.7: -1, none: only the shader samples it   */
                              /*   (facet_textures_service)                     */
    const char* doc;          /* one line for error messages and tools; may be NULL */
} facet_param_desc;

/* ------------------------------------------------------------------------ */
/* Lights, as the host passes them (world space): an array
 * (facet_draw.lights), so frozen for ABI 1 (VERSIONING RULES). */

enum facet_light_type {
    FACET_LIGHT_DIRECTIONAL = 0,
    FACET_LIGHT_POINT = 1,
    FACET_LIGHT_SPOT = 2
};

typedef struct facet_light {
    uint32_t type;           /* enum facet_light_type                        */
    uint32_t casts_shadow;   /* 0 or 1                                       */
    float position[3];       /* point and spot                               */
    float range;             /* 0: unlimited                                 */
    float direction[3];      /* unit vector the light travels along          */
    float intensity;
    float color[3];          /* linear RGB                                   */
    float attenuation[3];    /* constant, linear, quadratic                  */
    float spot_cos_inner;    /* spot: cosine of the full-intensity half-angle */
    float spot_cos_outer;    /* spot: cosine of the cut-off half-angle       */
} facet_light;

/* ------------------------------------------------------------------------ */
/* Shadow maps (ABI 1.1): depth seen from a shadow-casting light, rendered by
 * the host before the main pass when a visible material needs them. A
 * shader filters them itself (see facet::sdk::shadow_visibility), so its
 * own parameters choose the kernel and the bias. An array
 * (facet_draw.shadow_maps), so frozen for ABI 1. */

enum facet_shadow_projection { FACET_SHADOW_ORTHOGRAPHIC = 0, FACET_SHADOW_PERSPECTIVE = 1 };

typedef struct facet_shadow_map {
    uint32_t light;                  /* index into facet_draw.lights             */
    uint32_t projection;             /* enum facet_shadow_projection             */
    uint32_t width, height;
    float view_projection[16];       /* world -> light clip space, depth 0..w    */
    float near_plane, far_plane;     /* of that projection (standard, not reversed) */
    float texel_size;                /* world size of a texel: orthographic, in  */
                                     /*   world units; perspective, per unit of  */
                                     /*   distance from the light                */
    const float* depth;              /* [height][width], window depth 0..1 of the */
                                     /*   nearest caster, top row first          */
} facet_shadow_map;

/* v1.3: the same map as distances from the light, which a filter can read
 * with a fraction of the memory traffic and no conversion per tap (see
 * facet::sdk::shadow_visibility). A texel holds the distance of the
 * nearest caster along the light's axis (orthographic: window depth;
 * perspective: clip w), as (distance - near_plane) / (far_plane -
 * near_plane) * 65535 rounded up: 0 at the near plane, 65535 at the far
 * plane and wherever nothing was drawn. Around the map lies a border of
 * FACET_SHADOW_BORDER texels on every side that reads 65535, so that a
 * kernel centred on the map never reads past its storage: texel (x, y),
 * for -FACET_SHADOW_BORDER <= x < width + FACET_SHADOW_BORDER and the same
 * for y, is texels[y * stride + x]. An array parallel to
 * facet_draw.shadow_maps, so frozen for ABI 1. */
#define FACET_SHADOW_BORDER 8

typedef struct facet_shadow_distances {
    const uint16_t* texels;  /* texel (0, 0), top row first                 */
    uint32_t stride;         /* texels from one row to the next             */
    uint32_t reserved;       /* 0                                           */
} facet_shadow_distances;

/* v1.6: the same distances bounded, tile by tile, between two parallel
 * planes, from which a filter sees at once, for most receivers, that every
 * tap of its kernel is lit or that none is, and reads no texel (see
 * facet::sdk::shadow_visibility). Tile (tx, ty), for 0 <= tx < width /
 * FACET_SHADOW_TILE and the same for ty by height, begins at texel (x0, y0)
 * = FACET_SHADOW_TILE (tx, ty); its entry, the four floats from
 * tiles + 4 (ty * stride + tx), is {nearest, dx, dy, depth}: every stored
 * texel (x, y) within FACET_SHADOW_REACH texels of the tile on each axis
 * (x0 - REACH <= x < x0 + TILE + REACH, and the same for y; border
 * included) holds a distance between nearest + dx (x - x0) + dy (y - y0)
 * and that plus depth, the floats taken as exact numbers, with |dx| and
 * |dy| at most 2048 and nearest and nearest + depth within +-2^17 (so
 * that a filter's float sums stay within 2^18, where they round by 1/64
 * at most). The host makes them for a map whose width and height
 * are multiples of FACET_SHADOW_TILE once it has kept the map for a frame;
 * until then the entry's tiles are NULL. An array parallel to
 * facet_draw.shadow_maps (and cube_shadow_maps), so frozen for ABI 1. */
#define FACET_SHADOW_TILE 8
#define FACET_SHADOW_REACH 4

typedef struct facet_shadow_planes {
    const float* tiles;  /* tile (0, 0)                                  */
    uint32_t stride;     /* tiles from one row of tiles to the next      */
    uint32_t reserved;   /* 0                                            */
} facet_shadow_planes;

/* ------------------------------------------------------------------------ */
/* Host services, passed with every draw. */

typedef struct facet_draw facet_draw;
typedef struct facet_post_frame facet_post_frame; /* v1.4: POST-PROCESSING below */

enum facet_log_level { FACET_LOG_DEBUG = 0, FACET_LOG_INFO = 1, FACET_LOG_WARN = 2, FACET_LOG_ERROR = 3 };

typedef struct facet_host {
    uint16_t abi_major;
    uint16_t abi_minor;
    uint32_t struct_size;
    /* Log a message under the shader's name. Thread-safe. */
    void (*log)(int level, const char* shader, const char* message);
    /* Dependent texture read: sample texture parameter `slot` (the k-th
     * TEXTURE parameter of the schema) at `count` UVs, mip level 0, with the
     * material's filter and wrap modes. Writes rgba[c * count + i]. */
    void (*sample)(const facet_draw* draw, uint32_t slot, const float* u, const float* v,
                   uint32_t count, float* rgba);
    /* v1.4, for screen passes (facet_post_frame): runs task(context, i,
     * worker) once for each i in 0..count-1 on the host's threads, the
     * caller's among them, and returns when every call has; worker (below
     * frame->threads) tells a task which per-thread scratch it may use.
     * Call it only from the pass's post function: from a task it runs the
     * tasks on the calling thread, one after the other, and logs an error. */
    void (*parallel_for)(const facet_post_frame* frame, uint32_t count,
                         void (*task)(void* context, uint32_t index, uint32_t worker),
                         void* context);
    /* v1.4: memory for the pass's intermediate images: `bytes` bytes,
     * 64-byte aligned, under number `slot` (0..FACET_POST_SCRATCH_SLOTS-1)
     * of this pass in this chain. The host keeps it between frames (its
     * contents are undefined at each frame's start) and frees it with the
     * chain. NULL when the memory budget refuses it (the pass then leaves
     * the image as it is), and when called from a task rather than the
     * post function. */
    void* (*scratch)(const facet_post_frame* frame, uint32_t slot, size_t bytes);
    /* v1.7: an optional service, by its id and the version the plugin was
     * built against: a record that starts with its struct_size, or NULL
     * when the host has no such service in that version. The pointer stays
     * valid while the plugin is loaded. New services come this way, not as
     * new fields here. */
    const void* (*extension)(const char* id, uint32_t version);
} facet_host;

/* ------------------------------------------------------------------------ */
/* Services found through facet_host.extension (v1.7). */

/* "facet.textures", version 1: a draw's texture parameters sampled where
 * the shader wants them, with their filter and wrap, on the draw's
 * instruction-set path. */
#define FACET_TEXTURES_EXTENSION "facet.textures"
#define FACET_TEXTURES_VERSION 1u

enum facet_texture_kind {
    FACET_TEXTURE_NONE = 0, /* nothing bound: samples read white               */
    FACET_TEXTURE_2D = 1,
    FACET_TEXTURE_CUBE = 2  /* six square faces, +X, -X, +Y, -Y, +Z, -Z        */
};

typedef struct facet_texture_info {
    uint32_t kind;          /* enum facet_texture_kind                          */
    uint32_t width, height; /* level 0 (a cube: each face)                      */
    uint32_t levels;        /* mip levels, 1 when the filter reads level 0 only */
} facet_texture_info;

typedef struct facet_textures_service {
    uint32_t struct_size;
    /* What is bound to texture parameter `slot` (the k-th TEXTURE parameter
     * of the schema) in this draw. */
    void (*info)(const facet_draw* draw, uint32_t slot, facet_texture_info* out);
    /* Samples it at `count` lanes (1 to 16) of `mask` (bit i: lane i):
     * coords[k * count + i] is coordinate k of lane i (a 2D texture: u and
     * v, 0..1 across it, v down its rows; a cube: a direction x, y, z, not
     * necessarily unit), lod[i] its level of detail (0: level 0; clamped to
     * the levels there are; ignored by nearest and bilinear bindings, which
     * read level 0; NULL: 0). Writes rgba[c * count + i], linear RGBA, 0
     * outside the mask. A cube's direction picks the face of its largest
     * component (x before y before z where they are equal), whose texels are
     * then filtered as a 2D texture clamped to its edges. Thread-safe. */
    void (*sample)(const facet_draw* draw, uint32_t slot, const float* coords,
                   const float* lod, uint32_t count, uint32_t mask, float* rgba);
} facet_textures_service;

/* ------------------------------------------------------------------------ */
/* Per-draw state: one object drawn with one material. Read-only. */

struct facet_draw {
    const facet_host* host;
    const void* params;            /* the material's parameter block; never  */
                                   /*   NULL (zeros if there are no params)  */
    const void* host_data;         /* opaque to the plugin                   */
    float model[16];
    float view[16];
    float projection[16];
    float view_projection[16];
    float model_view_projection[16];
    float normal_matrix[16];       /* inverse-transpose of model up to a positive */
                                   /*   scale (3x3 in a 4x4): normalise normals */
    float camera_position[4];      /* world space, w = 1                     */
    uint32_t light_count;          /* 0 unless FACET_NEED_LIGHTS             */
    const facet_light* lights;
    uint32_t viewport_width;
    uint32_t viewport_height;
    float time;                    /* seconds, for animated shaders          */
    /* v1.1 */
    uint32_t shadow_map_count;     /* 0 unless FACET_NEED_SHADOW_MAP         */
    const facet_shadow_map* shadow_maps;
    /* v1.3: shadow_maps[i] as distances, or NULL */
    const facet_shadow_distances* shadow_distances;
    /* v1.3: the cube maps of the point lights that cast shadows (0 unless
     * FACET_NEED_SHADOW_MAP), six faces each, in the order +X, -X, +Y, -Y,
     * +Z, -Z of the direction from the light. A face is a perspective map of
     * 90 degrees (its `depth` is NULL: filter its distances), whose border
     * holds the distances just past its edge, so that a kernel near the
     * edge reads real texels. */
    uint32_t cube_shadow_map_count;                      /* cubes               */
    const facet_shadow_map* cube_shadow_maps;            /* [6 * count]         */
    const facet_shadow_distances* cube_shadow_distances; /* [6 * count]         */
    /* v1.6: shadow_maps[i] and cube_shadow_maps[i] bounded by planes
     * (facet_shadow_planes); NULL, or an entry with tiles NULL, where not */
    const facet_shadow_planes* shadow_planes;
    const facet_shadow_planes* cube_shadow_planes;                  /* [6 * count] */
};

/* A batch of vertices. Inputs are arrays indexed by vertex; an input the
 * shader did not ask for is NULL. */
typedef struct facet_vertex_batch {
    uint32_t count;
    const float* position;   /* [count][3] object space                     */
    const float* normal;     /* [count][3] object space, or NULL            */
    const float* uv;         /* [count][2], or NULL                         */
    const float* color;      /* [count][4] linear RGBA, or NULL             */
    const float* tangent;    /* [count][4] object space: xyz unit, along +u */
                             /*   and perpendicular to the normal; w = +1 or */
                             /*   -1, the bitangent (towards the texture's  */
                             /*   top row) being cross(normal, xyz) * w, as */
                             /*   glTF defines it; 0 where a vertex has no  */
                             /*   UVs to give it a frame. NULL unless the   */
                             /*   shader needs FACET_NEED_TANGENTS (v1.5)   */
                             /*   and the mesh has tangents (a loaded mesh  */
                             /*   with UVs does; one made in code may not)  */
    float* clip_position;    /* out: [count][4]                              */
    float* varyings;         /* out: [count][varying_floats]                 */
    uint32_t varying_floats; /* sum of the declared varyings' components    */
} facet_vertex_batch;

/* A 4x4 block of fragments, in structure-of-arrays layout: the value of float
 * k of the varyings for lane i is varyings[k * FACET_BLOCK_LANES + i]. Every
 * lane holds interpolated values, covered or not, so a shader may take
 * derivatives across quads. For a shader with FACET_SHADER_PACKABLE the
 * host may instead pack covered pixels of several blocks into one batch
 * (lane i at coord[i], coord[16 + i]); then only lanes in the mask hold
 * values. */
typedef struct facet_fragment_batch {
    int32_t x, y;           /* pixel of lane 0                               */
    uint32_t mask;          /* in: lanes covered and passing depth; out: a   */
                            /*   shader with FACET_NEED_DISCARD clears bits   */
    uint32_t front_facing;  /* 1 if the triangle faces the viewer            */
    const float* varyings;  /* [varying_floats][16]                         */
    const float* depth;     /* [16] window depth, 0..1                       */
    const float* texels;    /* [texture slot][4][16] linear RGBA, or NULL    */
    const float* shadow;    /* reserved: always NULL, never read; shadows    */
                            /*   come from facet_draw.shadow_maps (ABI 1.1)   */
    const float* ao;        /* [16] ambient visibility 0..1 (screen-space AO, */
                            /*   blurred) if FACET_NEED_AO, else NULL. From   */
                            /*   v1.3 also NULL when the frame ran no AO pass */
                            /*   (AO off, or no material asked): read 1       */
    float* color;           /* out: [4][16] linear RGBA                      */
    /* v1.2 */
    const float* coord;     /* [2][16] window x, y of each lane's pixel      */
                            /*   centre in a packed batch; NULL in a block   */
                            /*   (there x + i % 4 + 0.5, y + i / 4 + 0.5)    */
} facet_fragment_batch;

typedef void (*facet_vertex_fn)(const facet_draw* draw, const facet_vertex_batch* batch);
typedef void (*facet_fragment_fn)(const facet_draw* draw, facet_fragment_batch* batch);

/* ------------------------------------------------------------------------ */
/* POST-PROCESSING (v1.4). A screen pass (kind FACET_KIND_POST) works on the
 * finished image: the scene's passes (`post: [...]`) run in order on a
 * float target, in linear light, after the MSAA resolve and before the
 * conversion to the output format. Its descriptor has a name, version and
 * parameter schema like a shader's, no varyings, no vertex or fragment
 * function, `needs` 0, and the function `post`, which the host calls once
 * a frame, on one thread. The pass shares its work out to the host's
 * threads itself (facet_host.parallel_for) and keeps its intermediate
 * images in the host's scratch memory (facet_host.scratch). */
#define FACET_POST_SCRATCH_SLOTS 16

struct facet_post_frame {
    const facet_host* host;
    const void* params;      /* the pass's parameter block (never NULL)     */
    const void* host_data;   /* opaque to the plugin                        */
    uint32_t width, height;  /* pixels                                      */
    uint32_t stride;         /* pixels from one row to the next             */
    uint32_t threads;        /* workers parallel_for runs tasks on          */
    float* color;            /* [height][stride][4] linear RGBA, unbounded: */
                             /*   read it, and write the result in place    */
    const float* depth;      /* [height][stride] window depth 0..1 of the   */
                             /*   nearest surface, as the scene drew it     */
    uint32_t reversed_z;     /* 1: depth 1 is near and 0 the background;    */
                             /*   0: 0 is near and 1 the background         */
    float time;              /* seconds, as facet_draw.time                 */
};

typedef void (*facet_post_fn)(const facet_post_frame* frame);

/* ------------------------------------------------------------------------ */
/* The descriptor a plugin returns. Only ever appended to. */

typedef struct facet_shader_desc {
    /* v1.0 */
    uint16_t abi_major;              /* FACET_ABI_MAJOR the plugin was built with */
    uint16_t abi_minor;              /* FACET_ABI_MINOR the plugin was built with */
    uint32_t struct_size;            /* sizeof(facet_shader_desc) in the plugin   */
    const char* name;                /* must match the library's file name        */
    const char* version;             /* free-form, for logs                       */
    uint32_t needs;                  /* enum facet_need bits                      */
    uint32_t varying_count;
    const facet_varying_desc* varyings;
    uint32_t param_count;
    const facet_param_desc* params;
    uint32_t params_size;            /* bytes of the parameter block              */
    facet_vertex_fn vertex;
    facet_fragment_fn fragment;
    /* v1.2: the same fragment function compiled for wider instruction sets
     * (facet_add_shader() builds them from the same source; see
     * <facet/shader.hpp>), or NULL. The host calls the widest its own path
     * allows: fragment_avx512 on the avx512 path, else fragment_avx2 on the
     * avx2 or avx512 path, else `fragment`. Each computes what `fragment`
     * computes. The host only takes one of these paths on a CPU that has
     * its instruction set (facet/isa.hpp in the core). */
    facet_fragment_fn fragment_avx2;   /* x86-64-v3: AVX2, FMA, BMI1/2, F16C   */
    facet_fragment_fn fragment_avx512; /* x86-64-v4: AVX-512 F, BW, CD, DQ, VL */
    uint32_t flags;                    /* enum facet_shader_flag bits           */
    /* v1.4 */
    uint32_t kind;                     /* enum facet_plugin_kind                */
    facet_post_fn post;                /* FACET_KIND_POST: the pass; else NULL  */
    /* [param_count], or NULL when no parameter is a CHOICE: for a CHOICE
     * parameter, its names separated by '|' ("reinhard|aces"), the value
     * being the index of the name; NULL for the others. */
    const char* const* param_choices;
    /* v1.5: the last `conditional_varyings` varyings are read only when
     * parameter `varyings_condition` (an index into params: a TEXTURE or a
     * BOOL) is not 0, as a normal map's tangent is read only with a normal
     * map bound. When it is 0 the host may leave them uninterpolated: their
     * floats in a fragment batch are then unspecified, and the fragment
     * function must not read them (<facet/shader.hpp> copies only the
     * others). A TEXTURE parameter whose UV is one of them must be the
     * condition itself. 0: every varying is read. */
    uint32_t conditional_varyings;
    uint32_t varyings_condition;
} facet_shader_desc;

/* v1.4: what a plugin is. A host of ABI 1.3 or older sees only shaders;
 * a descriptor of 1.3 or older is a shader. */
enum facet_plugin_kind {
    FACET_KIND_SHADER = 0, /* a material shader: vertex and fragment            */
    FACET_KIND_POST = 1    /* a screen pass: post (POST-PROCESSING above)        */
};

/* Size of the v1.0 descriptor: the least a host accepts. */
#define FACET_SHADER_DESC_V1_0_SIZE (offsetof(facet_shader_desc, fragment) + sizeof(facet_fragment_fn))

typedef const facet_shader_desc* (*facet_shader_entry_fn)(void);

#ifdef __cplusplus
}
#endif

#endif /* FACET_SHADER_ABI_H */
