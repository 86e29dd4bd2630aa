/* facet's C API (C99): load a scene, change it, render it into your own
 * buffer. For C programs, a game engine's C layer, or a language binding.
 *
 *     facet_scene* scene = facet_scene_load("scene.yaml");
 *     facet_renderer* renderer = facet_renderer_new(0);
 *     int w, h;
 *     if (!scene || !renderer || facet_scene_size(scene, &w, &h)) { ...facet_error_message()... }
 *     unsigned char* rgba = malloc((size_t)w * h * 4);
 *     if (facet_render_rgba8(renderer, scene, rgba, (size_t)w * 4))
 *         fprintf(stderr, "%s\n", facet_error_message());
 *
 * Errors: a function that fails returns NULL or a non-zero facet_status,
 * and leaves the error for the calling thread to read with
 * facet_error_message(), facet_error_file() and facet_error_line() until
 * its next call into facet. facet also logs what it does to standard error
 * (facet_set_log_level). A handle is used by one thread at a time;
 * different handles may be used from different threads.
 *
 * Compatibility: FACET_API_MAJOR changes only when a function is removed
 * or changes what it means; FACET_API_MINOR grows when functions are added.
 * A program built against major M and minor m runs with a library whose
 * facet_api_version() has major M and minor at least m.
 *
 * Link: pkg-config --cflags --libs --static facet (the library is C++; the
 * static link brings its C++ runtime). Where facet is installed (its
 * shaders and default scene) comes from facet_set_install_root(). */
#ifndef FACET_FACET_H
#define FACET_FACET_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FACET_API_MAJOR 1
#define FACET_API_MINOR 0

/* The library's version, FACET_API_MAJOR << 16 | FACET_API_MINOR as built. */
unsigned facet_api_version(void);

typedef enum facet_status {
    FACET_OK = 0,
    FACET_FAILED = 1 /* the error says why */
} facet_status;

/* The calling thread's last error: its message ("" when the last call
 * succeeded), the file it is about ("" when none) and the line there (0
 * when not known). The strings live until the thread's next call. */
const char* facet_error_message(void);
const char* facet_error_file(void);
int facet_error_line(void);

/* Where facet is installed (the prefix: its lib/facet/plugins, its
 * share/facet). Programs in facet's own build find it themselves. */
facet_status facet_set_install_root(const char* prefix);
/* The default scene's file (share/facet/configs/default.yaml), or NULL. */
const char* facet_default_scene(void);
/* The least a log line must be to go to standard error: "trace", "debug",
 * "info" (the default), "warn", "error" or "off". */
facet_status facet_set_log_level(const char* level);

/* ---- scenes ------------------------------------------------------------ */

typedef struct facet_scene facet_scene;

/* A scene file, with its meshes, materials, textures and shaders; NULL on
 * error. */
facet_scene* facet_scene_load(const char* path);
/* A scene from YAML text, read as if it were the file `origin` (its folder
 * resolves the files the text names; NULL: "scene.yaml" in the current
 * folder). */
facet_scene* facet_scene_load_yaml(const char* yaml, const char* origin);
void facet_scene_free(facet_scene* scene);

/* The image size, and a new one (1..32768 a side). */
facet_status facet_scene_size(const facet_scene* scene, int* width, int* height);
facet_status facet_scene_set_size(facet_scene* scene, int width, int height);

/* The camera: where it is, what it looks at, and its vertical field of
 * view in degrees (0 < fov_y < 180). It stays, whatever the time. */
facet_status facet_scene_set_camera(facet_scene* scene, const float position[3],
                                    const float target[3], float fov_y);

/* Sets material parameter `param` of every material the object named
 * `object` is drawn with (the object alone: a material it shares with
 * others is copied for it) to `count` numbers: 1 for a float, int or bool,
 * 2 to 4 for a vector or colour (as many as it has), each checked against
 * the parameter's range. Fails naming the object or parameter when there is
 * none of that name, or the parameter is of another type (a texture, or a
 * choice, which a file names) or size. */
facet_status facet_scene_set_param(facet_scene* scene, const char* object, const char* param,
                                   const float* values, int count);

/* The number of lights; the index of the first named `name` (a light's
 * `name:` in the file), or -1 with an error naming it; and light `index`
 * (in the file's order): its linear RGB colour and its intensity (at
 * least 0). */
int facet_scene_light_count(const facet_scene* scene);
int facet_scene_light_index(const facet_scene* scene, const char* name);
facet_status facet_scene_set_light(facet_scene* scene, int index, const float color[3],
                                   float intensity);

/* Poses the scene's animation at `seconds` (finite). */
facet_status facet_scene_set_time(facet_scene* scene, double seconds);

/* ---- rendering --------------------------------------------------------- */

typedef struct facet_renderer facet_renderer;

/* A renderer with `threads` threads, counting the caller (0: one per
 * hardware thread, or FACET_NUM_THREADS). It keeps its threads and buffers
 * between frames. */
facet_renderer* facet_renderer_new(int threads);
void facet_renderer_free(facet_renderer* renderer);

/* Renders `scene` at its size into the caller's pixels, top row first,
 * `stride` bytes from a row to the next (at least width * 4 and width * 16):
 * 8-bit sRGB-encoded RGBA, as facet-render writes; or linear RGBA floats,
 * before any post-processing pass. */
facet_status facet_render_rgba8(facet_renderer* renderer, facet_scene* scene,
                                unsigned char* pixels, size_t stride);
facet_status facet_render_rgba32f(facet_renderer* renderer, facet_scene* scene, float* pixels,
                                  size_t stride);

/* Writes 8-bit RGBA pixels (top row first, `stride` bytes a row) as a PNG,
 * replacing `path` only once the whole file is written. */
facet_status facet_write_png(const char* path, int width, int height, const unsigned char* pixels,
                             size_t stride);

#ifdef __cplusplus
}
#endif

#endif /* FACET_FACET_H */
