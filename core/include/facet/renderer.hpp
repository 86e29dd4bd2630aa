// The renderer: plans and draws a frame of a Scene.
//
// Takes: a Scene (camera, lights, objects with materials, settings) and a
// target Framebuffer.
// Gives: the frame drawn, and FrameStats of what it did and skipped.
// render() decides which objects are visible, which passes the visible
// materials need (shadow maps, the depth pre-pass, AO)
// and in which order the objects go: opaque ones first, then blended ones
// back to front. It draws through its Pipeline (facet/pipeline.hpp), which
// embedders and tests may also use directly, and keeps the passes' buffers
// between frames.
#pragma once

#include "facet/pipeline.hpp"
#include "facet/scene.hpp"

#include <facet/shader_abi.h>

#include <memory>
#include <optional>
#include <vector>

namespace facet {

// One part of a visible object, with the material it is drawn with: what
// a frame's passes draw.
struct DrawItem {
    const Object* object = nullptr;
    const MeshPart* part = nullptr;   // null: the whole mesh (it has no parts)
    const Material* material = nullptr;
    const Bounds* bounds = nullptr;   // the part's, object space
    glm::mat4 model{1.0f};            // where it is drawn (Object::part_matrix)
    size_t order = 0;                 // position in the frame's list of items
};

// Appends the parts of `o` that can be drawn (visible, with a bound
// material) to `items`.
void add_draw_items(const Object& o, std::vector<DrawItem>& items);

// Points `call` at item `d`: its mesh, part and model matrix, and its
// material's shader, parameters and textures, and whether it may discard.
void set_item(DrawCall& call, const DrawItem& d);

class Renderer {
public:
    // A renderer on its own Pipeline(threads, isa).
    explicit Renderer(int threads = 0, std::optional<Isa> isa = std::nullopt);
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;

    // Resizes `target` to the scene's size, colour format and MSAA sample
    // count if needed, clears it, draws every visible object and resolves
    // the samples. Shadow maps are rendered first only if a visible material
    // needs them (and settings.shadows allows), and only those whose light,
    // casters or fitted bounds changed since the frame that drew them; the
    // AO pass only if a visible material needs AO (and settings.ao allows),
    // reading the frame's depth pre-pass (drawn for it if need be) in a
    // single-sampled frame whose opaque parts can all take part, else
    // drawing a pre-pass of its own. With a post chain (Scene::post, and
    // settings.post), the frame is drawn into a float target of the
    // renderer's own, and the chain's result goes to `target`, which then
    // has one sample. The statistics count the passes that ran and those
    // skipped. When the pipeline's stop flag is raised
    // (Pipeline::stop_when), the frame ends early and render() throws
    // Error(interrupted); the next render() starts afresh.
    FrameStats render(const Scene& scene, Framebuffer& target);

    // Renders rows [first_row, first_row + rows) of the scene's image into
    // `target` (resized to the scene's width and `rows`), bit for bit as
    // render() draws those rows of the whole image: what lets a very large
    // image be made band by band, in bounded memory, on many machines.
    // first_row must be a multiple of FACET_BLOCK_SIZE (4), as every band
    // of whole PNG segments (kPngSegmentRows, png.hpp) is.
    // Screen-space passes read beyond a band's rows, so a frame that would
    // run AO or a post chain throws Error(config_invalid) saying so; so do
    // rows outside the image.
    FrameStats render_rows(const Scene& scene, int first_row, int rows, Framebuffer& target);

    // Forgets the shadow maps kept from earlier frames, so that the next
    // render() draws every map it needs: what a frame costs while the
    // camera or the casters move (benchmarks).
    void forget_shadow_maps();

    Pipeline& pipeline() { return pipeline_; }
    int threads() const { return pipeline_.threads(); }
    Isa isa() const { return pipeline_.isa(); }

private:
    // What part of the frame a queued draw is.
    enum class Role { prepass, main };
    // Queues opaque or blended item `d` into `target` as that role: with
    // `prepassed` (the depth pre-pass is drawn or being drawn), an item that
    // takes part in it is drawn depth only in the pre-pass and then shaded
    // where its depth is the nearest; an item that does not is drawn in the
    // main pass only.
    void queue_item(const Scene& scene, DrawCall& call, const DrawItem& d, Role role,
                    bool prepassed, Framebuffer& target, FrameStats& counts);
    // The call queue_item() queues, in `call`; false where it queues none.
    static bool item_call(const Scene& scene, DrawCall& call, const DrawItem& d, Role role,
                          bool prepassed);
    void draw_depth_prepass(const Scene& scene, DrawCall& call, Framebuffer& target,
                            FrameStats& stats);
    // render_rows, which cancels what it queued when this throws.
    FrameStats draw_frame(const Scene& scene, int first_row, int rows, Framebuffer& target);
    // The frame plan: what is visible (Scratch), and which passes its
    // materials need.
    struct FramePlan {
        bool shadows = false;            // shadow maps
        bool ao = false;                 // the AO pass
        bool ao_shares_prepass = false;  // which reads the frame's depth pre-pass
        bool prepassed = false;          // a depth pre-pass before the main pass
        bool stencil = false;            // a material drawn uses the stencil buffer
    };
    FramePlan plan_frame(const Scene& scene, const DrawCall& call, FrameStats& stats);
    // The plan's passes into `frame`, in order: shadow maps, the frame's
    // clear and depth pre-pass, AO, the main pass.
    void draw_passes(const Scene& scene, const FramePlan& plan, DrawCall& call,
                     Framebuffer& frame, FrameStats& stats);
    void draw_main_pass(const Scene& scene, DrawCall& call, Framebuffer& target,
                        bool prepassed, bool stencil, FrameStats& stats);
    void queue_around_sky(const Scene& scene, DrawCall& call, Framebuffer& target,
                          FrameStats& stats);
    // The environment behind the opaque draws (core/src/pipeline/sky.hpp).
    void draw_sky(const Scene& scene, const DrawCall& call, Framebuffer& target);
    void draw_wire(const Scene& scene, DrawCall& call, Framebuffer& target, FrameStats& stats);

    struct BlendedItem {
        DrawItem item;
        float depth;   // view-space z of its bounds' centre
    };
    struct Scratch {
        std::vector<facet_light> lights;
        facet_environment environment{};     // the scene's, as draws and the sky read it
        std::vector<DrawItem> items;         // every drawable part
        std::vector<BlendedItem> blended;
        std::vector<DrawItem> casters;       // every drawable part, for shadow maps
        std::vector<DrawItem> opaque;        // visible opaque parts, for the pre-passes
        std::vector<DrawCall> opaque_calls;  // the main pass's, drawn again on the pre-pass's triangles or queued
        std::vector<DrawCall> after_sky;     // opaque ones that write no depth, drawn over the sky
    };
    struct Passes;  // shadow maps and AO buffers, kept between frames

    Scratch scratch_;
    std::unique_ptr<Passes> passes_;
    Pipeline pipeline_;
};

// The light as the plugin ABI carries it.
facet_light to_abi(const Light& light);

}  // namespace facet
