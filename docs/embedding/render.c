/* render: facet from C. Renders a scene into a buffer of this program's
 * own and writes it as a PNG.
 *
 *     render [SCENE.yaml [out.png]]      (default: facet's default scene, facet.png)
 *
 * Built against an installed facet with pkg-config alone:
 *
 *     cc -std=c99 -O2 render.c -o render \
 *        -DFACET_PREFIX_DIR="\"$(pkg-config --variable=prefix facet)\"" \
 *        $(pkg-config --cflags --libs --static facet)
 */
#include <facet/facet.h>

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char** argv) {
    /* Where facet's shaders and default scene are. */
    if (facet_set_install_root(FACET_PREFIX_DIR) != FACET_OK) goto failed;
    const char* scene_file = argc > 1 ? argv[1] : facet_default_scene();
    const char* out = argc > 2 ? argv[2] : "facet.png";
    facet_scene* scene = scene_file ? facet_scene_load(scene_file) : NULL;
    if (!scene) goto failed;

    /* One renderer for as many frames as you like (0: a thread a core). */
    facet_renderer* renderer = facet_renderer_new(0);
    int width, height;
    if (!renderer || facet_scene_size(scene, &width, &height) != FACET_OK) goto failed;
    const size_t stride = (size_t)width * 4;
    unsigned char* pixels = malloc(stride * (size_t)height);
    if (!pixels) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    if (facet_render_rgba8(renderer, scene, pixels, stride) != FACET_OK ||
        facet_write_png(out, width, height, pixels, stride) != FACET_OK)
        goto failed;
    printf("wrote %s (%dx%d)\n", out, width, height);
    free(pixels);
    facet_renderer_free(renderer);
    facet_scene_free(scene);
    return 0;

failed:
    /* The message names the file and line where there is one. */
    fprintf(stderr, "%s\n", facet_error_message());
    return 1;
}
