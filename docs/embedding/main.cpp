// embed: render a facet scene into a buffer of your own.
//
//     embed [SCENE.yaml] [out.png]
//
// Loads SCENE (facet's default scene if none), renders it once, copies the
// image into a std::vector<uint8_t> of 8-bit RGBA pixels that this program
// owns, prints its mean colour and, when given out.png, writes it as a PNG.
// CMakeLists.txt shows how it builds against an installed facet.
#include <facet/error.hpp>        // facet::Error: every error, with file:line
#include <facet/framebuffer.hpp>  // facet::Framebuffer, facet::write_png
#include <facet/paths.hpp>        // facet::set_install_root: where facet is
#include <facet/plugin.hpp>       // facet::PluginRegistry: finds shaders by name
#include <facet/renderer.hpp>     // facet::Renderer: draws a scene
#include <facet/scene.hpp>        // facet::Scene, facet::load_scene

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <vector>

int main(int argc, char** argv) {
    // facet finds its shaders, default scene and mesh sandbox in the prefix
    // it is installed in (FACET_PREFIX_DIR comes from CMakeLists.txt).
    facet::set_install_root(FACET_PREFIX_DIR);
    const std::filesystem::path scene_file =
        argc > 1 ? std::filesystem::path(argv[1]) : facet::default_scene_path();
    try {
        // A material's `shader: unlit` means unlit.so in facet's plugin
        // folder (or a folder the scene or FACET_PLUGIN_PATH names).
        facet::PluginRegistry registry;
        // The scene: camera, lights, objects with their meshes, materials
        // and shaders, and render settings (size, MSAA, ...).
        facet::Scene scene = facet::load_scene(scene_file, registry);

        // One renderer for as many frames as you like: it keeps its threads
        // (by default one per core) and buffers. render() sizes the target
        // to the scene.
        facet::Renderer renderer;
        facet::Framebuffer target;
        const facet::FrameStats stats = renderer.render(scene, target);

        // The frame as 8-bit sRGB RGBA, top row first, width * 4 bytes a
        // row, in our own buffer (kept between frames, its memory is reused).
        std::vector<uint8_t> rgba;
        renderer.pipeline().resolve_srgb8(target, rgba);

        // Use the pixels: here, their mean colour.
        double sum[4] = {0, 0, 0, 0};
        for (size_t i = 0; i < rgba.size(); ++i) sum[i % 4] += rgba[i];
        const double pixels = double(target.width()) * target.height();
        std::printf("%s: %dx%d in %.1f ms, %llu triangles drawn, mean RGBA %.1f %.1f %.1f %.1f\n",
                    scene_file.c_str(), target.width(), target.height(), stats.milliseconds,
                    static_cast<unsigned long long>(stats.triangles_rasterized),
                    sum[0] / pixels, sum[1] / pixels, sum[2] / pixels, sum[3] / pixels);
        if (argc > 2) {
            facet::write_png(argv[2], target.width(), target.height(), rgba);
            std::printf("wrote %s\n", argv[2]);
        }
        if (stats.triangles_rasterized == 0) {
            std::fprintf(stderr, "nothing was drawn: is the camera looking at the objects?\n");
            return 1;
        }
        return 0;
    } catch (const facet::Error& e) {  // a bad scene, material, mesh or shader
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
}
