// facet-bench --llvmpipe: the same scene drawn by Mesa's llvmpipe, for scale.
//
// An LlvmpipeRenderer draws a facet::Scene through OSMesa (gallium
// llvmpipe, an OpenGL 4.5 core context) with GLSL versions of facet's
// `phong` and `unlit` plugins. It reads each object's mesh, transform and
// material parameters, the camera and the lights from the Scene, so both
// renderers get the same input, and it sets GL up to follow facet's rules
// as far as GL allows:
//   - facet's own view and projection matrices, clip depth 0..w
//     (glClipControl ZERO_TO_ONE), the depth buffer cleared as facet clears
//     it (0 with reversed_z, else 1), and each draw's PipelineState: the
//     settings' depth_compare as glDepthFunc (GEQUAL by default), the
//     material's depth writes, cull mode and the front face;
//   - a float32 depth buffer, and one sample per pixel or four (the
//     settings' msaa; GL's standard 4x positions are facet's, and image()
//     resolves them with glBlitFramebuffer);
//   - the same coverage: pixel centres, 8 sub-pixel bits, and facet's
//     top-left rule (llvmpipe's own rule is bottom-left, so the image is
//     drawn upside down in GL and read back in facet's row order). The two
//     snap vertices from float (llvmpipe) and double (facet) window
//     coordinates, so a pixel centre within about 1/10000 pixel of an edge
//     can still fall differently;
//   - the colour buffer is linear float RGBA, like facet's (rgba32f), or
//     srgb8: GL_SRGB8_ALPHA8 with GL_FRAMEBUFFER_SRGB, so that llvmpipe
//     encodes each fragment's linear colour to 8-bit sRGB as it writes it
//     (4 bytes a pixel instead of 16), what a GL program would usually
//     render to; facet still writes rgba32f, and image() reads srgb8 back
//     decoded to linear;
//   - geometry is uploaded once (VBOs and an IBO per object), as facet's
//     meshes stay in memory between frames;
//   - the colour is the plugins' formulas, base textures included: each
//     is uploaded with facet's own mip chain, in GL_SRGB8_ALPHA8 for a
//     colour texture (decoded before filtering, as facet does) or GL_RGBA8,
//     with the binding's filter (nearest, bilinear from level 0, or
//     trilinear: GL_LINEAR_MIPMAP_LINEAR) and wrap, and the material's
//     alpha cutoff discards as facet's does.
//   - blending as facet blends: each material's factors and equations
//     (glBlendFuncSeparate, glBlendEquationSeparate, glBlendColor; a named
//     mode as its factors), blended parts drawn after the opaque ones,
//     farthest first, as facet orders them.
//   - a material's `draw`: its part's triangles, its edges (each once) as
//     GL_LINES of its line_width, or its vertices as GL_POINTS of its
//     point_size; flat varyings from a line's first end point. GL draws a
//     line as facet's rectangle only with multisampling (single-sampled,
//     it follows the diamond-exit rule).
// What it does not do: normal maps, MSAA other than 1 or 4 samples,
// alpha to coverage (GL's samples are not facet's dither),
// subpixel_bits other than 8, wireframe (facet's wire over pushed-back
// surfaces), shadow maps, AO, or any shader other than phong and unlit
// (supports() says which). upload() and render() throw for those settings
// rather than draw something else than facet.
//
// llvmpipe reads its thread count (LP_NUM_THREADS) once per process, when
// OSMesa creates its screen; worker.hpp runs each measurement in a
// child process for that reason. Needs OSMesa (FACET_HAVE_OSMESA).
#pragma once

#include <facet/scene.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace facet::bench {

// The colour buffer llvmpipe renders into.
enum class LlvmpipeTarget { rgba32f, srgb8 };

class LlvmpipeRenderer {
public:
    // An OSMesa context with a width x height framebuffer object. Throws
    // std::runtime_error when OSMesa cannot make a core 4.5 llvmpipe context.
    // Each call below makes that context current on the calling thread.
    LlvmpipeRenderer(int width, int height, LlvmpipeTarget target);
    ~LlvmpipeRenderer();
    LlvmpipeRenderer(const LlvmpipeRenderer&) = delete;
    LlvmpipeRenderer& operator=(const LlvmpipeRenderer&) = delete;

    // True when `shader` has a GLSL version here.
    static bool supports(const std::string& shader);
    // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits),
    // OpenGL 4.5 (Core Profile) Mesa 22.3.6".
    std::string renderer_name() const;

    // Uploads every object's mesh once; later frames draw from these
    // buffers. Throws std::runtime_error for what this renderer cannot
    // draw (an unsupported shader, a normal map, alpha to coverage, a base
    // texture with a transform or on a second UV set; settings with msaa
    // other than 1 or 4, subpixel_bits other than 8, or wireframe) and
    // for a GL error, which it names (GL_OUT_OF_MEMORY, ...).
    void upload(const Scene& scene);
    // Draws one frame of `scene` (uploaded before) and waits for it
    // (glFinish). Returns its wall time in milliseconds, clear included.
    // Throws as upload() does for the settings and for GL errors.
    double render(const Scene& scene);
    // The last frame, linear RGBA, top row first (facet's layout). An sRGB
    // target is decoded to linear by GL on reading.
    std::vector<glm::vec4> image() const;
    // 1 where the last frame's RGB is not black, else 0: which pixels any
    // geometry covers, for a frame drawn on a black clear. One byte per
    // pixel, top row first.
    std::vector<uint8_t> coverage() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace facet::bench
