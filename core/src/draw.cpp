// Geometry for queued draws: vertex stage, primitive assembly, clipping and
// setup (in parallel chunks), then, for all queued draws together, binning
// into tiles (bin.cpp) and the tiles rasterized and shaded in parallel by
// the renderer's kernels (kernels.hpp: rasterize.cpp, fragment.cpp).
// Triangles go through in batches of at most kTriangleBatch, which bounds
// memory however large the mesh.
#include "bin.hpp"
#include "clip.hpp"
#include "draw_context.hpp"
#include "geometry.hpp"
#include "setup.hpp"

#include "facet/error.hpp"
#include "facet/math.hpp"
#include "facet/renderer.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace facet {

namespace {

constexpr uint32_t kVertexBatch = 256;
constexpr size_t kSetupChunk = 1024;                   // triangles per setup task
constexpr size_t kTriangleBatch = 32 * kSetupChunk;   // triangles binned at once, at most
// (each round of setup, binning and rasterization ends with a thread idle,
// so fewer rounds scale better; 32k setups, 6 MiB, stay in the caches)
constexpr int kMaxQueuedDraws = 256;                   // draws binned at once, at most
// Every queued draw's last chunk may be partly full.
constexpr int kMaxChunks = int(kTriangleBatch / kSetupChunk) + kMaxQueuedDraws;
// Bins hold chunk << 16 | index: both must fit in 16 bits (a clipped
// triangle becomes at most kMaxClipVertices - 2 setups).
static_assert(kSetupChunk * (kMaxClipVertices - 2) < (1u << 16));
static_assert(kMaxChunks < (1 << 16));

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

// Sign of the area of a convex clip-space polygon on screen (y down); 0
// when it is no wider than a step of the sub-pixel grid. Then every point
// of it lies within a step of its outline, and the fan of its snapped
// corners can fold over itself and cover samples twice.
int screen_orientation(const ClipVertex* poly, int n, const Viewport& viewport) {
    double area = 0.0, perimeter = 0.0;  // twice the area, in pixels
    for (int i = 0; i < n; ++i) {
        const glm::dvec2 a = to_window(poly[i].position, viewport);
        const glm::dvec2 b = to_window(poly[(i + 1) % n].position, viewport);
        area += a.x * b.y - b.x * a.y;
        perimeter += glm::length(b - a);
    }
    const double step = std::ldexp(1.0, -std::clamp(viewport.subpixel_bits, 1, kSubpixelBits));
    if (!(std::abs(area) > perimeter * step)) return 0;
    return area > 0.0 ? 1 : -1;
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

// What the vertex stage records of each vertex in WindowVertex::user: its
// outcodes against the viewport (for rejection) and the guard band (for
// clipping), and whether it is unusable.
constexpr uint32_t kInvalid = 1u << 16;   // a non-finite clip position
constexpr uint32_t kNoWindow = 1u << 17;  // w <= 0: not projected
uint32_t view_code(uint32_t user) { return user & 0xFFu; }
uint32_t band_code(uint32_t user) { return user >> 8 & 0xFFu; }

// Outcodes of every vertex of [first, first + count), and the window
// position of those inside the guard band: once per vertex, however many
// triangles share it.
void project_vertices(QueuedDraw& d, size_t first, size_t count, const Viewport& viewport) {
    const double guard = viewport.guard_ndc();
    for (size_t i = first; i < first + count; ++i) {
        WindowVertex& w = d.window[i];
        if (!finite(d.clip[i])) {
            w.user = kInvalid;
            continue;
        }
        const glm::dvec4 c(d.clip[i]);
        w.user = outcode(c, 1.0) | outcode(c, guard) << 8;
        if (band_code(w.user) == 0 && !project_vertex(c, viewport, w)) w.user |= kNoWindow;
    }
}

// Assembles, clips and sets up a range of a mesh's triangles into `chunk`.
class Assembler {
public:
    Assembler(const QueuedDraw& d, const Viewport& viewport, const CullState& cull)
        : dc_(d.dc), draw_(d), viewport_(viewport), cull_(cull), guard_(viewport.guard_ndc()) {}

    void run(const uint32_t* idx, size_t triangles, SetupChunk& chunk) const {
        for (size_t t = 0; t < triangles; ++t, idx += 3) {
            ++chunk.stats.triangles_in;
            const WindowVertex* w[3] = {&draw_.window[idx[0]], &draw_.window[idx[1]],
                                        &draw_.window[idx[2]]};
            const uint32_t any = w[0]->user | w[1]->user | w[2]->user;
            if (any & kInvalid) {
                ++chunk.stats.triangles_invalid;
                continue;
            }
            if (view_code(w[0]->user) & view_code(w[1]->user) & view_code(w[2]->user)) {
                ++chunk.stats.triangles_culled_frustum;
                continue;
            }
            const float* varyings[3];
            for (int i = 0; i < 3; ++i)
                varyings[i] = draw_.varyings.data() + size_t(idx[i]) * dc_.varying_floats;
            SetupResult r;
            if (const uint32_t planes = band_code(any)) {
                const SetupVertex v[3] = {{glm::dvec4(draw_.clip[idx[0]]), varyings[0]},
                                          {glm::dvec4(draw_.clip[idx[1]]), varyings[1]},
                                          {glm::dvec4(draw_.clip[idx[2]]), varyings[2]}};
                r = clipped(v, planes, chunk);
                if (r == SetupResult::ok) ++chunk.stats.triangles_clipped;
            } else if (any & kNoWindow) {
                r = SetupResult::degenerate;  // a vertex at the origin, w = 0
            } else {
                TriangleSetup& s = chunk.setups.emplace_back();
                r = setup_triangle(w, varyings, viewport_, cull_, s);
                if (r != SetupResult::ok) chunk.setups.pop_back();
            }
            count(r, chunk.stats);
        }
    }

private:
    SetupResult setup(const SetupVertex v[3], int orientation, SetupChunk& chunk) const {
        TriangleSetup& t = chunk.setups.emplace_back();
        const SetupResult r = setup_triangle(v, viewport_, cull_, t, orientation);
        if (r != SetupResult::ok) chunk.setups.pop_back();
        return r;
    }

    // Clips the triangle and sets up the fan of what is left, each piece held
    // to the orientation of the whole polygon.
    SetupResult clipped(const SetupVertex v[3], uint32_t planes, SetupChunk& chunk) const {
        ClipVertex in[3], out[kMaxClipVertices];
        const int floats = int(dc_.varying_floats);
        for (int i = 0; i < 3; ++i) {
            in[i].position = v[i].clip;
            std::memcpy(in[i].varyings, v[i].varyings, sizeof(float) * floats);
        }
        const int n = clip_polygon(in, 3, planes, guard_, floats, dc_.interpolation, out);
        if (n < 3) return SetupResult::clipped_away;
        // Flat varyings keep the first input vertex's value, not a blend.
        for (int k = 0; k < floats; ++k)
            if (dc_.interpolation[k] == FACET_INTERP_FLAT)
                for (int i = 0; i < n; ++i) out[i].varyings[k] = v[0].varyings[k];
        const size_t first = chunk.clipped_used;
        chunk.clipped_used += size_t(n);
        if (chunk.clipped.size() < chunk.clipped_used) chunk.clipped.resize(chunk.clipped_used);
        std::copy(out, out + n, chunk.clipped.begin() + std::ptrdiff_t(first));
        const int orientation = screen_orientation(out, n, viewport_);
        if (orientation == 0) return SetupResult::degenerate;
        SetupResult result = SetupResult::clipped_away;
        for (int i = 1; i + 1 < n; ++i) {
            const ClipVertex* a = &chunk.clipped[first];
            const ClipVertex* b = &chunk.clipped[first + size_t(i)];
            const ClipVertex* c = &chunk.clipped[first + size_t(i) + 1];
            const SetupVertex tri[3] = {{a->position, a->varyings},
                                        {b->position, b->varyings},
                                        {c->position, c->varyings}};
            const SetupResult r = setup(tri, orientation, chunk);
            if (r == SetupResult::ok || result == SetupResult::clipped_away) result = r;
        }
        return result;
    }

    const DrawContext& dc_;
    const QueuedDraw& draw_;  // its vertices
    const Viewport& viewport_;
    const CullState& cull_;
    const double guard_;  // guard-band half-width, NDC
};

// Vertex stage: every vertex once, kVertexBatch per plugin call (batches in
// parallel), with only the inputs the shader asks for.
void shade_vertices(const Mesh& mesh, const ShaderPlugin& shader, const Viewport& viewport,
                    ThreadPool& pool, QueuedDraw& d) {
    const size_t vcount = mesh.vertex_count();
    const uint32_t floats = shader.varying_floats();
    d.clip.resize(vcount);
    d.window.resize(vcount);
    d.varyings.resize(vcount * floats + 1);
    const int batches = int((vcount + kVertexBatch - 1) / kVertexBatch);
    pool.parallel_for(batches, [&](int b, int) {
        const size_t first = size_t(b) * kVertexBatch;
        const facet_vertex_batch batch{
            uint32_t(std::min<size_t>(kVertexBatch, vcount - first)),
            glm::value_ptr(mesh.positions[first]),
            input(shader, FACET_NEED_NORMALS, mesh.normals, first),
            input(shader, FACET_NEED_UVS, mesh.uvs, first),
            input(shader, FACET_NEED_COLORS, mesh.colors, first),
            nullptr,  // tangents: no shader may ask for them yet (plugin.cpp refuses it)
            glm::value_ptr(d.clip[first]),
            d.varyings.data() + first * floats,
            floats};
        shader.desc().vertex(&d.abi, &batch);
        project_vertices(d, first, batch.count, viewport);
    });
}

// Bins every queued triangle and rasterizes the tiles in parallel, adding
// the triangle and fragment counts to `stats`. The queued draws stay (a
// draw may have more triangles to come).
void rasterize_queued(Geometry& g, FrameStats& stats) {
    if (g.chunks_used == 0) return;
    g.bins.resize(g.target->width(), g.target->height());
    for (Geometry::WorkerStats& w : g.worker_stats) w.stats = {};
    g.bins.bin(g.chunks, g.chunks_used);
    const std::vector<int>& busy = g.bins.busy();
    g.pool.parallel_for(int(busy.size()), [&](int i, int worker) {
        g.kernels->draw_tile(g, busy[size_t(i)], g.worker_stats[size_t(worker)].stats);
    });
    g.bins.clear();
    for (int c = 0; c < g.chunks_used; ++c) stats += g.chunks[size_t(c)].stats;
    for (const Geometry::WorkerStats& w : g.worker_stats) stats += w.stats;
    g.chunks_used = 0;
    g.triangles_queued = 0;
}

}  // namespace

void Renderer::draw(const DrawCall& call, Framebuffer& target, FrameStats& stats) {
    queue(call, target, stats);
    flush(stats);
}

void Renderer::queue(const DrawCall& call, Framebuffer& target, FrameStats& stats) {
    if (!call.mesh || !call.shader)
        throw Error(ErrorCode::config_invalid, "draw call without a mesh or a shader");
    const Mesh& mesh = *call.mesh;
    const ShaderPlugin& shader = *call.shader;
    Geometry& g = *geometry_;
    if (g.chunks_used > 0 && (g.target != &target || g.draws_used == kMaxQueuedDraws))
        rasterize_queued(g, stats);
    if (g.chunks_used == 0) g.draws_used = 0;  // every earlier draw is done
    if (g.draws.size() == size_t(g.draws_used)) g.draws.push_back(std::make_unique<QueuedDraw>());
    int index = g.draws_used++;
    QueuedDraw& d = *g.draws[size_t(index)];
    g.target = &target;
    ++stats.draws;

    d.dc = {};
    prepare_context(d.dc, shader, g.kernels->isa, call.textures, call.texture_count);
    d.dc.state = call.state;
    d.dc.target = &target;
    d.dc.ao = shader.needs(FACET_NEED_AO) ? call.ao : nullptr;
    d.abi = make_abi_draw(call, target.width(), target.height(), d.dc);
    d.dc.abi = &d.abi;
    const Viewport viewport{target.width(), target.height(), target.samples(),
                            call.state.subpixel_bits};
    shade_vertices(mesh, shader, viewport, g.pool, d);
    stats.vertices_shaded += mesh.vertex_count();

    const CullState cull = cull_state(call.state);
    const Assembler assembler(d, viewport, cull);
    const size_t triangles = mesh.triangle_count();
    for (size_t first = 0; first < triangles; first += kTriangleBatch) {
        const size_t count = std::min(kTriangleBatch, triangles - first);
        const int chunks = int((count + kSetupChunk - 1) / kSetupChunk);
        if (g.triangles_queued + count > kTriangleBatch || g.chunks_used + chunks > kMaxChunks) {
            rasterize_queued(g, stats);
            // Only this draw is left: it moves to the first slot, freeing the
            // others (and their vertex storage) for the draws that follow.
            std::swap(g.draws[0], g.draws[size_t(index)]);
            index = 0;
            g.draws_used = 1;
        }
        if (g.chunks.size() < size_t(g.chunks_used + chunks))
            g.chunks.resize(size_t(g.chunks_used + chunks));
        g.pool.parallel_for(chunks, [&](int c, int) {
            SetupChunk& chunk = g.chunks[size_t(g.chunks_used + c)];
            chunk.setups.clear();
            chunk.clipped_used = 0;
            chunk.draw = index;
            chunk.stats = {};
            const size_t begin = first + size_t(c) * kSetupChunk;
            assembler.run(mesh.indices.data() + 3 * begin,
                          std::min(kSetupChunk, first + count - begin), chunk);
        });
        g.chunks_used += chunks;
        g.triangles_queued += count;
    }
}

void Renderer::flush(FrameStats& stats) {
    rasterize_queued(*geometry_, stats);
    geometry_->draws_used = 0;
}

}  // namespace facet
