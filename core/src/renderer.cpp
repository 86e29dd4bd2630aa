// Scene-level rendering: the frame plan (which objects, in which order, with
// which state), then one Renderer::draw() per object (draw.cpp).
#include "facet/renderer.hpp"

#include "clip.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace facet {

namespace {

// True when all eight corners of `b` lie outside one plane of the frustum.
bool outside_frustum(const Bounds& b, const glm::mat4& mvp) {
    uint32_t all = ~0u;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 corner(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y,
                               i & 4 ? b.max.z : b.min.z);
        all &= outcode(glm::dvec4(mvp * glm::vec4(corner, 1.0f)), 1.0);
    }
    return all != 0;
}

float view_depth(const Object& o, const glm::mat4& view) {
    const glm::vec3 centre = 0.5f * (o.mesh->bounds.min + o.mesh->bounds.max);
    return (view * o.transform.matrix() * glm::vec4(centre, 1.0f)).z;
}

PipelineState pipeline_state(const Material& m, const RenderSettings& s) {
    PipelineState p;
    p.cull = m.cull.value_or(s.cull);
    p.front_ccw = s.front_ccw;
    p.blend = m.blend;
    p.depth_compare = s.depth_compare;
    p.depth_write = m.writes_depth();
    return p;
}

}  // namespace

FrameStats& FrameStats::operator+=(const FrameStats& o) {
    objects += o.objects;
    objects_culled += o.objects_culled;
    draws += o.draws;
    vertices_shaded += o.vertices_shaded;
    triangles_in += o.triangles_in;
    triangles_culled_frustum += o.triangles_culled_frustum;
    triangles_culled_backface += o.triangles_culled_backface;
    triangles_culled_degenerate += o.triangles_culled_degenerate;
    triangles_invalid += o.triangles_invalid;
    triangles_clipped += o.triangles_clipped;
    triangles_rasterized += o.triangles_rasterized;
    blocks_shaded += o.blocks_shaded;
    fragments_shaded += o.fragments_shaded;
    fragments_depth_rejected += o.fragments_depth_rejected;
    milliseconds += o.milliseconds;
    return *this;
}

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
    const auto start = std::chrono::steady_clock::now();
    const RenderSettings& s = scene.settings;
    if (target.width() != s.width || target.height() != s.height) target.resize(s.width, s.height);
    target.clear(s.clear_color, s.reversed_z ? 0.0f : 1.0f);

    DrawCall call;
    call.view = scene.camera.view();
    call.projection = scene.camera.projection(float(s.width) / float(s.height), s.reversed_z);
    call.camera_position = scene.camera.position;
    scratch_.lights.clear();
    for (const Light& l : scene.lights) scratch_.lights.push_back(to_abi(l));
    call.lights = scratch_.lights.data();
    call.light_count = uint32_t(scratch_.lights.size());

    FrameStats stats;
    auto draw_object = [&](const Object& o) {
        const Material& m = *o.material;
        const std::shared_ptr<ShaderPlugin> keep = m.plugin;  // loaded for the whole draw
        call.mesh = o.mesh.get();
        call.shader = m.plugin.get();
        call.params = m.block ? m.block->bytes : nullptr;
        call.textures = m.textures.data();
        call.texture_count = int(m.textures.size());
        call.model = o.transform.matrix();
        call.state = pipeline_state(m, s);
        draw(call, target, stats);
    };

    scratch_.blended.clear();
    for (const Object& o : scene.objects) {
        if (!o.visible || !o.mesh || !o.material || !o.material->plugin) continue;
        ++stats.objects;
        if (outside_frustum(o.mesh->bounds, call.projection * call.view * o.transform.matrix())) {
            ++stats.objects_culled;
            continue;
        }
        if (o.material->blend == BlendMode::opaque) draw_object(o);
        else scratch_.blended.push_back({&o, 0.0f, scratch_.blended.size()});
    }
    // Blended objects after the opaque ones, farthest first (view z is negative
    // in front of the camera, so the most negative is farthest); ties keep
    // scene order.
    for (BlendedObject& b : scratch_.blended) b.depth = view_depth(*b.object, call.view);
    std::sort(scratch_.blended.begin(), scratch_.blended.end(),
              [](const BlendedObject& a, const BlendedObject& b) {
                  return a.depth < b.depth || (a.depth == b.depth && a.order < b.order);
              });
    for (const BlendedObject& b : scratch_.blended) draw_object(*b.object);

    stats.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

}  // namespace facet
