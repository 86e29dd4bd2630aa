// Geometry for one draw: vertex stage, primitive assembly, clipping, setup,
// then rasterization and the fragment stage (fragment.cpp).
#include "clip.hpp"
#include "fragment.hpp"
#include "rasterize.hpp"
#include "setup.hpp"

#include "facet/error.hpp"
#include "facet/math.hpp"
#include "facet/renderer.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>

namespace facet {

namespace {

constexpr uint32_t kVertexBatch = 256;

void copy_matrix(float* dst, const glm::mat4& m) { std::memcpy(dst, glm::value_ptr(m), 64); }

facet_draw make_abi_draw(const DrawCall& call, const Framebuffer& target,
                         const DrawContext& dc) {
    facet_draw d{};
    static const ParamBlock kNoParams{};
    d.host = host_services();
    d.params = call.params ? call.params : kNoParams.bytes;  // never NULL
    d.host_data = &dc;
    copy_matrix(d.model, call.model);
    copy_matrix(d.view, call.view);
    copy_matrix(d.projection, call.projection);
    copy_matrix(d.view_projection, call.projection * call.view);
    copy_matrix(d.model_view_projection, call.projection * call.view * call.model);
    copy_matrix(d.normal_matrix, glm::mat4(normal_matrix(call.model)));
    d.camera_position[0] = call.camera_position.x;
    d.camera_position[1] = call.camera_position.y;
    d.camera_position[2] = call.camera_position.z;
    d.camera_position[3] = 1.0f;
    if (call.shader->needs(FACET_NEED_LIGHTS)) {
        d.light_count = call.light_count;
        d.lights = call.lights;
    }
    if (call.shader->needs(FACET_NEED_SHADOW_MAP)) {
        d.shadow_map_count = call.shadow_map_count;
        d.shadow_maps = call.shadow_maps;
    }
    d.viewport_width = uint32_t(target.width());
    d.viewport_height = uint32_t(target.height());
    d.time = call.time;
    return d;
}

template <class T>
const float* input(const ShaderPlugin& shader, facet_need need, const std::vector<T>& data,
                   size_t first) {
    if (!shader.needs(need) || data.empty()) return nullptr;
    return glm::value_ptr(data[first]);
}

bool finite(const glm::vec4& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

CullState cull_state(const PipelineState& s) {
    return {s.cull == CullMode::back, s.cull == CullMode::front, s.front_ccw};
}

// Sign of the area of a convex clip-space polygon on screen (y down).
int screen_orientation(const ClipVertex* poly, int n, const Viewport& viewport) {
    double area = 0.0;
    for (int i = 0; i < n; ++i) {
        const glm::dvec2 a = to_window(poly[i].position, viewport);
        const glm::dvec2 b = to_window(poly[(i + 1) % n].position, viewport);
        area += a.x * b.y - b.x * a.y;
    }
    return (area > 0.0) - (area < 0.0);
}

// Clips the triangle and draws the fan of what is left, each piece held to
// the orientation of the whole polygon. Returns the result that counts for
// the input triangle.
template <class Draw>
SetupResult draw_clipped(const SetupVertex v[3], uint32_t planes, const Viewport& viewport,
                         const DrawContext& dc, Draw&& draw_one) {
    ClipVertex in[3], out[kMaxClipVertices];
    const int floats = int(dc.varying_floats);
    for (int i = 0; i < 3; ++i) {
        in[i].position = v[i].clip;
        std::memcpy(in[i].varyings, v[i].varyings, sizeof(float) * floats);
    }
    const int n =
        clip_polygon(in, 3, planes, viewport.guard_ndc(), floats, dc.interpolation, out);
    if (n < 3) return SetupResult::clipped_away;
    // Flat varyings keep the first input vertex's value, not a blend.
    for (int k = 0; k < floats; ++k)
        if (dc.interpolation[k] == FACET_INTERP_FLAT)
            for (int i = 0; i < n; ++i) out[i].varyings[k] = v[0].varyings[k];
    const int orientation = screen_orientation(out, n, viewport);
    SetupResult result = SetupResult::clipped_away;
    for (int i = 1; i + 1 < n; ++i) {
        const SetupVertex tri[3] = {{out[0].position, out[0].varyings},
                                    {out[i].position, out[i].varyings},
                                    {out[i + 1].position, out[i + 1].varyings}};
        const SetupResult r = draw_one(tri, orientation);
        if (r == SetupResult::ok || result == SetupResult::clipped_away) result = r;
    }
    return result;
}

void count(SetupResult r, FrameStats& stats) {
    switch (r) {
        case SetupResult::ok: ++stats.triangles_rasterized; break;
        case SetupResult::culled_backface: ++stats.triangles_culled_backface; break;
        case SetupResult::clipped_away: ++stats.triangles_culled_frustum; break;
        case SetupResult::degenerate:
        case SetupResult::no_pixels: ++stats.triangles_culled_degenerate; break;
    }
}

// Vertex stage: every vertex once, kVertexBatch per plugin call, with only
// the inputs the shader asks for.
void shade_vertices(const Mesh& mesh, const ShaderPlugin& shader, const facet_draw& abi,
                    std::vector<glm::vec4>& clip, std::vector<float>& varyings) {
    const size_t vcount = mesh.vertex_count();
    const uint32_t floats = shader.varying_floats();
    clip.resize(vcount);
    varyings.resize(vcount * floats + 1);
    for (size_t first = 0; first < vcount; first += kVertexBatch) {
        const facet_vertex_batch batch{
            uint32_t(std::min<size_t>(kVertexBatch, vcount - first)),
            glm::value_ptr(mesh.positions[first]),
            input(shader, FACET_NEED_NORMALS, mesh.normals, first),
            input(shader, FACET_NEED_UVS, mesh.uvs, first),
            input(shader, FACET_NEED_COLORS, mesh.colors, first),
            nullptr,  // tangents: no shader may ask for them yet (plugin.cpp refuses it)
            glm::value_ptr(clip[first]),
            varyings.data() + first * floats,
            floats};
        shader.desc().vertex(&abi, &batch);
    }
}

}  // namespace

void Renderer::draw(const DrawCall& call, Framebuffer& target, FrameStats& stats) {
    if (!call.mesh || !call.shader)
        throw Error(ErrorCode::config_invalid, "draw call without a mesh or a shader");
    const Mesh& mesh = *call.mesh;
    const ShaderPlugin& shader = *call.shader;
    ++stats.draws;

    DrawContext dc;
    prepare_context(dc, shader, call.textures, call.texture_count);
    dc.state = call.state;
    dc.target = &target;
    dc.ao = shader.needs(FACET_NEED_AO) ? call.ao : nullptr;
    const facet_draw abi = make_abi_draw(call, target, dc);
    dc.abi = &abi;
    shade_vertices(mesh, shader, abi, scratch_.clip, scratch_.varyings);
    stats.vertices_shaded += mesh.vertex_count();

    // Primitive assembly and everything after it, one triangle at a time.
    const Viewport viewport{target.width(), target.height()};
    const CullState cull = cull_state(call.state);
    TriangleSetup setup;
    auto draw_one = [&](const SetupVertex tri[3], int orientation) {
        const SetupResult r = setup_triangle(tri, viewport, cull, setup, orientation);
        if (r == SetupResult::ok)
            rasterize(setup, [&](const Block& b) { shade_block(dc, setup, b, stats); });
        return r;
    };
    const uint32_t floats = dc.varying_floats;
    const uint32_t* idx = mesh.indices.data();
    for (size_t t = 0; t < mesh.triangle_count(); ++t, idx += 3) {
        ++stats.triangles_in;
        const glm::vec4* c[3] = {&scratch_.clip[idx[0]], &scratch_.clip[idx[1]],
                                 &scratch_.clip[idx[2]]};
        if (!finite(*c[0]) || !finite(*c[1]) || !finite(*c[2])) {
            ++stats.triangles_invalid;
            continue;
        }
        const ClipClass cc = classify(*c[0], *c[1], *c[2], viewport.guard_ndc());
        if (cc.reject) {
            ++stats.triangles_culled_frustum;
            continue;
        }
        SetupVertex v[3];
        for (int i = 0; i < 3; ++i)
            v[i] = {glm::dvec4(*c[i]), scratch_.varyings.data() + size_t(idx[i]) * floats};
        if (!cc.clip) {
            count(draw_one(v, 0), stats);
            continue;
        }
        const SetupResult r = draw_clipped(v, cc.clip, viewport, dc, draw_one);
        if (r == SetupResult::ok) ++stats.triangles_clipped;
        count(r, stats);
    }
}

}  // namespace facet
