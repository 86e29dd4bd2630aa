// The pipeline: draws meshes with shader plugins into a Framebuffer.
//
// A draw flows: vertex stage (plugin, in batches) -> primitive assembly ->
// homogeneous clipping -> perspective divide and viewport -> fixed-point
// setup and back-face culling -> binning into 64x64 tiles -> rasterization
// in 4x4 blocks -> early depth test -> fragment stage (plugin, one call per
// batch) -> depth write -> blend -> framebuffer. docs/ARCHITECTURE.md names
// the file for each stage.
//
// Takes: DrawCalls (a mesh, a shader, its parameters and state) and a target.
// Gives: the target drawn, and FrameStats of what each draw did and skipped.
// It knows nothing of scenes: Renderer (facet/renderer.hpp) plans a frame of
// a Scene and draws it through a Pipeline.
//
// A Pipeline owns the thread pool and the instruction-set path its stages
// run on, and keeps scratch buffers between draws, so a steady frame
// allocates nothing; use one Pipeline per thread.
#pragma once

#include "facet/framebuffer.hpp"
#include "facet/isa.hpp"
#include "facet/render_state.hpp"

#include <facet/shader_abi.h>

#include <glm/glm.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace facet {

struct Mesh;
struct MeshPart;
class ShaderPlugin;
struct TextureBinding;
class ThreadPool;  // core/src/base/thread_pool.hpp
struct Kernels;    // core/src/pipeline/kernels.hpp
struct DrawQueue;  // core/src/pipeline/draw_queue.hpp
struct AoFrame;    // core/src/pipeline/kernels.hpp
struct SkyRows;    // core/src/pipeline/sky.hpp

// What a frame did and what it skipped. Triangle counts are per input
// triangle: each ends in exactly one of culled_frustum, culled_backface,
// culled_degenerate, invalid or rasterized.
struct FrameStats {
    uint64_t objects = 0;
    uint64_t objects_culled = 0;        // outside the view frustum, by bounds
    uint64_t draws = 0;
    uint64_t vertices_shaded = 0;
    uint64_t triangles_in = 0;
    uint64_t triangles_culled_frustum = 0;
    uint64_t triangles_culled_backface = 0;
    uint64_t triangles_culled_degenerate = 0;  // zero area or no pixel centre
    uint64_t triangles_invalid = 0;            // NaN or Inf in a vertex
    uint64_t triangles_clipped = 0;            // needed clipping (and kept a part)
    uint64_t triangles_rasterized = 0;
    uint64_t blocks_shaded = 0;                // fragment batches
    uint64_t fragments_shaded = 0;             // covered lanes sent to the shader
    uint64_t fragments_depth_rejected = 0;     // covered lanes the early depth test removed
    // Depth written with no shader call: shadow maps and pre-passes (which
    // count nothing else in the frame's statistics).
    uint64_t fragments_depth_only = 0;
    // Passes run. Each runs only when a visible material needs it.
    uint64_t shadow_passes = 0;                // shadow maps drawn
    uint64_t shadow_maps_reused = 0;           // ... kept: nothing they depend on changed
    uint64_t shadow_casters_culled = 0;        // casters outside a drawn map's light frustum
    // AO's own depth pre-pass: in an MSAA frame, or one with a part that
    // cannot take part in the frame's.
    uint64_t prepasses = 0;
    // The frame's depth pre-pass: RenderSettings::depth_prepass, or for AO,
    // which reads it, in a single-sampled frame.
    uint64_t depth_prepasses = 0;
    // Draws of the main pass on the depth pre-pass's triangles: their
    // vertex stage, setup and binning ran once for both (Pipeline::redraw).
    uint64_t draws_redrawn = 0;
    uint64_t ao_passes = 0;                    // SSAO and its blur
    uint64_t post_passes = 0;                  // screen passes of the post chain
    // What the visible materials asked for, whether or not the render
    // settings let the pass run (so an app can say why a pass was skipped).
    bool shadows_needed = false;
    bool ao_needed = false;
    double milliseconds = 0.0;                 // Renderer::render() wall time
    double ms_shadow = 0.0;                    // ... spent in shadow passes
    double ms_prepass = 0.0;                   // ... in both kinds of pre-pass
    double ms_ao = 0.0;
    double ms_main = 0.0;
    double ms_post = 0.0;                      // MSAA resolve, post chain, output
    // Each screen pass's time, for the first kPostTimings in chain order.
    static constexpr int kPostTimings = 8;
    double ms_post_pass[kPostTimings] = {};

    FrameStats& operator+=(const FrameStats& o);
};

// Fixed-function state of one draw.
struct PipelineState {
    CullMode cull = CullMode::back;
    bool front_ccw = true;
    BlendMode blend = BlendMode::opaque;
    BlendFunc blend_func;  // blend == custom
    DepthCompare depth_compare = DepthCompare::greater_equal;
    bool depth_write = true;
    bool color_write = true;  // false: depth only (shadow maps, pre-passes)
    // Draws the wire of a triangle mesh instead of its surface: the edges of
    // its triangles that `cull` keeps (each edge once), as lines
    // `line_width` pixels wide in wire_color, with no fragment shader (the
    // vertex shader still places them) and no alpha to coverage. Renderer
    // draws it over a frame's triangle parts that write colour when
    // RenderSettings::wireframe is on: 1 pixel wide and opaque, whatever
    // the part's blending, line width or alpha to coverage.
    bool wireframe = false;
    int subpixel_bits = 8;    // vertex snapping precision, 1..8 (D3D10+: 8)
    // Vulkan's depth bias, for triangles (not lines, points or the wire):
    // each one's window depth moves by depth_bias_constant * r +
    // depth_bias_slope * m, where m is the larger of its depth's slopes per
    // pixel in x and y, and r the spacing of floats at its largest depth
    // (2^(e - 23) for exponent e), before the depth test; its corners'
    // depths are then held inside 0..1 (add_depth_bias). The sign says
    // which way: toward the far depth pushes the surface back.
    float depth_bias_constant = 0.0f;
    float depth_bias_slope = 0.0f;
    // The shader's alpha (0..1) covers that share of a pixel's samples:
    // floor(alpha * n + d) of its n, d a 4x4 ordered dither of the pixel in
    // 0..1, taken in turn from sample (x + 2 y) mod n. With one sample, a
    // dithered alpha test. The colour written keeps its alpha.
    bool alpha_to_coverage = false;
    // The stencil test and operations, on a target with a stencil buffer
    // (none: as GL without one, every fragment passes and nothing is
    // written). A draw that uses it is shaded block by block, in order.
    StencilState stencil;
    // Lines and points: never culled, always front-facing; flat varyings
    // from the first end point.
    Topology topology = Topology::triangles;
    float line_width = 1.0f;  // pixels, lines
    float point_size = 1.0f;  // pixels, points
    glm::vec3 wire_color{1.0f, 0.45f, 0.05f};  // linear; orange shows on light and dark
};

// One mesh (or one part of it), one shader, one set of matrices.
struct DrawCall {
    const Mesh* mesh = nullptr;
    // The part drawn (its triangles, and only its vertices are shaded), or
    // null: the whole mesh. One that lies outside the mesh throws
    // Error(config_invalid); its indices must keep to its vertices
    // (validate_mesh checks both).
    const MeshPart* part = nullptr;
    const ShaderPlugin* shader = nullptr;
    const void* params = nullptr;                // the shader's parameter block
    const TextureBinding* textures = nullptr;    // by texture slot
    int texture_count = 0;
    glm::mat4 model{1.0f};
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    glm::vec3 camera_position{0.0f};
    const facet_light* lights = nullptr;
    uint32_t light_count = 0;
    // For FACET_NEED_SHADOW_MAP: each light's shadow, [light_count], or null.
    const facet_shadow* shadows = nullptr;
    // Ambient visibility, for FACET_NEED_AO: target-sized, or the renderer's
    // AO pass at half size (its grid, which the fragment stage upsamples a
    // tile at a time, by the depth the AO pass read). At most one is set.
    const float* ao = nullptr;
    const AoFrame* ao_grid = nullptr;
    float time = 0.0f;
    // The scene's environment as shaders light by it ("facet.environment"),
    // or null; it must outlive the draw.
    const facet_environment* environment = nullptr;
    // A band of a taller image: the target holds rows [first_row, first_row
    // + its height) of an image image_height rows tall (and as wide as the
    // target). Positions snap on the whole image's grid before moving up by
    // first_row whole pixels, so the band is bit for bit those rows of the
    // whole image. 0: the target is the whole image.
    int image_height = 0;
    int first_row = 0;
    // false: the material never discards though its shader can
    // (Material::discards), so its fragments may be packed and its depth
    // drawn with no shader call.
    bool may_discard = true;
    PipelineState state;
};

// The thread count a renderer takes when given 0: FACET_NUM_THREADS when
// set (1..256, counting the caller; as llvmpipe's LP_NUM_THREADS), else
// one per hardware thread. A value that is not such a number throws
// Error(config_invalid), as a bad FACET_ISA does.
int default_threads();

class Pipeline {
public:
    // Draws with `threads` threads (counting the caller); 0:
    // default_threads(). Its kernels are those of `isa` (isa.hpp), by default
    // default_isa(): FACET_ISA or the best the CPU has; a path the CPU lacks
    // throws Error(isa_unavailable). The image depends on neither.
    explicit Pipeline(int threads = 0, std::optional<Isa> isa = std::nullopt);
    ~Pipeline();
    Pipeline(Pipeline&&) noexcept;
    Pipeline& operator=(Pipeline&&) noexcept;

    // Draws one mesh into `target` (which must be cleared by the caller).
    void draw(const DrawCall& call, Framebuffer& target, FrameStats& stats);

    // The same, but rasterization may wait for flush(): queued draws into
    // one target are binned together, so each tile is rasterized once for
    // all of them, in submission order (the image is the same as with
    // draw()). Everything `call` points at (mesh, shader, parameters,
    // textures, lights, shadow maps, AO) must live, and the target keep its
    // size, until flush(), which adds the triangle and fragment counts to
    // its `stats`. When the queue is full, or `call` is for another target,
    // queue() rasterizes what waits first, counting it in its own `stats`.
    // clear() and resolve() of a target with queued draws throw
    // Error(out_of_range), as does Renderer::render().
    void queue(const DrawCall& call, Framebuffer& target, FrameStats& stats);
    // Rasterizes what waits. With keep_geometry, what the queued draws' vertex
    // stage and setup made, binned, is kept for redraw() (only when
    // every triangle of theirs waited: a queue that filled up and was
    // rasterized part way keeps nothing), until the next queue() or flush().
    void flush(FrameStats& stats, bool keep_geometry = false);
    // Draws `calls` on the triangles flush(stats, true) kept: calls[i] on
    // those of the i-th draw kept, which it must make alike (the same mesh,
    // part, shader, parameters, textures, matrices, camera, lights, shadow
    // maps, time, culling, sub-pixel bits and band, with the data they point
    // at unchanged: Geometry in draw_queue.hpp), into the same target, of the
    // same size and samples. Only its depth test and writes, colour writes,
    // blending and AO may differ: a pre-pass's triangles, shaded. The image
    // and counts are those of queue() and flush() of the calls (the
    // vertices, shaded once, counted here); FrameStats::draws_redrawn counts
    // them. Returns false, drawing nothing, where nothing was kept (draws
    // queued since still wait) or the calls do not match what was (which is
    // then dropped): then queue them.
    bool redraw(const std::vector<DrawCall>& calls, Framebuffer& target, FrameStats& stats);
    // Throws Error(out_of_range), naming `what`, while draws queued for
    // `target` wait.
    void require_flushed(const Framebuffer& target, const char* what) const;

    // Framebuffer::clear(), waiting for the draws that follow: each 64x64
    // tile of `target` is cleared as the first triangles drawn into it are,
    // in the cache, and the tiles none touched when flush() (or redraw(),
    // cancel(), resolve(), resolve_srgb8()) completes the clear, so no pass
    // reads the whole target only to overwrite it; of those, a tile known
    // to hold these values still (nothing has touched it since a clear to
    // them: see Framebuffer::color_data()) is not written again. Until then
    // `target` must live, keep its size, and be read through none of its
    // own methods.
    void clear(Framebuffer& target, const glm::vec4& color, float depth, uint8_t stencil = 0);
    // Drops the queued draws (and what flush(stats, true) kept) undrawn,
    // and completes any clear that waits: for a frame abandoned part way,
    // say by an exception, so that the next one starts afresh.
    void cancel();
    // Framebuffer::resolve() on all the pipeline's threads.
    void resolve(Framebuffer& target);
    // The sky pass (core/src/pipeline/sky.hpp) into `sky.target`, whose
    // draws must be flushed, on all the pipeline's threads.
    void sky(const SkyRows& sky);
    // Framebuffer::resolve_srgb8() on all the pipeline's threads: the 8-bit
    // sRGB image of a float target, for a PNG or a window, at the cost of a
    // clear (from an srgb8 target it is a copy).
    void resolve_srgb8(const Framebuffer& target, std::vector<uint8_t>& out);

    // Stops work while *stop is true (a signal or another thread sets it;
    // null, the default: never): queue() and flush() drop what waits, and
    // tiles not yet begun stay undrawn, so drawing ends within about a
    // tile's work. The target then holds an unfinished image: say so
    // (Renderer::render throws Error(interrupted)). Clear the flag to draw
    // again. `stop` must outlive the pipeline or be replaced.
    void stop_when(const std::atomic<bool>* stop) { stop_ = stop; }
    bool stopped() const { return stop_ && stop_->load(std::memory_order_relaxed); }

    int threads() const;
    Isa isa() const;
    // For the core's own passes (shadow maps, AO), which run on the same
    // threads and instruction-set path.
    ThreadPool& pool() { return *pool_; }
    const Kernels& kernels() const { return *kernels_; }

private:
    std::unique_ptr<ThreadPool> pool_;
    const Kernels* kernels_;
    std::unique_ptr<DrawQueue> queue_;
    const std::atomic<bool>* stop_ = nullptr;
};

}  // namespace facet
