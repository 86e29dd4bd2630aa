/* The C API (facet/facet.h), from C99: every call, and the errors of bad
 * input. Run by the test command (tests/CMakeLists.txt: c_api); prints
 * each failed check and exits non-zero if any failed. */
#include <facet/facet.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond)                                                               \
    do {                                                                          \
        if (!(cond)) {                                                            \
            fprintf(stderr, "%s:%d: failed: %s (last error: %s)\n", __FILE__,    \
                    __LINE__, #cond, facet_error_message());                      \
            ++failures;                                                           \
        }                                                                         \
    } while (0)

/* Whether the last error's message holds `part`. */
static int said(const char* part) { return strstr(facet_error_message(), part) != NULL; }

/* A phong sphere beside the installed demo scenes, lit by one light. */
static const char* kScene =
    "camera: {position: [0, 0, 3], target: [0, 0, 0], fov_y: 45}\n"
    "render: {size: [32, 24], clear_color: [0.1, 0.2, 0.3, 1]}\n"
    "lights:\n"
    "  - {name: sun, type: directional, direction: [-1, -1, -1], color: [1, 1, 1], intensity: 2}\n"
    "objects:\n"
    "  - name: ball\n"
    "    mesh: ../../assets/sphere/sphere.obj\n"
    "    material: {shader: phong, params: {diffuse: [0.8, 0.3, 0.2]}}\n";

static double sum(const unsigned char* p, size_t n) {
    double s = 0;
    for (size_t i = 0; i < n; ++i) s += p[i];
    return s;
}

static void errors(facet_scene* scene, const char* origin) {
    const float rgb[3] = {1, 1, 1}, one = 1, two[2] = {1, 2}, nan3[3] = {NAN, 0, 0};
    const float elsewhere[3] = {1, 2, 3};
    CHECK(facet_scene_load("no-such-scene.yaml") == NULL && said("no-such-scene.yaml"));
    CHECK(strcmp(facet_error_file(), "no-such-scene.yaml") == 0);
    CHECK(facet_scene_load_yaml("objects: [", origin) == NULL && facet_error_line() > 0);
    CHECK(facet_scene_load_yaml("camera: {fov_y: 400}\n", origin) == NULL && said("fov_y"));
    CHECK(facet_scene_set_param(scene, "nobody", "diffuse", rgb, 3) == FACET_FAILED &&
          said("no object named 'nobody'"));
    CHECK(facet_scene_set_param(scene, "ball", "no_such", rgb, 3) == FACET_FAILED &&
          said("no_such"));
    CHECK(facet_scene_set_param(scene, "ball", "diffuse", two, 2) == FACET_FAILED &&
          said("takes 3"));
    CHECK(facet_scene_set_param(scene, "ball", "base_texture", &one, 1) == FACET_FAILED &&
          said("texture"));
    CHECK(facet_scene_set_param(scene, "ball", "diffuse", nan3, 3) == FACET_FAILED &&
          said("finite"));
    CHECK(facet_scene_set_param(scene, "ball", "shininess", &one, 0) == FACET_FAILED);
    CHECK(facet_scene_set_light(scene, 3, rgb, 1) == FACET_FAILED && said("light 3"));
    CHECK(facet_scene_set_camera(scene, rgb, rgb, 45) == FACET_FAILED);
    CHECK(facet_scene_set_camera(scene, rgb, elsewhere, 200) == FACET_FAILED &&
          said("field of view"));
    CHECK(facet_scene_set_time(scene, NAN) == FACET_FAILED);
    CHECK(facet_scene_set_size(scene, 0, 10) == FACET_FAILED);
    CHECK(facet_scene_set_param(NULL, "ball", "diffuse", rgb, 3) == FACET_FAILED && said("NULL"));
    CHECK(facet_renderer_new(-1) == NULL);
}

int main(void) {
    CHECK(facet_set_log_level("loud") == FACET_FAILED && said("loud"));
    CHECK(facet_set_log_level("warn") == FACET_OK);
    CHECK(facet_api_version() >> 16 == FACET_API_MAJOR);
    CHECK((int)(facet_api_version() & 0xFFFF) >= (int)FACET_API_MINOR);
    const char* def = facet_default_scene();
    CHECK(def != NULL);
    if (!def) return 1;
    /* The text's files beside the demo scenes: configs/scenes/api.yaml. */
    char origin[4096];
    snprintf(origin, sizeof origin, "%.*sscenes/api.yaml", (int)(strrchr(def, '/') - def + 1), def);

    facet_scene* scene = facet_scene_load_yaml(kScene, origin);
    facet_renderer* renderer = facet_renderer_new(2);
    CHECK(scene != NULL && renderer != NULL);
    if (!scene || !renderer) return 1;
    int w = 0, h = 0;
    CHECK(facet_scene_size(scene, &w, &h) == FACET_OK && w == 32 && h == 24);
    CHECK(facet_scene_light_count(scene) == 1);
    CHECK(facet_scene_light_index(scene, "sun") == 0);
    CHECK(facet_scene_light_index(scene, "moon") == -1 && said("no light named 'moon'"));

    /* 8-bit, rows with room between them that is left alone. */
    const size_t stride = (size_t)w * 4 + 12;
    unsigned char* a = malloc(stride * (size_t)h);
    unsigned char* b = malloc(stride * (size_t)h);
    float* f = malloc((size_t)w * (size_t)h * 16);
    memset(a, 0xAB, stride * (size_t)h);
    memset(b, 0xAB, stride * (size_t)h);
    CHECK(facet_render_rgba8(renderer, scene, a, stride) == FACET_OK);
    CHECK(a[stride - 1] == 0xAB && a[stride * (size_t)h - 1] == 0xAB);
    /* The clear colour in a corner, the sphere in the middle. */
    CHECK(a[0] != a[(size_t)(h / 2) * stride + (size_t)(w / 2) * 4]);
    CHECK(facet_render_rgba8(renderer, scene, b, stride) == FACET_OK);
    CHECK(memcmp(a, b, stride * (size_t)h) == 0);
    CHECK(facet_render_rgba32f(renderer, scene, f, (size_t)w * 16) == FACET_OK);
    CHECK(fabsf(f[3] - 1.0f) < 1e-6f && fabsf(f[0] - 0.1f) < 1e-6f);  /* the clear colour */
    CHECK(facet_render_rgba8(renderer, scene, a, 4) == FACET_FAILED && said("stride"));

    /* What each setter changes: each image differs from the one before. */
    const size_t bytes = stride * (size_t)h;
    const float black[3] = {0, 0, 0}, white[3] = {1, 1, 1}, dim[3] = {0.2f, 0.2f, 0.2f};
    const double lit = sum(b, bytes);
    CHECK(facet_scene_set_param(scene, "ball", "diffuse", black, 3) == FACET_OK);
    CHECK(facet_render_rgba8(renderer, scene, a, stride) == FACET_OK);
    CHECK(sum(a, bytes) < lit);
    CHECK(facet_scene_set_light(scene, 0, dim, 1) == FACET_OK);  /* black: no change to see */
    CHECK(facet_scene_set_param(scene, "ball", "diffuse", white, 3) == FACET_OK);
    CHECK(facet_render_rgba8(renderer, scene, b, stride) == FACET_OK);
    CHECK(sum(b, bytes) > sum(a, bytes));
    CHECK(facet_scene_set_light(scene, 0, white, 2) == FACET_OK);
    CHECK(facet_render_rgba8(renderer, scene, a, stride) == FACET_OK);
    CHECK(sum(a, bytes) > sum(b, bytes));  /* a brighter light */
    const float eye[3] = {0, 0, 30}, at[3] = {0, 0, 0};
    CHECK(facet_scene_set_camera(scene, eye, at, 10) == FACET_OK);
    CHECK(facet_render_rgba8(renderer, scene, b, stride) == FACET_OK);
    CHECK(memcmp(a, b, bytes) != 0);  /* farther, narrower: another picture */
    CHECK(facet_scene_set_time(scene, 1.5) == FACET_OK);
    CHECK(facet_scene_set_size(scene, 16, 8) == FACET_OK);
    CHECK(facet_scene_size(scene, &w, &h) == FACET_OK && w == 16 && h == 8);
    memset(a, 0xAB, bytes);
    CHECK(facet_render_rgba8(renderer, scene, a, stride) == FACET_OK);
    CHECK(a[8 * stride] == 0xAB && a[16 * 4] == 0xAB);  /* rows and columns past 16x8 untouched */
    CHECK(a[7 * stride + 15 * 4 + 3] == 255);            /* the last pixel written: opaque */

    errors(scene, origin);
    CHECK(facet_write_png("c_api_test.png", w, h, a, stride) == FACET_OK);
    FILE* png = fopen("c_api_test.png", "rb");
    unsigned char signature[8] = {0};
    CHECK(png && fread(signature, 1, 8, png) == 8 && signature[1] == 'P' && signature[2] == 'N');
    if (png) fclose(png);
    remove("c_api_test.png");
    CHECK(facet_write_png("/no/such/folder/x.png", w, h, a, stride) == FACET_FAILED &&
          said("x.png"));

    free(a);
    free(b);
    free(f);
    facet_renderer_free(renderer);
    facet_scene_free(scene);
    if (failures) fprintf(stderr, "%d check(s) failed\n", failures);
    return failures ? 1 : 0;
}
