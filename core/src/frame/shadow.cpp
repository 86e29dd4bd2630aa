#include "frame/shadow.hpp"

#include "pipeline/clip.hpp"
#include "plugin/internal_shaders.hpp"
#include "base/thread_pool.hpp"
#include "pipeline/kernels.hpp"
#include "pipeline/shadow_rows.hpp"

#include "facet/math.hpp"
#include "facet/memory.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <utility>

namespace facet {

namespace {

// World-space corners of the casters' bounds, into `out`.
void caster_corners(const std::vector<DrawItem>& casters, std::vector<glm::vec3>& out) {
    out.clear();
    for (const DrawItem& d : casters) {
        const glm::mat4 m = d.model;
        const Bounds& b = *d.bounds;
        for (int i = 0; i < 8; ++i)
            out.push_back(glm::vec3(m * glm::vec4(i & 1 ? b.max.x : b.min.x,
                                                  i & 2 ? b.max.y : b.min.y,
                                                  i & 4 ? b.max.z : b.min.z, 1.0f)));
    }
}

// Corners of the camera's view frustum from its near plane to `distance`.
std::array<glm::vec3, 8> frustum_corners(const Camera& c, float aspect, float distance) {
    const glm::vec3 forward = glm::normalize(c.target - c.position);
    const glm::vec3 right = glm::normalize(glm::cross(forward, c.up));
    const glm::vec3 up = glm::cross(right, forward);
    std::array<glm::vec3, 8> out;
    int k = 0;
    for (float d : {c.near, std::min(c.far, distance)}) {
        const float h = c.orthographic ? 0.5f * c.ortho_height
                                       : d * std::tan(glm::radians(c.fov_y) * 0.5f);
        for (int i = 0; i < 4; ++i)
            out[size_t(k++)] = c.position + forward * d + right * (i & 1 ? h : -h) * aspect +
                               up * (i & 2 ? h : -h);
    }
    return out;
}

glm::vec3 any_perpendicular_up(const glm::vec3& dir) {
    return std::abs(dir.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
}

// Orthographic projection of the light-view box [lo, hi] (x, y square; view
// z negative ahead), standard depth: 0 at the near face.
glm::mat4 box_projection(glm::vec3 lo, glm::vec3 hi, float& near, float& far) {
    near = -hi.z;
    far = -lo.z;
    const glm::vec2 centre = 0.5f * glm::vec2(lo + hi);
    const float side = std::max(hi.x - lo.x, hi.y - lo.y);
    glm::mat4 m(1.0f);
    m[0][0] = m[1][1] = 2.0f / side;
    m[3][0] = -centre.x * m[0][0];
    m[3][1] = -centre.y * m[1][1];
    m[2][2] = -1.0f / (far - near);
    m[3][2] = -near / (far - near);
    return m;
}

void directional(const Scene& scene, const Light& light, const std::vector<glm::vec3>& casters,
                 float aspect, int size, facet_shadow_map& sm, glm::mat4& view,
                 glm::mat4& proj) {
    const glm::vec3 dir = glm::normalize(light.direction);
    view = look_at(glm::vec3(0.0f), dir, any_perpendicular_up(dir));
    const float reach = scene.settings.shadow_distance > 0.0f ? scene.settings.shadow_distance
                                                               : scene.camera.far;
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& p : frustum_corners(scene.camera, aspect, reach)) {
        const glm::vec3 q = glm::vec3(view * glm::vec4(p, 1.0f));
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    glm::vec3 olo(INFINITY), ohi(-INFINITY);  // the objects' box
    for (const glm::vec3& p : casters) {
        const glm::vec3 q = glm::vec3(view * glm::vec4(p, 1.0f));
        olo = glm::min(olo, q);
        ohi = glm::max(ohi, q);
    }
    // Across the light: only where the view and the objects overlap (nothing
    // else can receive a shadow). Along it: every caster, wherever it is.
    lo = glm::vec3(glm::max(glm::vec2(lo), glm::vec2(olo)), std::min(lo.z, olo.z) - 0.01f);
    hi = glm::vec3(glm::min(glm::vec2(hi), glm::vec2(ohi)), std::max(hi.z, ohi.z) + 0.01f);
    hi = glm::max(hi, lo + 0.02f);  // never empty
    proj = box_projection(lo, hi, sm.near_plane, sm.far_plane);
    sm.projection = FACET_SHADOW_ORTHOGRAPHIC;
    sm.texel_size = 2.0f / proj[0][0] / float(size);
}

void spot(const Light& light, const std::vector<glm::vec3>& casters, int size,
          facet_shadow_map& sm, glm::mat4& view, glm::mat4& proj) {
    const glm::vec3 dir = glm::normalize(light.direction);
    view = look_at(light.position, light.position + dir, any_perpendicular_up(dir));
    float far = 0.1f;
    for (const glm::vec3& p : casters) far = std::max(far, glm::length(p - light.position));
    const float fov = glm::radians(std::min(2.0f * light.spot_outer + 2.0f, 170.0f));
    sm.near_plane = std::min(std::max(far * 1e-4f, 0.01f), far * 0.5f);  // a range of 0.005 too
    sm.far_plane = far * 1.01f;
    proj = perspective(fov, 1.0f, sm.near_plane, sm.far_plane, false);
    sm.projection = FACET_SHADOW_PERSPECTIVE;
    sm.texel_size = 2.0f * std::tan(fov * 0.5f) / float(size);
}

// The key of a map seen through view_projection: the casters it can see.
// Returns how many it cannot.
uint64_t make_key(const std::vector<DrawItem>& casters, const glm::mat4& view_projection,
                  int size, float time, ShadowMapKey& key) {
    key.size = size;
    key.view_projection = view_projection;
    key.casters.clear();
    key.time = 0.0f;
    for (const DrawItem& d : casters) {
        const glm::mat4 model = d.model;
        if (outside_frustum(*d.bounds, view_projection * model)) continue;
        const Material& m = *d.material;
        key.casters.push_back({d.object->drawn_mesh(), d.part, model, m.discards ? &m : nullptr,
                               m.discards ? m.block : nullptr});
        if (m.discards) key.time = time;
    }
    return casters.size() - key.casters.size();
}

// The casters' depth; a cutout's own shader runs, with no lights, so that
// what it discards casts no shadow.
void draw_depth(const ShadowMapKey& key, const glm::mat4& view, const glm::mat4& proj,
                Pipeline& pipeline, Framebuffer& target, FrameStats& frame) {
    DrawCall call;
    call.view = view;
    call.projection = proj;
    call.state.cull = CullMode::none;  // open meshes (planes) cast from both sides
    call.state.depth_compare = DepthCompare::less;
    call.state.color_write = false;
    FrameStats stats;  // the main pass's statistics count the main pass only
    for (const ShadowMapKey::Caster& c : key.casters) {
        call.mesh = c.mesh.get();
        call.part = c.part;
        call.model = c.model;
        call.shader = c.cutout ? c.cutout->plugin.get() : &internal::plugin<internal::DepthOnly>();
        call.params = c.cutout ? c.params->bytes : nullptr;
        call.textures = c.cutout ? c.cutout->textures.data() : nullptr;
        call.texture_count = c.cutout ? int(c.cutout->textures.size()) : 0;
        call.time = key.time;
        pipeline.queue(call, target, stats);
    }
    pipeline.flush(stats);
    frame.fragments_depth_only += stats.fragments_depth_only;
}

// Texels from one row of a map's distances to the next: the map and its
// border, rounded up to a whole number of cache lines (the shadow scene at
// 1920x1080 filtered its two 2048-texel maps 2% faster on one thread with
// rows 2080 texels, 65 lines, apart than 2064, 64.5 lines), and one line
// more where that would be a multiple of 4096 bytes, whose rows would all
// fall in the same few cache sets (not measured: no shipped size does).
int distance_stride(int width) {
    const int stride = (width + 2 * FACET_SHADOW_BORDER + 31) & ~31;
    return stride % 2048 == 0 ? stride + 32 : stride;
}

// The map's window depths as distances (facet_shadow_distances), on all
// threads, into `texels`: a map drawn `size` texels a side, into a distance
// array FACET_SHADOW_BORDER texels wider on every side whose border reads
// 65535 (set again each time: the slot may have held a cube face, whose
// border is drawn); or, for a cube face drawn with its border
// (`with_border`), the whole drawing.
void make_distances(const facet_shadow_map& sm, const Framebuffer& depth, bool with_border,
                    Pipeline& pipeline, std::vector<uint16_t>& texels) {
    constexpr int kBorder = FACET_SHADOW_BORDER;
    const int stride = distance_stride(int(sm.width));
    const size_t size = size_t(stride) * size_t(sm.height + 2 * kBorder);
    if (texels.size() != size) texels.assign(size, uint16_t(65535));
    if (!with_border) {
        const size_t width = size_t(sm.width) + 2 * kBorder, height = size_t(sm.height);
        for (size_t y = 0; y < height + 2 * kBorder; ++y) {
            uint16_t* row = texels.data() + y * size_t(stride);
            if (y < kBorder || y >= height + kBorder) {
                std::fill(row, row + width, uint16_t(65535));
            } else {
                std::fill(row, row + kBorder, uint16_t(65535));
                std::fill(row + width - kBorder, row + width, uint16_t(65535));
            }
        }
    }
    ShadowDistanceRows rows;
    rows.depth = std::as_const(depth).depth();
    rows.depth_stride = depth.stride();
    rows.distances =
        with_border ? texels.data() : texels.data() + size_t(kBorder) * size_t(stride) + kBorder;
    rows.distance_stride = stride;
    rows.width = depth.width();
    rows.orthographic = sm.projection == FACET_SHADOW_ORTHOGRAPHIC;
    rows.near_plane = sm.near_plane;
    rows.far_plane = sm.far_plane;
    const Kernels& kernels = pipeline.kernels();
    const int height = depth.height();
    constexpr int kBand = 32;
    pipeline.pool().parallel_for((height + kBand - 1) / kBand, [&](int band, int) {
        kernels.shadow_distance_rows(rows, band * kBand, std::min(kBand, height - band * kBand));
    });
}

// The planes that bound a map's distances (`texels`, as make_distances
// leaves them) tile by tile (facet_shadow_planes), on all threads, into
// `tiles`. They are made for a map the first frame it is kept, not the frame
// it is drawn: making them costs about what they save in two frames (for
// the shadow scene's two 2048-texel maps, 11 ms on one thread, against 5 ms
// a frame saved filtering them at 1920x1080), so a map drawn again every
// frame, as while its light, its casters or (for a directional light) the
// camera move, goes without.
void make_planes(const facet_shadow_map& sm, const std::vector<uint16_t>& texels,
                 Pipeline& pipeline, std::vector<float>& tiles) {
    constexpr int kTile = FACET_SHADOW_TILE;
    ShadowPlaneRows rows;
    rows.stride = distance_stride(int(sm.width));
    rows.distances = texels.data() + size_t(FACET_SHADOW_BORDER) * size_t(rows.stride + 1);
    rows.width = int(sm.width);
    const int tile_rows = int(sm.height) / kTile;
    tiles.resize(size_t(4) * size_t(rows.width / kTile) * size_t(tile_rows));
    rows.tiles = tiles.data();
    const Kernels& kernels = pipeline.kernels();
    constexpr int kBand = 4;
    pipeline.pool().parallel_for((tile_rows + kBand - 1) / kBand, [&](int band, int) {
        kernels.shadow_plane_rows(rows, band * kBand, std::min(kBand, tile_rows - band * kBand));
    });
}

// A point light's cube face `face` (+X, -X, +Y, -Y, +Z, -Z): the 90-degree
// map shaders read (`sm`, `size` texels a side), and the projection it is
// drawn with, as much wider as its border of FACET_SHADOW_BORDER texels.
void cube_face(const Light& light, const std::vector<glm::vec3>& casters, int face, int size,
               facet_shadow_map& sm, glm::mat4& view, glm::mat4& drawn) {
    static const glm::vec3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0},
                                       {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 axis = kAxes[face];
    view = look_at(light.position, light.position + axis, any_perpendicular_up(axis));
    float far = 0.1f;
    for (const glm::vec3& p : casters) far = std::max(far, glm::length(p - light.position));
    if (light.range > 0.0f) far = std::min(far, light.range);
    sm.near_plane = std::min(std::max(far * 1e-4f, 0.01f), far * 0.5f);  // a range of 0.005 too
    sm.far_plane = far * 1.01f;
    sm.projection = FACET_SHADOW_PERSPECTIVE;
    sm.texel_size = 2.0f / float(size);  // 2 tan(45 degrees) / size
    const glm::mat4 proj = perspective(glm::radians(90.0f), 1.0f, sm.near_plane, sm.far_plane,
                                       false);
    std::memcpy(sm.view_projection, glm::value_ptr(proj * view), sizeof sm.view_projection);
    const float half = 0.5f * float(size);
    const float wider = 2.0f * std::atan((half + float(FACET_SHADOW_BORDER)) / half);
    drawn = perspective(wider, 1.0f, sm.near_plane, sm.far_plane, false);
}

// A light's map size: its own or the scene's, rounded up to a multiple of
// 16 (whole tiles of planes, FACET_SHADOW_TILE, and depth rows of whole
// vectors, Framebuffer::stride()).
int map_size(const Scene& scene, const Light& light) {
    return ((light.shadow_map_size ? light.shadow_map_size : scene.settings.shadow_map_size) +
            15) & ~15;
}

// What the scene's shadow maps hold, together: each map's distances and
// planes, and the one depth target they are drawn into in turn.
void require_shadow_maps_within_budget(const Scene& scene) {
    uint64_t bytes = 0, largest_drawn = 0, maps = 0;
    int largest = 0;
    for (const Light& light : scene.lights) {
        if (!light.casts_shadow) continue;
        const int size = map_size(scene, light);
        const bool cube = light.type == LightType::point;
        const uint64_t faces = cube ? 6 : 1;
        const uint64_t drawn = uint64_t(size) + (cube ? 2 * FACET_SHADOW_BORDER : 0);
        const uint64_t distances =
            uint64_t(distance_stride(size)) * uint64_t(size + 2 * FACET_SHADOW_BORDER) * 2;
        const uint64_t planes = uint64_t(size / FACET_SHADOW_TILE) *
                                uint64_t(size / FACET_SHADOW_TILE) * 4 * sizeof(float);
        bytes += faces * (distances + planes);
        largest_drawn = std::max(largest_drawn, drawn);
        largest = std::max(largest, size);
        maps += faces;
    }
    bytes += largest_drawn * largest_drawn * sizeof(float);
    if (bytes <= memory_budget()) return;  // no message made: a steady frame allocates nothing
    require_within_budget(bytes,
                          "shadow mapping (" + std::to_string(maps) + " maps, the largest " +
                              std::to_string(largest) + " texels a side)",
                          scene.source.string());
}

}  // namespace

void render_shadow_maps(const Scene& scene, const std::vector<DrawItem>& casters,
                        Pipeline& pipeline, ShadowMaps& maps, FrameStats& stats) {
    require_shadow_maps_within_budget(scene);
    caster_corners(casters, maps.corners);
    const float aspect = float(scene.settings.width) / float(scene.settings.height);
    maps.faces.clear();
    maps.first_face.assign(scene.lights.size(), 0);
    maps.by_light.assign(scene.lights.size(), facet_shadow{});
    size_t slot = 0;  // the maps drawn, in the order of the lights
    // Draws slot k, `drawn_size` texels a side through drawn_proj * view,
    // unless what it holds is already that; then points sm at its
    // distances and their planes.
    const auto draw_slot = [&](facet_shadow_map& sm, const glm::mat4& view,
                               const glm::mat4& drawn_proj, int drawn_size, bool with_border) {
        const size_t k = slot++;
        if (maps.drawn_size.size() <= k) maps.drawn_size.resize(k + 1, 0);
        if (maps.distance_texels.size() <= k) maps.distance_texels.resize(k + 1);
        if (maps.plane_tiles.size() <= k) maps.plane_tiles.resize(k + 1);
        if (maps.key.size() <= k) maps.key.resize(k + 1);  // empty: nothing drawn yet
        Framebuffer& depth = maps.depth;
        const uint64_t culled = make_key(casters, drawn_proj * view, drawn_size,
                                        float(scene.time), maps.next);
        if (maps.next == maps.key[k] && maps.drawn_size[k] == drawn_size) {
            ++stats.shadow_maps_reused;
            if (maps.plane_tiles[k].empty())
                make_planes(sm, maps.distance_texels[k], pipeline, maps.plane_tiles[k]);
        } else {
            std::swap(maps.key[k], maps.next);
            maps.drawn_size[k] = drawn_size;
            if (depth.width() != drawn_size)
                depth.resize(drawn_size, drawn_size, ColorFormat::none);
            pipeline.clear(depth, glm::vec4(0.0f), 1.0f);
            draw_depth(maps.key[k], view, drawn_proj, pipeline, depth, stats);
            make_distances(sm, depth, with_border, pipeline, maps.distance_texels[k]);
            maps.plane_tiles[k].clear();  // made again if the map is kept
            ++stats.shadow_passes;
            stats.shadow_casters_culled += culled;
        }
        const int stride = distance_stride(int(sm.width));
        sm.stride = uint32_t(stride);
        sm.texels =
            maps.distance_texels[k].data() + size_t(FACET_SHADOW_BORDER) * size_t(stride + 1);
        const std::vector<float>& tiles = maps.plane_tiles[k];
        sm.tiles = tiles.empty() ? nullptr : tiles.data();
        sm.tile_stride = sm.width / FACET_SHADOW_TILE;
    };
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& light = scene.lights[i];
        if (!light.casts_shadow) continue;
        const int size = map_size(scene, light);
        glm::mat4 view, proj;
        maps.first_face[i] = maps.faces.size();
        if (light.type == LightType::point) {
            for (int face = 0; face < 6; ++face) {
                facet_shadow_map& sm = maps.faces.emplace_back();
                cube_face(light, maps.corners, face, size, sm, view, proj);
                sm.width = sm.height = uint32_t(size);
                draw_slot(sm, view, proj, size + 2 * FACET_SHADOW_BORDER, true);
            }
            maps.by_light[i].map_count = 6;
            continue;
        }
        facet_shadow_map& sm = maps.faces.emplace_back();
        if (light.type == LightType::directional)
            directional(scene, light, maps.corners, aspect, size, sm, view, proj);
        else
            spot(light, maps.corners, size, sm, view, proj);
        sm.width = sm.height = uint32_t(size);
        std::memcpy(sm.view_projection, glm::value_ptr(proj * view), sizeof sm.view_projection);
        draw_slot(sm, view, proj, size, false);
        maps.by_light[i].map_count = 1;
    }
    // The faces are all made: point each light's record at its own.
    for (size_t i = 0; i < scene.lights.size(); ++i)
        if (maps.by_light[i].map_count) maps.by_light[i].maps = maps.faces.data() + maps.first_face[i];
}

}  // namespace facet
