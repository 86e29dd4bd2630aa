// Scene-level rendering: the frame plan (which objects, in which order, with
// which state, after which passes), then every object queued and rasterized
// together through the Pipeline (pipeline.cpp).
#include "facet/renderer.hpp"

#include "frame/ao.hpp"
#include "frame/post.hpp"
#include "pipeline/clip.hpp"
#include "pipeline/sky.hpp"
#include "plugin/plugin_calls.hpp"
#include "frame/shadow.hpp"
#include "base/timing.hpp"

#include "facet/error.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace facet {

namespace {

float view_depth(const DrawItem& d, const glm::mat4& view) {
    const glm::vec3 centre = 0.5f * (d.bounds->min + d.bounds->max);
    return (view * d.model * glm::vec4(centre, 1.0f)).z;
}

PipelineState pipeline_state(const Material& m, const RenderSettings& s) {
    PipelineState p;
    p.cull = m.cull.value_or(s.cull);
    p.front_ccw = s.front_ccw;
    p.blend = m.blend;
    p.blend_func = m.blend_func;
    p.depth_compare = s.depth_compare;
    p.depth_write = m.writes_depth();
    if (s.wireframe && m.draw == Topology::triangles) {
        // Pushed back by its slope (as glPolygonOffset(1, 4)), under its
        // wire, which draw_wire draws at the depth of its edges: a sample
        // the 1-pixel line covers lies within half a pixel of the edge,
        // where the surface is at most 0.71 (half of root 2) slopes nearer.
        const float away = s.far_depth() > 0.5f ? 1.0f : -1.0f;
        p.depth_bias_slope = away;
        p.depth_bias_constant = 4.0f * away;
    }
    p.subpixel_bits = s.subpixel_bits;
    p.alpha_to_coverage = m.alpha_to_coverage;
    p.color_write = m.color_write;
    p.stencil = m.stencil;
    p.topology = m.draw;
    p.line_width = m.line_width;
    p.point_size = m.point_size;
    return p;
}

// With a depth pre-pass, an object takes part when it writes depth with a
// non-strict compare: then the last fragment drawn at the nearest depth wins
// with the pre-pass (compare equal) as without it, and the image is the same.
// Not with alpha to coverage, whose samples depend on the shader's alpha,
// which a depth-only pass does not compute.
bool in_depth_prepass(const PipelineState& p) {
    return p.depth_write && !p.alpha_to_coverage && !p.stencil.enabled &&
           (p.depth_compare == DepthCompare::less_equal ||
            p.depth_compare == DepthCompare::greater_equal);
}

// Whether a visible object's material uses the stencil buffer: the frame's
// target then has one.
bool uses_stencil(const Scene& scene) {
    for (const Object& o : scene.objects) {
        if (!o.visible || !o.mesh) continue;
        for (size_t i = 0; i < o.drawn_mesh()->part_count(); ++i)
            if (const Material* m = o.material_of(i); m && m->stencil.enabled) return true;
    }
    return false;
}

// Whether a part is seen by the shadow maps and AO: not one that writes
// neither colour nor depth (a stencil mask), which hides nothing.
bool occludes(const Material& m) { return m.color_write || m.writes_depth(); }

}  // namespace

void add_draw_items(const Object& o, std::vector<DrawItem>& items) {
    if (!o.visible || !o.mesh) return;
    const Mesh& mesh = *o.drawn_mesh();
    for (size_t i = 0; i < mesh.part_count(); ++i) {
        const Material* m = o.material_of(i);
        if (!m || !m->plugin) continue;
        const MeshPart* part = mesh.parts.empty() ? nullptr : &mesh.parts[i];
        items.push_back({&o, part, m, part ? &part->bounds : &mesh.bounds, o.part_matrix(i),
                         items.size()});
    }
}

void set_item(DrawCall& call, const DrawItem& d) {
    const Material& m = *d.material;
    call.mesh = d.object->drawn_mesh().get();
    call.part = d.part;
    call.model = d.model;
    call.shader = m.plugin.get();
    call.params = m.block ? m.block->bytes : nullptr;
    call.textures = m.textures.data();
    call.texture_count = int(m.textures.size());
    call.may_discard = m.discards;
}

struct Renderer::Passes {
    ShadowMaps shadow;
    AoPass ao;
    Framebuffer hdr;  // the frame, when a post chain runs on it
    PostChain post;
};

Renderer::Renderer(int threads, std::optional<Isa> isa)
    : passes_(std::make_unique<Passes>()), pipeline_(threads, isa) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

void Renderer::forget_shadow_maps() { passes_->shadow.key.clear(); }

facet_light to_abi(const Light& l) {
    facet_light out{};
    out.type = uint32_t(l.type);
    out.casts_shadow = l.casts_shadow ? 1u : 0u;
    for (int i = 0; i < 3; ++i) {
        out.position[i] = l.position[i];
        out.direction[i] = l.direction[i];
        out.color[i] = l.color[i];
        out.attenuation[i] = l.attenuation[i];
    }
    out.range = l.range;
    out.intensity = l.intensity;
    out.spot_cos_inner = std::cos(glm::radians(l.spot_inner));
    out.spot_cos_outer = std::cos(glm::radians(l.spot_outer));
    return out;
}


FrameStats Renderer::render(const Scene& scene, Framebuffer& target) {
    return render_rows(scene, 0, scene.settings.height, target);
}

FrameStats Renderer::render_rows(const Scene& scene, int first_row, int rows,
                                 Framebuffer& target) {
    pipeline_.require_flushed(target, "Renderer::render");  // it may resize the target
    try {
        return draw_frame(scene, first_row, rows, target);
    } catch (...) {
        take_abandoned_call();  // the next frame calls plugins again
        pipeline_.cancel();     // nothing of the frame waits for the next one
        forget_shadow_maps();  // a map cut short must not be kept as if complete
        throw;
    }
}

namespace {

// Rows [first_row, first_row + rows) of the scene's image: inside it, and
// starting on the image's grid of blocks, so that each block's weights,
// and the quads that give derivatives, are the whole image's.
void check_rows(const Scene& scene, int first_row, int rows) {
    const RenderSettings& s = scene.settings;
    if (rows < 1 || first_row < 0 || first_row > s.height - rows)
        throw Error(ErrorCode::out_of_range,
                    "rows " + std::to_string(first_row) + ".." +
                        std::to_string(int64_t(first_row) + rows - 1) + " of a " +
                        std::to_string(s.width) + "x" + std::to_string(s.height) + " image",
                    scene.source.string());
    if (first_row % FACET_BLOCK_SIZE != 0)
        throw Error(ErrorCode::out_of_range,
                    "a band starts at row " + std::to_string(first_row) + ", not on a multiple of " +
                        std::to_string(FACET_BLOCK_SIZE) + " (the rasterizer's blocks)",
                    scene.source.string());
}

}  // namespace

FrameStats Renderer::draw_frame(const Scene& scene, int first_row, int rows,
                                Framebuffer& target) {
    const auto start = std::chrono::steady_clock::now();
    const RenderSettings& s = scene.settings;
    check_rows(scene, first_row, rows);
    const bool band = first_row != 0 || rows != s.height;
    const auto fit = [&](Framebuffer& fb, ColorFormat format, int samples, bool stencil) {
        if (fb.width() != s.width || fb.height() != rows || fb.samples() != samples ||
            fb.format() != format || fb.has_stencil() != stencil)
            fb.resize(s.width, rows, format, samples, stencil);
    };
    // With a post chain, the frame is drawn in float and the chain's result
    // goes to the target.
    const bool post = s.post && !scene.post.empty();
    if (band && post)
        throw Error(ErrorCode::config_invalid,
                    "a band of rows cannot run the post chain, whose passes read pixels beyond "
                    "it; render the whole image, or set render: {post: false}",
                    scene.source.string());
    Framebuffer& frame = post ? passes_->hdr : target;
    fit(frame, post ? ColorFormat::rgba32f : s.color_format, s.msaa, uses_stencil(scene));
    if (post) fit(target, s.color_format, 1, false);

    DrawCall call;
    call.view = scene.camera.view();
    call.projection = scene.camera.projection(float(s.width) / float(s.height), s.reversed_z);
    call.camera_position = scene.camera.position;
    call.time = float(scene.time);
    if (band) {
        call.image_height = s.height;
        call.first_row = first_row;
    }
    scratch_.lights.clear();
    for (const Light& l : scene.lights) scratch_.lights.push_back(to_abi(l));
    call.lights = scratch_.lights.data();
    call.light_count = uint32_t(scratch_.lights.size());
    scratch_.environment = scene.environment.record();
    if (scene.environment && scene.environment.settings.lights())
        call.environment = &scratch_.environment;

    FrameStats stats;
    const FramePlan plan = plan_frame(scene, call, stats);
    if (plan.ao && band)
        throw Error(ErrorCode::config_invalid,
                    "a band of rows cannot run ambient occlusion, which reads depth beyond it; "
                    "render the whole image, or set render: {ao: false}",
                    scene.source.string());
    draw_passes(scene, plan, call, frame, stats);
    const auto post_start = std::chrono::steady_clock::now();
    if (!pipeline_.stopped()) pipeline_.resolve(frame);
    if (post && !pipeline_.stopped())
        passes_->post.run(scene.post, frame, target, s, float(scene.time), pipeline_, stats);
    stats.ms_post += elapsed_ms(post_start);
    if (std::string stalled = take_abandoned_call(); !stalled.empty()) {
        forget_shadow_maps();  // drawn by calls that may have been given up
        throw Error(ErrorCode::plugin_stalled, std::move(stalled), scene.source.string());
    }
    if (pipeline_.stopped()) {
        forget_shadow_maps();  // maps cut short must not be kept as if complete
        throw Error(ErrorCode::interrupted, "the frame was stopped before it was complete");
    }
    stats.milliseconds = elapsed_ms(start);
    return stats;
}

Renderer::FramePlan Renderer::plan_frame(const Scene& scene, const DrawCall& call,
                                         FrameStats& stats) {
    const RenderSettings& s = scene.settings;
    FramePlan plan;
    scratch_.items.clear();
    scratch_.blended.clear();
    scratch_.casters.clear();
    scratch_.opaque.clear();
    for (const Object& o : scene.objects) {
        const size_t first = scratch_.items.size();
        add_draw_items(o, scratch_.items);
        if (scratch_.items.size() == first) continue;
        ++stats.objects;
        // The whole mesh's bounds hold its parts only where none moves.
        if (o.part_poses.empty() &&
            outside_frustum(o.drawn_mesh()->bounds, call.projection * call.view * o.transform.matrix())) {
            ++stats.objects_culled;
            for (size_t i = first; i < scratch_.items.size(); ++i)
                if (occludes(*scratch_.items[i].material)) scratch_.casters.push_back(scratch_.items[i]);
            continue;
        }
        for (size_t i = first; i < scratch_.items.size(); ++i) {
            const DrawItem& d = scratch_.items[i];
            if (occludes(*d.material)) scratch_.casters.push_back(d);
            if (d.part && outside_frustum(*d.bounds, call.projection * call.view * d.model))
                continue;
            const Material& m = *d.material;
            stats.shadows_needed |= m.uses_shadows;
            stats.ao_needed |= m.uses_ao;
            plan.shadows |= s.shadows && m.uses_shadows;
            plan.ao |= s.ao && m.uses_ao;
            if (m.blend == BlendMode::opaque) scratch_.opaque.push_back(d);
            else scratch_.blended.push_back({d, 0.0f});
            plan.stencil |= m.stencil.enabled;
        }
    }
    // AO needs the depth of every opaque surface before the main pass. When
    // the frame is single-sampled and every opaque part can take part in the
    // main pass's depth pre-pass, that pre-pass is drawn first and serves
    // both: AO reads the frame's depth, and the main pass then shades each
    // pixel once (the same image, as with depth_prepass). Otherwise AO draws
    // its own.
    plan.ao_shares_prepass =
        plan.ao && s.msaa == 1 &&
        std::all_of(scratch_.opaque.begin(), scratch_.opaque.end(), [&](const DrawItem& d) {
            return in_depth_prepass(pipeline_state(*d.material, s));
        });
    // The stencil's operations see the depth the draws before them left,
    // in scene order: no pre-pass may write depth ahead of them.
    if (plan.stencil) {
        if (s.depth_prepass)
            spdlog::debug("depth pre-pass off: the scene's materials use the stencil buffer");
        plan.ao_shares_prepass = false;
    }
    plan.prepassed = !plan.stencil && (s.depth_prepass || plan.ao_shares_prepass);
    return plan;
}

void Renderer::draw_passes(const Scene& scene, const FramePlan& plan, DrawCall& call,
                           Framebuffer& frame, FrameStats& stats) {
    const RenderSettings& s = scene.settings;
    if (plan.shadows) {
        const auto t = std::chrono::steady_clock::now();
        render_shadow_maps(scene, scratch_.casters, pipeline_, passes_->shadow, stats);
        call.shadows = passes_->shadow.by_light.data();
        stats.ms_shadow += elapsed_ms(t);
    }
    // The frame's clear waits for its first pass's draws (Pipeline::clear),
    // and a pass into another target (shadow maps, AO's own pre-pass) would
    // complete it first: so it comes after those.
    const auto clear_frame = [&] {
        pipeline_.clear(frame, s.clear_color, s.far_depth(), s.clear_stencil);
    };
    if (plan.prepassed) {
        clear_frame();
        draw_depth_prepass(scene, call, frame, stats);
    }
    if (plan.ao) {
        passes_->ao.run(scratch_.opaque, call.view, call.projection, s, call.time,
                        plan.ao_shares_prepass ? &frame : nullptr, pipeline_, stats);
        call.ao = passes_->ao.visibility();
        call.ao_grid = passes_->ao.grid();
    }
    if (!plan.prepassed) clear_frame();
    draw_main_pass(scene, call, frame, plan.prepassed, plan.stencil, stats);
}

void Renderer::queue_item(const Scene& scene, DrawCall& call, const DrawItem& d, Role role,
                          bool prepassed, Framebuffer& target, FrameStats& counts) {
    if (item_call(scene, call, d, role, prepassed)) pipeline_.queue(call, target, counts);
}

bool Renderer::item_call(const Scene& scene, DrawCall& call, const DrawItem& d, Role role,
                         bool prepassed) {
    const Material& m = *d.material;
    set_item(call, d);
    call.state = pipeline_state(m, scene.settings);
    // Only opaque parts are in the pre-pass (a blended one that writes depth
    // is drawn, far to near, in the main pass alone).
    if (prepassed && m.blend == BlendMode::opaque && in_depth_prepass(call.state)) {
        if (role == Role::prepass) {
            call.state.color_write = false;  // depth only: no shader runs
        } else {
            call.state.depth_compare = DepthCompare::equal;  // the nearest, once
            call.state.depth_write = false;
        }
    } else if (role == Role::prepass) {
        return false;
    }
    return true;
}

void Renderer::draw_depth_prepass(const Scene& scene, DrawCall& call, Framebuffer& target,
                                  FrameStats& stats) {
    const auto start = std::chrono::steady_clock::now();
    FrameStats prepass;  // the main pass's statistics count the main pass only
    for (const DrawItem& d : scratch_.opaque)
        queue_item(scene, call, d, Role::prepass, true, target, prepass);
    pipeline_.flush(prepass, true);  // its triangles, for the main pass (draw_main_pass)
    stats.fragments_depth_only += prepass.fragments_depth_only;
    stats.depth_prepasses += 1;
    stats.ms_prepass += elapsed_ms(start);
}

// Opaque objects in scene order, then blended ones farthest first (view z
// is negative in front of the camera, so the most negative is farthest);
// ties keep scene order. Queued, and rasterized together at the end: the
// scene (and so each material's plugin, block and textures) outlives the
// pass.
void Renderer::draw_main_pass(const Scene& scene, DrawCall& call, Framebuffer& target,
                              bool prepassed, bool stencil, FrameStats& stats) {
    const auto start = std::chrono::steady_clock::now();
    // After the pre-pass, the opaque parts are its triangles shaded: where
    // each is drawn in both and the pre-pass kept them (it did not fill the
    // queue), they are drawn again with the main pass's state, without a
    // second vertex stage, setup and binning. Otherwise they are queued.
    // With a sky, an opaque part that writes no depth would leave the far
    // depth the sky fills: it is drawn after the sky, over it. In a frame
    // that uses the stencil the parts keep their order (one may test what
    // another wrote), and the sky comes before the first it would hide.
    const bool sky = scene.environment && scene.environment.settings.shows();
    if (sky && stencil) {
        queue_around_sky(scene, call, target, stats);
    } else {
        scratch_.opaque_calls.clear();
        scratch_.after_sky.clear();
        for (const DrawItem& d : scratch_.opaque) {
            if (!item_call(scene, call, d, Role::main, prepassed)) continue;
            const bool writes_depth = pipeline_state(*d.material, scene.settings).depth_write;
            (sky && !writes_depth ? scratch_.after_sky : scratch_.opaque_calls).push_back(call);
        }
        if (!prepassed || !pipeline_.redraw(scratch_.opaque_calls, target, stats))
            for (const DrawCall& c : scratch_.opaque_calls) pipeline_.queue(c, target, stats);
        if (sky) {
            pipeline_.flush(stats);  // the opaque draws: the sky goes where they left the far depth
            draw_sky(scene, call, target);
            for (const DrawCall& c : scratch_.after_sky) pipeline_.queue(c, target, stats);
        }
    }
    for (BlendedItem& b : scratch_.blended) b.depth = view_depth(b.item, call.view);
    std::sort(scratch_.blended.begin(), scratch_.blended.end(),
              [](const BlendedItem& a, const BlendedItem& b) {
                  return a.depth < b.depth || (a.depth == b.depth && a.item.order < b.item.order);
              });
    for (const BlendedItem& b : scratch_.blended)
        queue_item(scene, call, b.item, Role::main, prepassed, target, stats);
    pipeline_.flush(stats);
    if (scene.settings.wireframe) draw_wire(scene, call, target, stats);
    stats.ms_main += elapsed_ms(start);
}

// The wire of every triangle part drawn (RenderSettings::wireframe), over
// the frame: the edges of its triangles that face the eye (as its culling
// keeps them), as lines a pixel wide in the wire colour, tested against
// the depth (and stencil) the frame left and writing neither. Its surfaces
// were pushed back (pipeline_state), so that a wire shows over its own.
void Renderer::draw_wire(const Scene& scene, DrawCall& call, Framebuffer& target,
                         FrameStats& stats) {
    const auto wire = [&](const DrawItem& d) {
        const Material& m = *d.material;
        if (m.draw != Topology::triangles || !m.color_write) return;
        set_item(call, d);
        call.may_discard = false;
        PipelineState& p = call.state = pipeline_state(m, scene.settings);
        p.wireframe = true;
        p.depth_write = false;
        p.blend = BlendMode::opaque;
        p.alpha_to_coverage = false;
        p.depth_bias_constant = p.depth_bias_slope = 0.0f;
        p.line_width = 1.0f;
        p.stencil.front.write_mask = p.stencil.back.write_mask = 0;
        pipeline_.queue(call, target, stats);
    };
    for (const DrawItem& d : scratch_.opaque) wire(d);
    for (const BlendedItem& b : scratch_.blended) wire(b.item);
    pipeline_.flush(stats);
}

// The opaque parts in scene order, the sky drawn before the first that
// writes colour and no depth (or after them all): where the sky fills a
// pixel, the parts before it left the far depth, and a part after it that
// writes depth covers the sky as it would have covered the clear colour.
void Renderer::queue_around_sky(const Scene& scene, DrawCall& call, Framebuffer& target,
                                FrameStats& stats) {
    bool sky_drawn = false;
    const auto sky_now = [&] {
        pipeline_.flush(stats);
        draw_sky(scene, call, target);
        sky_drawn = true;
    };
    for (const DrawItem& d : scratch_.opaque) {
        if (!item_call(scene, call, d, Role::main, false)) continue;
        if (!sky_drawn && !call.state.depth_write && call.state.color_write) sky_now();
        pipeline_.queue(call, target, stats);
    }
    if (!sky_drawn) sky_now();
}

void Renderer::draw_sky(const Scene& scene, const DrawCall& call, Framebuffer& target) {
    const RenderSettings& s = scene.settings;
    SkyRows sky;
    sky.target = &target;
    sky.environment = &scratch_.environment;
    sky.blur = scene.environment.settings.blur;
    sky.first_row = call.first_row;
    sky.far_depth = s.far_depth();
    sky_directions(sky, call.view, call.projection, call.camera_position,
                   scene.camera.orthographic, s.width, s.height);
    pipeline_.sky(sky);
}

}  // namespace facet
