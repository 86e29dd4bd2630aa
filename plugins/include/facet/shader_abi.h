/*
 * facet plugin ABI 2 (plain C).
 *
 * WHAT THIS IS
 *   The contract between the facet core (the host) and a plugin (a shared
 *   library). A plugin exports exactly one function,
 *
 *       const facet_plugin_desc* facet_plugin_entry(void);
 *
 *   which returns a constant descriptor that lives as long as the library
 *   is loaded. A plugin is a material shader (facet_plugin_desc.shader:
 *   its varyings, what it needs from the core, and the functions that
 *   shade a batch of vertices and a batch of 16 fragments) or a screen
 *   pass (facet_plugin_desc.pass: a function run on the finished image).
 *   Either has a name and a parameter schema. The host pays one indirect
 *   call per batch, never per pixel.
 *
 * WHAT THIS IS NOT
 *   Not a C++ API: only C types cross the boundary, so a plugin built by
 *   another compiler still loads. Authors normally use <facet/shader.hpp>
 *   and <facet/post.hpp>, which make the descriptor and the batch loops
 *   from one shading body.
 *
 * THE COMPATIBILITY RULE
 *   1. A host loads a plugin of its own major version only. In every major
 *      version the plugin's descriptor and the host's table (facet_host)
 *      start with abi_major, abi_minor and struct_size, so either side can
 *      tell what the other was built for. A host of ABI 2 refuses a plugin
 *      built for ABI 1 (whose entry point was facet_shader_entry) and says
 *      which ABI it was built for: rebuild it against this SDK.
 *   2. Within a major version, a minor version only adds:
 *      - A record one side gives the other carries its struct_size, or its
 *        reader knows its size from the other's abi_minor. New fields go
 *        at its end; a reader treats fields past the size as zero.
 *      - A record that comes in an array (varyings, parameters, lights,
 *        shadow maps, fragment entries) is frozen for the major version,
 *        since its reader indexes it with the size it was built with.
 *        Anything new about it comes in a record of its own.
 *      - A new host service is not a new field: a plugin asks for it by
 *        id and version (facet_host.extension), and does without it when
 *        the host answers NULL.
 *      - A new instruction set is a new facet_isa value; a host ignores
 *        fragment entries for values it does not know.
 *
 * THREADING
 *   Plugins are stateless and reentrant: the host calls a shader's batch
 *   functions from several threads at once. Parameters live in the host
 *   and reach the plugin as a read-only block.
 *
 * CONVENTIONS
 *   Matrices are 4x4, column-major (GLM layout). Colours are linear RGBA.
 *   Clip space is right-handed with depth 0..w (D3D/Vulkan style; the
 *   host's projections are reversed-Z by default).
 *
 * CONTENTS
 *   versions and the entry point; the parameter schema; material shaders
 *   (needs, varyings, entry points); lights and shadows; a draw and its
 *   batches; screen passes; the host's services; the plugin descriptor.
 */
#ifndef FACET_SHADER_ABI_H
#define FACET_SHADER_ABI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Versions and the entry point. */

#define FACET_ABI_MAJOR 2
#define FACET_ABI_MINOR 1

/* The one symbol a plugin exports (ABI 2 on). */
#define FACET_PLUGIN_ENTRY_SYMBOL "facet_plugin_entry"
/* What ABI 1 plugins exported: a host looks for it only to name the ABI an
 * old plugin was built for when it refuses it. */
#define FACET_ABI1_ENTRY_SYMBOL "facet_shader_entry"

#if defined(_WIN32)
#define FACET_EXPORT __declspec(dllexport)
#else
#define FACET_EXPORT __attribute__((visibility("default")))
#endif

/* Limits a host guarantees to support. */
#define FACET_MAX_VARYINGS 8        /* declared varyings                    */
#define FACET_MAX_VARYING_FLOATS 32 /* sum of their components              */
#define FACET_MAX_PARAMS 32         /* parameters in a schema               */
#define FACET_MAX_TEXTURES 8        /* texture parameters in a schema       */
#define FACET_MAX_PARAMS_SIZE 1024  /* bytes in the parameter block         */

/* ------------------------------------------------------------------------ */
/* The parameter schema, of a shader or a screen pass. The host validates
 * YAML materials against it and lays out the parameter block: each value
 * is stored at `offset` in the block. */

enum facet_param_type {
    FACET_PARAM_FLOAT = 0,   /* float                                         */
    FACET_PARAM_INT = 1,     /* int32_t                                       */
    FACET_PARAM_BOOL = 2,    /* int32_t, 0 or 1                               */
    FACET_PARAM_VEC2 = 3,    /* float[2]                                      */
    FACET_PARAM_VEC3 = 4,    /* float[3]                                      */
    FACET_PARAM_VEC4 = 5,    /* float[4]                                      */
    FACET_PARAM_COLOR3 = 6,  /* float[3], linear RGB                          */
    FACET_PARAM_COLOR4 = 7,  /* float[4], linear RGBA                         */
    FACET_PARAM_TEXTURE = 8, /* int32_t: 1 if a texture is bound, else 0;     */
                             /*   a shader's only (a screen pass takes none)  */
    FACET_PARAM_CHOICE = 9   /* int32_t, the index of a name among the        */
                             /*   parameter's choices (facet_schema.choices); */
                             /*   YAML gives the name                         */
};

enum facet_param_flag {
    FACET_PARAM_SRGB = 1u << 0, /* TEXTURE holds colour: decode sRGB to linear */
    FACET_PARAM_CUBE = 1u << 1, /* TEXTURE is a cube map (six faces, or an     */
                                /*   equirectangular image), sampled by        */
                                /*   direction (facet_textures_service); its   */
                                /*   uv_varying is -1. Without it: 2D          */
    /* A parameter that says whether a material uses a service its shader
     * can use. A host runs a pass only for the visible materials that use
     * it: */
    FACET_PARAM_USES_SHADOWS = 1u << 2, /* BOOL: false, and the material      */
                                        /*   needs no shadow map              */
    FACET_PARAM_USES_AO = 1u << 3,      /* FLOAT or BOOL: 0, and the material  */
                                        /*   needs no AO                      */
    FACET_PARAM_USES_DISCARD = 1u << 4  /* FLOAT or BOOL: 0, and the material  */
                                        /*   never discards (an alpha cutoff  */
                                        /*   of 0): the host may pack its     */
                                        /*   fragments and draw its depth     */
                                        /*   with no shader call              */
};

typedef struct facet_param_desc {
    const char* name;
    uint32_t type;            /* enum facet_param_type                          */
    uint32_t offset;          /* byte offset in the parameter block             */
    float default_value[4];   /* used where the material gives no value         */
    float min_value;          /* inclusive range, per component; ignored for    */
    float max_value;          /*   BOOL, TEXTURE and CHOICE                     */
    uint32_t flags;           /* enum facet_param_flag                          */
    int32_t uv_varying;       /* TEXTURE: the varying whose first two           */
                              /*   components are its UV, where the host        */
                              /*   samples it per block before calling the      */
                              /*   fragment function; -1: none, only the        */
                              /*   shader samples it (facet_textures_service)   */
    const char* doc;          /* one line for error messages and tools; may be NULL */
} facet_param_desc;

typedef struct facet_schema {
    uint32_t param_count;
    uint32_t params_size;         /* bytes of the parameter block              */
    const facet_param_desc* params;
    /* [param_count], or NULL when no parameter is a CHOICE: for a CHOICE,
     * its names separated by '|' ("reinhard|aces"), the value being the
     * index of the name; NULL for the others. */
    const char* const* choices;
} facet_schema;

/* ------------------------------------------------------------------------ */
/* Material shaders: what they need, their varyings, their entry points. */

/* What a shader needs from the core; the core provides only what is asked,
 * and refuses a shader that needs what it cannot provide. */
enum facet_need {
    FACET_NEED_NORMALS = 1u << 0,     /* vertex normals (else NULL)              */
    FACET_NEED_UVS = 1u << 1,         /* vertex texture coordinates              */
    FACET_NEED_COLORS = 1u << 2,      /* vertex colours                          */
    FACET_NEED_TANGENTS = 1u << 3,    /* vertex tangents                         */
    FACET_NEED_LIGHTS = 1u << 4,      /* facet_draw.lights                       */
    FACET_NEED_TEXTURES = 1u << 5,    /* texels of texture parameters            */
    FACET_NEED_SHADOW_MAP = 1u << 6,  /* facet_draw.shadows                      */
    FACET_NEED_AO = 1u << 7,          /* facet_fragment_batch.ao; the host's AO  */
                                      /*   pass takes its radius and sample count */
                                      /*   from the scene's render settings       */
    FACET_NEED_DERIVATIVES = 1u << 8, /* differences across quads: fragments come */
                                      /*   in whole 4x4 blocks, every lane        */
                                      /*   interpolated                           */
    FACET_NEED_BLENDING = 1u << 9,    /* output alpha is meant for blending      */
    FACET_NEED_DISCARD = 1u << 10,    /* the fragment function clears mask bits  */
                                      /*   (a material whose USES_DISCARD         */
                                      /*   parameter is 0 is drawn as if not)     */
    FACET_NEED_UV1 = 1u << 11         /* ABI 2.1: a second set of texture        */
                                      /*   coordinates (facet_vertex_batch.uv1)   */
};

/* How a shader's fragment function may be called (facet_shader_desc.flags). */
enum facet_shader_flag {
    /* Lanes of one fragment batch may come from different blocks and
     * triangles of one draw (all front-facing or all back-facing): the host
     * then shades only covered pixels, packed into as few batches as it
     * can, each lane's pixel in facet_fragment_batch.coord. A block whose
     * every lane is covered and passes still comes as a 4x4 block (coord
     * NULL), as does everything the host does not pack. For shaders that
     * compute nothing across lanes. The host packs only opaque,
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

/* Instruction sets a fragment function may be compiled for. A host calls
 * the entry of the widest one its path allows, and takes a path only on a
 * CPU that has its instruction set. Each entry computes what the
 * FACET_ISA_BASELINE one computes, which every shader has. */
enum facet_isa {
    FACET_ISA_BASELINE = 0,  /* the architecture's baseline: SSE2 on x86-64, */
                             /*   NEON on AArch64                           */
    FACET_ISA_X86_64_V3 = 1, /* AVX2, FMA, BMI1/2, F16C                     */
    FACET_ISA_X86_64_V4 = 2  /* AVX-512 F, BW, CD, DQ, VL                   */
};

typedef struct facet_draw facet_draw;
typedef struct facet_vertex_batch facet_vertex_batch;
typedef struct facet_fragment_batch facet_fragment_batch;

typedef void (*facet_vertex_fn)(const facet_draw* draw, const facet_vertex_batch* batch);
typedef void (*facet_fragment_fn)(const facet_draw* draw, facet_fragment_batch* batch);

typedef struct facet_fragment_entry {
    uint32_t isa;               /* enum facet_isa                            */
    facet_fragment_fn fragment;
} facet_fragment_entry;

typedef struct facet_shader_desc {
    uint32_t struct_size;            /* sizeof(facet_shader_desc) in the plugin   */
    uint32_t needs;                  /* enum facet_need bits                      */
    uint32_t flags;                  /* enum facet_shader_flag bits               */
    uint32_t varying_count;
    const facet_varying_desc* varyings;
    /* The last `conditional_varyings` varyings are read only when parameter
     * `varyings_condition` (an index into the schema: a TEXTURE or a BOOL)
     * is not 0, as a normal map's tangent is read only with a normal map
     * bound. When it is 0 the host may leave them uninterpolated: their
     * floats in a fragment batch are then unspecified, and the fragment
     * function must not read them; the vertex function need not write
     * them, and the host reads nothing of them. A TEXTURE whose UV is one of them must
     * be the condition itself. 0: every varying is read. */
    uint32_t conditional_varyings;
    uint32_t varyings_condition;
    facet_vertex_fn vertex;
    uint32_t fragment_count;         /* 1..: one entry per instruction set        */
    const facet_fragment_entry* fragments;
    /* ABI 2.1. 1 + the index of the varying that carries the second set of
     * texture coordinates (from FACET_NEED_UV1), where the host samples a
     * texture parameter that a material binds to set 1; 0: none. It must
     * have two components or more, and not be conditional. */
    uint32_t second_uv;
    /* ABI 2.1. 1 + the index of a second TEXTURE or BOOL parameter: the
     * conditional varyings are then read when either condition is not 0
     * (a normal map's tangent and a per-vertex mode's terms can share
     * them); 0: none. A 2.0 host ignores it, and interpolates them under
     * the first condition alone: <facet/shader.hpp> then gives the
     * fragment function zeros for them. */
    uint32_t varyings_condition_also;
} facet_shader_desc;

/* ------------------------------------------------------------------------ */
/* Lights and their shadows, as the host passes them (world space). */

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

/* A shadow map: what a shadow-casting light sees of the casters, rendered
 * by the host before the main pass when a visible material needs it. A
 * shader filters it itself (<facet/shadows.hpp>), so its own parameters
 * choose the kernel and the bias.
 *
 * A texel holds the distance of the nearest caster along the light's axis
 * (orthographic: window depth; perspective: clip w), as (distance -
 * near_plane) / (far_plane - near_plane) * 65535 rounded up: 0 at the near
 * plane, 65535 at the far plane and wherever nothing was drawn. Around the
 * map lies a border of FACET_SHADOW_BORDER texels that reads 65535, or,
 * for a cube's face, the distances just past its edge, so that a kernel
 * centred on the map never reads past its storage: texel (x, y), for
 * -FACET_SHADOW_BORDER <= x < width + FACET_SHADOW_BORDER and the same for
 * y, is texels[y * stride + x].
 *
 * Tiles bound the distances between two parallel planes, from which a
 * filter sees at once, for most receivers, that every tap of its kernel is
 * lit or that none is, and reads no texel. Tile (tx, ty), for 0 <= tx <
 * width / FACET_SHADOW_TILE and the same for ty by height, begins at texel
 * (x0, y0) = FACET_SHADOW_TILE (tx, ty); its four floats, from
 * tiles + 4 (ty * tile_stride + tx), are {nearest, dx, dy, depth}: every
 * stored texel (x, y) within FACET_SHADOW_REACH texels of the tile on each
 * axis (x0 - REACH <= x < x0 + TILE + REACH, and the same for y; border
 * included) holds a distance between nearest + dx (x - x0) + dy (y - y0)
 * and that plus depth, the floats taken as exact numbers, with |dx| and
 * |dy| at most 2048 and nearest and nearest + depth within +-2^17 (so that
 * a filter's float sums stay within 2^18, where they round by 1/64 at
 * most). The host makes them for a map whose width and height are
 * multiples of FACET_SHADOW_TILE once it has kept the map for a frame;
 * until then `tiles` is NULL. */
#define FACET_SHADOW_BORDER 8
#define FACET_SHADOW_TILE 8
#define FACET_SHADOW_REACH 4

enum facet_shadow_projection { FACET_SHADOW_ORTHOGRAPHIC = 0, FACET_SHADOW_PERSPECTIVE = 1 };

typedef struct facet_shadow_map {
    uint32_t projection;         /* enum facet_shadow_projection              */
    uint32_t width, height;      /* texels                                    */
    uint32_t stride;             /* texels from one row to the next           */
    float view_projection[16];   /* world -> light clip space, depth 0..w     */
    float near_plane, far_plane; /* of that projection (standard, not reversed) */
    float texel_size;            /* world size of a texel: orthographic, in   */
                                 /*   world units; perspective, per unit of   */
                                 /*   distance from the light                 */
    uint32_t tile_stride;        /* tiles from one row of tiles to the next   */
    const uint16_t* texels;      /* texel (0, 0), top row first               */
    const float* tiles;          /* tile (0, 0), or NULL                      */
} facet_shadow_map;

/* One light's shadow, parallel to facet_draw.lights: no map, one (a
 * directional or spot light), or a cube of six for a point light, in the
 * order +X, -X, +Y, -Y, +Z, -Z of the direction from the light, each face
 * a perspective map of 90 degrees. */
typedef struct facet_shadow {
    uint32_t map_count;          /* 0, 1 or 6                                 */
    uint32_t reserved;           /* 0                                         */
    const facet_shadow_map* maps;
} facet_shadow;

/* ------------------------------------------------------------------------ */
/* A draw, and the batches a shader shades. */

typedef struct facet_host facet_host;

/* One object drawn with one material. Read-only. */
struct facet_draw {
    const facet_host* host;
    const void* params;            /* the material's parameter block; never  */
                                   /*   NULL (zeros if there are no params)  */
    const void* host_data;         /* opaque to the plugin                   */
    /* transforms */
    float model[16];
    float view[16];
    float projection[16];
    float view_projection[16];
    float model_view_projection[16];
    float normal_matrix[16];       /* inverse-transpose of model up to a positive */
                                   /*   scale (3x3 in a 4x4): normalise normals */
    /* camera and frame */
    float camera_position[4];      /* world space, w = 1                     */
    uint32_t viewport_width;
    uint32_t viewport_height;
    float time;                    /* seconds, for animated shaders          */
    /* lighting */
    uint32_t light_count;          /* 0 unless FACET_NEED_LIGHTS             */
    const facet_light* lights;
    const facet_shadow* shadows;   /* [light_count] if FACET_NEED_SHADOW_MAP */
                                   /*   and the frame drew shadow maps, else */
                                   /*   NULL                                 */
};

/* A batch of vertices. Inputs are arrays indexed by vertex; an input the
 * shader did not ask for is NULL. */
struct facet_vertex_batch {
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
                             /*   shader needs FACET_NEED_TANGENTS and the  */
                             /*   mesh has tangents (a loaded mesh with UVs */
                             /*   does; one made in code may not)           */
    float* clip_position;    /* out: [count][4]                              */
    float* varyings;         /* out: [count][varying_floats]                 */
    uint32_t varying_floats; /* sum of the declared varyings' components    */
    /* ABI 2.1 (read it only from a host of abi_minor 1 or more): */
    const float* uv1;        /* [count][2] a second set of texture           */
                             /*   coordinates (glTF's TEXCOORD_1), or NULL  */
                             /*   unless FACET_NEED_UV1 and the mesh has it */
};

/* A fragment batch is one 4x4 block of pixels, lane i pixel
 * (x + i % 4, y + i / 4), or, for a FACET_SHADER_PACKABLE shader, 16
 * pixels from anywhere (coord). In a block the 2x2 quads are lanes
 * {0,1,4,5}, {2,3,6,7}, {8,9,12,13}, {10,11,14,15}, so derivatives are
 * differences within a quad. */
#define FACET_BLOCK_SIZE 4
#define FACET_BLOCK_LANES 16

/* Structure-of-arrays layout: float k of the varyings for lane i is
 * varyings[k * FACET_BLOCK_LANES + i]. In a block every lane holds
 * interpolated values, covered or not; in a packed batch only the lanes
 * in the mask do. */
struct facet_fragment_batch {
    int32_t x, y;           /* a block: the pixel of lane 0                  */
    const float* coord;     /* a packed batch: [2][16] window x, y of each   */
                            /*   lane's pixel centre; NULL in a block (there */
                            /*   x + i % 4 + 0.5, y + i / 4 + 0.5)           */
    uint32_t mask;          /* in: lanes covered and passing depth; out: a   */
                            /*   shader with FACET_NEED_DISCARD clears bits   */
    uint32_t front_facing;  /* 1 if the triangle faces the viewer            */
    const float* varyings;  /* [varying_floats][16]                         */
    const float* depth;     /* [16] window depth, 0..1                       */
    const float* texels;    /* [texture slot][4][16] linear RGBA at each     */
                            /*   texture's uv_varying, or NULL               */
    const float* ao;        /* [16] ambient visibility 0..1 (screen-space AO, */
                            /*   blurred) if FACET_NEED_AO and the frame ran  */
                            /*   an AO pass; else NULL: read 1               */
    float* color;           /* out: [4][16] linear RGBA                      */
};

/* ------------------------------------------------------------------------ */
/* Screen passes. A screen pass works on the finished image: the scene's
 * passes (`post: [...]`) run in order on a float target, in linear light,
 * after the MSAA resolve and before the conversion to the output format.
 * The host calls its function once a frame, on one thread; the pass
 * shares its work out to the host's threads itself, and keeps its
 * intermediate images in the host's scratch memory (facet_pass_service). */

typedef struct facet_pass_frame {
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
} facet_pass_frame;

typedef void (*facet_pass_fn)(const facet_pass_frame* frame);

typedef struct facet_pass_desc {
    uint32_t struct_size;    /* sizeof(facet_pass_desc) in the plugin       */
    facet_pass_fn run;
} facet_pass_desc;

/* ------------------------------------------------------------------------ */
/* The host's services, passed with every draw and frame. */

enum facet_log_level { FACET_LOG_DEBUG = 0, FACET_LOG_INFO = 1, FACET_LOG_WARN = 2, FACET_LOG_ERROR = 3 };

struct facet_host {
    uint16_t abi_major;
    uint16_t abi_minor;
    uint32_t struct_size;
    /* Logs a message under the plugin's name. Thread-safe. */
    void (*log)(int level, const char* plugin, const char* message);
    /* An optional service, by its id and the version the plugin was built
     * against: a record that starts with its struct_size, or NULL when the
     * host has no such service in that version. The pointer stays valid
     * while the plugin is loaded. Thread-safe. */
    const void* (*extension)(const char* id, uint32_t version);
};

/* "facet.textures", version 2: a draw's texture parameters sampled where
 * the shader wants them, with their filter and wrap, on the draw's
 * instruction-set path. Version 1's record ends before sample_grad: ask
 * for version 2, and for 1 where a host has no 2. */
#define FACET_TEXTURES_EXTENSION "facet.textures"
#define FACET_TEXTURES_VERSION 2u

enum facet_texture_kind {
    FACET_TEXTURE_NONE = 0, /* nothing bound: samples read white               */
    FACET_TEXTURE_2D = 1,
    FACET_TEXTURE_CUBE = 2  /* six square faces, +X, -X, +Y, -Y, +Z, -Z        */
};

typedef struct facet_texture_info {
    uint32_t kind;          /* enum facet_texture_kind                          */
    uint32_t width, height; /* level 0 (a cube: each face)                      */
    uint32_t levels;        /* mip levels, 1 when the filter reads level 0 only
                               (nearest, bilinear)                              */
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
    /* Version 2. As sample, with each lane's screen derivatives of a 2D
     * texture's coordinates: grads[k * count + i] is du/dx, dv/dx, du/dy,
     * dv/dy of lane i, in UV units a pixel. A binding filtered
     * `anisotropic` filters over the footprint they span, as GLSL's
     * textureGrad (and ignores lod). Every other binding, and a cube map,
     * does not read them: it reads at lod as sample does (NULL lod: level
     * 0), so give the level the derivatives give as well. NULL grads: as
     * sample. Thread-safe. */
    void (*sample_grad)(const facet_draw* draw, uint32_t slot, const float* coords,
                        const float* lod, const float* grads, uint32_t count, uint32_t mask,
                        float* rgba);
} facet_textures_service;

/* "facet.environment", version 1: the light arriving from the scene's
 * environment (an image all around it, `environment:` in a scene),
 * prefiltered by the host at load, for a shader to light by.
 *
 * The maps hold radiance in their own frame; a world direction d is looked
 * up at to_environment * d. Linear RGB, times `intensity`:
 *   - Diffuse: irradiance / pi (the radiance of a uniform environment that
 *     would give as much) at unit normal n, in the maps' frame, intensity
 *     included: c[0] + c[1] y + c[2] z + c[3] x + c[4] x y + c[5] y z
 *     + c[6] (3 z^2 - 1) + c[7] x z + c[8] (x^2 - y^2), c = irradiance[k]
 *     (RGB, and a 0). The nine spherical harmonics of the radiance, each
 *     convolved with the cosine lobe (Ramamoorthi and Hanrahan 2001); where
 *     a bright source makes it ring below 0, read 0.
 *   - Specular: level l of `levels` holds the radiance convolved with the
 *     GGX lobe of perceptual roughness l / (levels - 1) (alpha its square)
 *     around each direction, as the split sum takes it (normal = view =
 *     reflection; Karis 2013); level 0 is the environment itself. A level
 *     is six square faces, +X, -X, +Y, -Y, +Z, -Z (as cube maps lie,
 *     facet_textures_service), each size[l] texels a side with a border of
 *     one texel all round that holds the texels of the directions just past
 *     its edges: texel (x, y) of face f, for -1 <= x, y <= size[l], is
 *     texels + 4 * (offset[l] + f * (size[l] + 2)^2 + (y + 1) * (size[l] + 2)
 *     + x + 1), RGBA float with A = 1. A face's texel (x, y) is centred on
 *     ((x + 0.5) / size, (y + 0.5) / size) of the face's 0..1 square, so
 *     bilinear filtering needs no clamp and shows no seam.
 *   - The split-sum BRDF: the specular light reflected is the level's
 *     radiance times f0 A + B (Schlick's Fresnel, GGX, Smith's
 *     height-correlated visibility). brdf holds brdf_size^2 cells, cell
 *     (i, j) at n.v = i / (brdf_size - 1) and perceptual roughness
 *     j / (brdf_size - 1): floats brdf + 4 (j brdf_size + i) are A and B of
 *     that cell and of cell (i + 1, j) (for the last i, the same again), so
 *     that one 16-byte read gives both cells a bilinear tap takes from a row.
 */
#define FACET_ENVIRONMENT_EXTENSION "facet.environment"
#define FACET_ENVIRONMENT_VERSION 1u
#define FACET_ENVIRONMENT_MAX_LEVELS 16

typedef struct facet_environment {
    uint32_t struct_size;
    uint32_t levels;                                /* 1..FACET_ENVIRONMENT_MAX_LEVELS */
    float to_environment[9];                        /* a rotation, 3x3 column-major    */
    float intensity;                                /* of the specular levels          */
    float irradiance[9][4];
    uint32_t size[FACET_ENVIRONMENT_MAX_LEVELS];    /* texels a side of level l's faces */
    uint32_t offset[FACET_ENVIRONMENT_MAX_LEVELS];  /* in texels: face 0's (-1, -1)    */
    const float* texels;
    uint32_t brdf_size;                             /* at least 2                      */
    const float* brdf;
} facet_environment;

typedef struct facet_environment_service {
    uint32_t struct_size;
    /* The environment lighting `draw`, or NULL when its scene has none or
     * shows it only as a background. Thread-safe; it stays valid for the
     * draw. */
    const facet_environment* (*lighting)(const facet_draw* draw);
} facet_environment_service;

/* "facet.pass", version 1: threads and memory for a screen pass. Call them
 * only from the pass's function, never from one of its tasks. */
#define FACET_PASS_EXTENSION "facet.pass"
#define FACET_PASS_VERSION 1u
#define FACET_PASS_SCRATCH_SLOTS 16

typedef struct facet_pass_service {
    uint32_t struct_size;
    /* Runs task(context, i, worker) once for each i in 0..count-1 on the
     * host's threads, the caller's among them, and returns when every call
     * has; worker (below frame->threads) tells a task which per-thread
     * scratch it may use. Called from a task, it runs the tasks on the
     * calling thread, one after the other, and logs an error. */
    void (*parallel_for)(const facet_pass_frame* frame, uint32_t count,
                         void (*task)(void* context, uint32_t index, uint32_t worker),
                         void* context);
    /* `bytes` bytes, 64-byte aligned, under number `slot`
     * (0..FACET_PASS_SCRATCH_SLOTS-1) of this pass in this chain. The host
     * keeps them between frames (their contents are undefined at each
     * frame's start) and frees them with the chain. NULL when the memory
     * budget refuses them (the pass then leaves the image as it is), and
     * when called from a task. */
    void* (*scratch)(const facet_pass_frame* frame, uint32_t slot, size_t bytes);
} facet_pass_service;

/* ------------------------------------------------------------------------ */
/* The descriptor a plugin's entry point returns. Exactly one of shader and
 * pass is set. */

typedef struct facet_plugin_desc {
    uint16_t abi_major;              /* FACET_ABI_MAJOR the plugin was built with */
    uint16_t abi_minor;              /* FACET_ABI_MINOR the plugin was built with */
    uint32_t struct_size;            /* sizeof(facet_plugin_desc) in the plugin   */
    const char* name;                /* must match the library's file name        */
    const char* version;             /* free-form, for logs                       */
    facet_schema schema;
    const facet_shader_desc* shader; /* a material shader, or NULL                */
    const facet_pass_desc* pass;     /* a screen pass, or NULL                    */
} facet_plugin_desc;

typedef const facet_plugin_desc* (*facet_plugin_entry_fn)(void);

#ifdef __cplusplus
}
#endif

#endif /* FACET_SHADER_ABI_H */
