// The Pipeline (facet/pipeline.hpp): queued draws go through the vertex
// stage (vertex.cpp) and primitive assembly, clipping and setup
// (assembly.cpp) in parallel chunks as they are queued, each chunk binning
// its setups into tiles as it ends (bin.cpp); at flush() each tile gathers
// the chunks that touch it, and the tiles are rasterized and shaded in
// parallel by the pipeline's kernels (kernels.hpp:
// rasterize.cpp, fragment.cpp). Triangles go through in batches of at most
// kTriangleBatch, which bounds memory however large the mesh. A flush may
// keep what it drew (flush(stats, true)) for redraw(): the same triangles
// shaded again with other state, as a main pass after a depth pre-pass.
#include "facet/pipeline.hpp"

#include "pipeline/assembly.hpp"
#include "pipeline/draw_queue.hpp"
#include "pipeline/framebuffer_access.hpp"
#include "pipeline/kernels.hpp"
#include "pipeline/sky.hpp"
#include "base/thread_pool.hpp"
#include "pipeline/vertex.hpp"

#include "facet/error.hpp"
#include "facet/mesh.hpp"
#include "facet/plugin.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <string>

namespace facet {

namespace {

constexpr size_t kSetupChunk = 1024;                   // triangles per setup task
constexpr size_t kTriangleBatch = 32 * kSetupChunk;   // triangles binned at once, at most
// (each round of setup, binning and rasterization ends with a thread idle,
// so fewer rounds scale better; 32k setups, 6 MiB, stay in the caches)
constexpr int kMaxQueuedDraws = 256;                   // draws binned at once, at most
// Every queued draw's last chunk may be partly full.
constexpr int kMaxChunks = int(kTriangleBatch / kSetupChunk) + kMaxQueuedDraws;
// A chunk's setups are numbered in 16 bits (SetupChunk::binned): a clipped
// triangle, or a line's or point's quadrilateral, becomes at most
// kMaxClipVertices - 2 setups.
static_assert(kSetupChunk * (kMaxClipVertices - 2) < (1u << 16));

// Forgets the queued triangles, drawn or not, and any kept.
void drop_queued(DrawQueue& g) {
    if (g.kept) g.bins.clear();
    g.kept = false;
    g.chunks_used = 0;
    g.triangles_queued = 0;
}

// How a draw reads its part: as triangles (three mesh indices each), its
// wire (a MeshEdge each, the part's edges), lines (two vertex indices each,
// its edges once) or points (one each, its vertices).
enum class Primitives { triangles, wire, lines, points };

Primitives primitives_of(const PipelineState& s) {
    if (s.wireframe) return Primitives::wire;
    switch (s.topology) {
        case Topology::triangles: return Primitives::triangles;
        case Topology::lines: return Primitives::lines;
        case Topology::points: return Primitives::points;
    }
    return Primitives::triangles;
}

size_t indices_per(Primitives p) {
    switch (p) {
        case Primitives::triangles: return 3;
        case Primitives::wire: return sizeof(MeshEdge) / sizeof(uint32_t);
        case Primitives::lines: return 2;
        case Primitives::points: return 1;
    }
    return 3;
}

// What a draw of `part` as its wire, lines or points reads (Primitives).
void list_primitives(const Mesh& mesh, const MeshPart& part, Primitives kind, EdgeCache& cache,
                     std::vector<uint32_t>& out) {
    out.clear();
    if (kind == Primitives::points) {
        for (uint32_t v = 0; v < part.vertex_count; ++v) out.push_back(part.first_vertex + v);
        return;
    }
    const std::vector<MeshEdge>& edges =
        cache.edges(mesh.indices.data() + part.first_index, part.index_count);
    if (kind == Primitives::wire) {
        static_assert(sizeof(MeshEdge) == 4 * sizeof(uint32_t));
        out.resize(edges.size() * 4);
        std::memcpy(out.data(), edges.data(), edges.size() * sizeof(MeshEdge));
        return;
    }
    for (size_t i = 0; i < edges.size(); ++i) {
        if (i > 0 && edges[i].a == edges[i - 1].a && edges[i].b == edges[i - 1].b) continue;
        out.push_back(edges[i].a);
        out.push_back(edges[i].b);
    }
}

// A queued draw's state and what its fragments read, from `call` (whose band
// of rows, if any, lies within its image).
void set_context(QueuedDraw& d, const DrawCall& call, Framebuffer& target, Isa isa) {
    const ShaderPlugin& shader = *call.shader;
    d.dc = {};
    prepare_context(d.dc, shader, isa, call.params, call.textures, call.texture_count,
                    call.may_discard, call.state);
    d.dc.target = &target;
    // The stencil test applies where the target has the buffer: as in GL,
    // a target without one passes every fragment and writes nothing.
    d.dc.stencil = call.state.stencil.enabled && target.has_stencil();
    if (d.dc.stencil) d.dc.packable = false;  // its tests come in order, block by block
    d.dc.ao = shader.needs(FACET_NEED_AO) ? call.ao : nullptr;
    d.dc.ao_grid = shader.needs(FACET_NEED_AO) ? call.ao_grid : nullptr;
    // Without an AO pass a plugin of ABI 1.3 on gets a NULL ao, which it
    // reads as full visibility: nothing is gathered or packed for it.
    if (!d.dc.ao && !d.dc.ao_grid && shader.desc().abi_minor >= 3) d.dc.needs_ao = false;
    if (call.state.wireframe) {  // the wire's colour is the state's: no fragment shader runs
        d.dc.varying_floats = 0;
        d.dc.sample_textures = d.dc.packable = d.dc.may_discard = d.dc.needs_ao = false;
        d.dc.state.alpha_to_coverage = false;  // no alpha to pick samples by
        d.dc.ao = nullptr;
        d.dc.ao_grid = nullptr;
    }
    d.dc.environment = call.environment;
    d.dc.first_row = call.image_height > 0 ? call.first_row : 0;
    d.abi = make_abi_draw(call, target.width(),
                          call.image_height > 0 ? call.image_height : target.height(), d.dc);
    d.dc.abi = &d.abi;
}

// Rasterizes the tiles of the binned triangles in parallel, adding the
// triangle and fragment counts to `stats`. Once `stop` is true, tiles not
// yet begun are skipped.
void rasterize_binned(DrawQueue& g, ThreadPool& pool, const Kernels& kernels,
                      const Pipeline& stop, FrameStats& stats) {
    for (DrawQueue::WorkerStats& w : g.worker_stats) w.stats = {};
    const std::vector<int>& busy = g.bins.busy();
    g.clear_now = nullptr;
    for (PendingClear& c : g.clears)
        if (c.waiting && c.target == g.target && c.fits()) g.clear_now = &c;
    pool.parallel_for(int(busy.size()), [&](int i, int worker) {
        if (stop.stopped()) return;
        kernels.draw_tile(g, busy[size_t(i)], g.worker_stats[size_t(worker)].stats);
    });
    g.clear_now = nullptr;
    for (int c = 0; c < g.chunks_used; ++c) stats += g.chunks[size_t(c)].stats;
    for (const DrawQueue::WorkerStats& w : g.worker_stats) stats += w.stats;
}

// Gathers the queued chunks into tiles and rasterizes them (rasterize_binned). The
// queued draws stay (a draw may have more triangles to come); with `keep`,
// the triangles and their bins too, for Pipeline::redraw.
void rasterize_queued(DrawQueue& g, ThreadPool& pool, const Kernels& kernels,
                      const Pipeline& stop, FrameStats& stats, bool keep = false) {
    if (g.chunks_used == 0) return;
    if (stop.stopped()) return drop_queued(g);
    g.bins.gather(g.chunks, g.chunks_used);  // each chunk was binned as it was set up
    rasterize_binned(g, pool, kernels, stop, stats);
    if (keep && !stop.stopped()) {
        g.kept = true;
        g.kept_width = g.target->width(), g.kept_height = g.target->height();
        g.kept_samples = g.target->samples();
        return;
    }
    g.bins.clear();
    drop_queued(g);
}

// Whether `known` says which of the target's tiles still hold every value
// `c` writes (compared bit for bit: -0 and 0 differ).
bool holds_values_of(const FramebufferAccess::ClearedTiles& known, const PendingClear& c) {
    return known.tile_size == kTileSize && known.columns == c.columns && known.rows == c.rows &&
           known.held.size() == c.cleared.size() &&
           std::memcmp(&known.color, &c.color, sizeof c.color) == 0 &&
           std::memcmp(&known.depth, &c.depth, sizeof c.depth) == 0 && known.stencil == c.stencil;
}

// Records that the tiles no draw touched hold c's values, and the rest not.
void remember_clear(FramebufferAccess::ClearedTiles& known, const PendingClear& c) {
    known.tile_size = kTileSize;
    known.columns = c.columns;
    known.rows = c.rows;
    known.color = c.color;
    known.depth = c.depth;
    known.stencil = c.stencil;
    known.held.resize(c.cleared.size());
    for (size_t t = 0; t < c.cleared.size(); ++t) known.held[t] = !c.cleared[t];
}

// Completes the clears that wait (PendingClear): each row of tiles in
// parallel, the tiles no draw cleared in runs (a row with none cleared as
// one run of storage), less those the target still holds from a clear to
// the same values that nothing has touched since (Framebuffer's
// ClearedTiles): a frame that leaves most of the target empty, as a small
// mesh in view does, then writes only what its draws touched.
void complete_clears(DrawQueue& g, ThreadPool& pool, const Kernels& kernels) {
    for (PendingClear& c : g.clears) {
        if (!c.waiting) continue;
        c.waiting = false;
        if (!c.fits()) continue;  // resized since: its contents are undefined until cleared again
        Framebuffer& fb = *c.target;
        FramebufferAccess::ClearedTiles& known = FramebufferAccess::cleared(fb);
        const bool trusted = FramebufferAccess::known(fb) && holds_values_of(known, c);
        pool.parallel_for(c.rows, [&](int row, int) {
            const size_t at = size_t(row) * size_t(c.columns);
            const auto written = [&](int column) {  // drawn, or still holding the values
                return c.cleared[at + size_t(column)] || (trusted && known.held[at + size_t(column)]);
            };
            for (int first = 0; first < c.columns;) {
                if (written(first)) {
                    ++first;
                    continue;
                }
                int last = first;
                while (last + 1 < c.columns && !written(last + 1)) ++last;
                int x0, y0, x1, y1, last_x0, last_y0, last_x1, last_y1;
                c.storage_rect(row * c.columns + first, x0, y0, x1, y1);
                c.storage_rect(row * c.columns + last, last_x0, last_y0, last_x1, last_y1);
                kernels.clear_rect(fb, x0, y0, last_x1, y1, c.color, c.depth, c.stencil, true);
                first = last + 1;
            }
        });
        remember_clear(known, c);
    }
}

// Calls fn(first_row, rows) for bands of `height` rows, in parallel.
template <class Fn>
void for_row_bands(ThreadPool& pool, int height, Fn&& fn) {
    constexpr int kBand = 32;
    pool.parallel_for((height + kBand - 1) / kBand, [&](int band, int) {
        fn(band * kBand, std::min(kBand, height - band * kBand));
    });
}

}  // namespace

// The table of a path's kernels (kernels.hpp): those the build linked in.
const Kernels& kernels(Isa isa) {
    switch (checked_isa(isa)) {
#if FACET_KERNELS_avx2
        case Isa::avx2: return facet_kernels_avx2;
#endif
#if FACET_KERNELS_avx512
        case Isa::avx512: return facet_kernels_avx512;
#endif
        default: return facet_kernels_portable;
    }
}


int default_threads() {
    const char* env = std::getenv("FACET_NUM_THREADS");
    if (!env || !*env) return int(std::max(1u, std::thread::hardware_concurrency()));
    int n = 0;
    const char* c = env;
    for (; *c >= '0' && *c <= '9' && n <= 256; ++c) n = n * 10 + (*c - '0');
    if (*c != '\0' || n < 1 || n > 256)
        throw Error(ErrorCode::config_invalid,
                    "FACET_NUM_THREADS=" + std::string(env) + ": expected a thread count 1..256");
    return n;
}

Pipeline::Pipeline(int threads, std::optional<Isa> isa)
    : pool_(std::make_unique<ThreadPool>(threads > 0 ? threads : default_threads())),
      kernels_(&facet::kernels(isa ? checked_isa(*isa) : default_isa())),
      queue_(std::make_unique<DrawQueue>(pool_->size())) {
    const auto set = [](const char* name) {
        const char* value = std::getenv(name);
        return value && *value;
    };
    spdlog::debug("pipeline: {} threads ({}), the {} path ({})", pool_->size(),
                  threads > 0                   ? "asked for"
                  : set("FACET_NUM_THREADS") ? "FACET_NUM_THREADS"
                                                : "one per hardware thread",
                  isa_name(kernels_->isa),
                  isa                   ? "asked for"
                  : set("FACET_ISA") ? "FACET_ISA"
                                        : "the best this CPU has");
}
Pipeline::~Pipeline() = default;
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;

int Pipeline::threads() const { return pool_->size(); }
Isa Pipeline::isa() const { return kernels_->isa; }

void Pipeline::draw(const DrawCall& call, Framebuffer& target, FrameStats& stats) {
    queue(call, target, stats);
    flush(stats);
}

void Pipeline::queue(const DrawCall& call, Framebuffer& target, FrameStats& stats) {
    if (!call.mesh || !call.shader)
        throw Error(ErrorCode::config_invalid, "draw call without a mesh or a shader");
    if (stopped()) return drop_queued(*queue_);
    const Mesh& mesh = *call.mesh;
    const ShaderPlugin& shader = *call.shader;
    if (shader.is_post())
        throw Error(ErrorCode::plugin_invalid,
                    "'" + shader.name() + "' is a screen pass: it cannot draw a mesh",
                    shader.origin());
    DrawQueue& g = *queue_;
    if (g.kept) drop_queued(g);
    if (g.chunks_used > 0 && (g.target != &target || g.draws_used == kMaxQueuedDraws)) {
        // Full, its draws are rasterized before all of theirs are queued;
        // for another target, they are all there is of theirs.
        g.split = g.target == &target;
        rasterize_queued(g, *pool_, *kernels_, *this, stats);
    }
    if (g.chunks_used == 0) g.draws_used = 0;  // every earlier draw is done
    if (g.draws.size() == size_t(g.draws_used)) g.draws.push_back(std::make_unique<QueuedDraw>());
    int index = g.draws_used++;
    QueuedDraw& d = *g.draws[size_t(index)];
    g.target = &target;
    ++stats.draws;
    d.geometry = Geometry(call);

    const int image_height = call.image_height > 0 ? call.image_height : target.height();
    if (call.image_height > 0 &&
        (call.first_row < 0 || int64_t(call.first_row) + target.height() > call.image_height))
        throw Error(ErrorCode::out_of_range,
                    "a band of rows " + std::to_string(call.first_row) + ".." +
                        std::to_string(int64_t(call.first_row) + target.height() - 1) +
                        " lies outside its image of " + std::to_string(call.image_height) +
                        " rows");
    set_context(d, call, target, kernels_->isa);
    g.bins.resize(target.width(), target.height());  // the grid each chunk is binned on
    const Viewport viewport{target.width(), image_height,      target.samples(),
                            call.state.subpixel_bits, d.dc.first_row, target.height()};
    const MeshPart part = call.part ? *call.part : mesh.whole_part();
    if (uint64_t(part.first_index) + part.index_count > mesh.indices.size() ||
        part.index_count % 3 != 0 ||
        uint64_t(part.first_vertex) + part.vertex_count > mesh.vertex_count())
        throw Error(ErrorCode::config_invalid,
                    "draw call of part '" + part.name + "', which lies outside its mesh",
                    mesh.source);
    shade_vertices(mesh, part.first_vertex, part.vertex_count, shader, viewport, *kernels_, *pool_,
                   d);
    stats.vertices_shaded += part.vertex_count;

    const CullState cull = cull_state(call.state);
    const Assembler assembler(d, viewport, cull, part.first_vertex, kernels_->assemble_triangles);
    const Primitives kind = primitives_of(call.state);
    if (kind != Primitives::triangles) list_primitives(mesh, part, kind, g.edges, d.primitives);
    const size_t per = indices_per(kind);
    const uint32_t* part_indices = mesh.indices.data() + part.first_index;
    const uint32_t* indices = kind == Primitives::triangles ? part_indices : d.primitives.data();
    const size_t triangles =
        kind == Primitives::triangles ? part.triangle_count() : d.primitives.size() / per;
    for (size_t first = 0; first < triangles; first += kTriangleBatch) {
        if (stopped()) return drop_queued(g);
        const size_t count = std::min(kTriangleBatch, triangles - first);
        const int chunks = int((count + kSetupChunk - 1) / kSetupChunk);
        if (g.triangles_queued + count > kTriangleBatch || g.chunks_used + chunks > kMaxChunks) {
            rasterize_queued(g, *pool_, *kernels_, *this, stats);
            g.split = true;
            // Only this draw is left: it moves to the first slot, freeing the
            // others (and their vertex storage) for the draws that follow.
            std::swap(g.draws[0], g.draws[size_t(index)]);
            index = 0;
            g.draws_used = 1;
        }
        if (g.chunks.size() < size_t(g.chunks_used + chunks))
            g.chunks.resize(size_t(g.chunks_used + chunks));
        pool_->parallel_for(chunks, [&](int c, int) {
            SetupChunk& chunk = g.chunks[size_t(g.chunks_used + c)];
            chunk.setups.clear();
            chunk.clipped_used = 0;
            chunk.draw = index;
            chunk.stats = {};
            const size_t begin = first + size_t(c) * kSetupChunk;
            const size_t n = std::min(kSetupChunk, first + count - begin);
            const uint32_t* first_primitive = indices + per * begin;
            switch (kind) {
                case Primitives::triangles: assembler.run(first_primitive, n, chunk); break;
                case Primitives::wire:
                    assembler.run_wire(first_primitive, n, indices, part_indices, chunk);
                    break;
                case Primitives::lines: assembler.run_lines(first_primitive, n, chunk); break;
                case Primitives::points: assembler.run_points(first_primitive, n, chunk); break;
            }
            g.bins.bin_chunk(chunk);
        });
        g.chunks_used += chunks;
        g.triangles_queued += count;
    }
}

void Pipeline::flush(FrameStats& stats, bool keep_geometry) {
    DrawQueue& g = *queue_;
    if (g.kept) drop_queued(g);
    rasterize_queued(g, *pool_, *kernels_, *this, stats, keep_geometry && !g.split);
    g.split = false;
    if (!g.kept) g.draws_used = 0;
    complete_clears(g, *pool_, *kernels_);
}

void Pipeline::cancel() {
    drop_queued(*queue_);
    queue_->draws_used = 0;
    queue_->split = false;
    complete_clears(*queue_, *pool_, *kernels_);
}

bool Pipeline::redraw(const std::vector<DrawCall>& calls, Framebuffer& target,
                      FrameStats& stats) {
    DrawQueue& g = *queue_;
    if (!g.kept) return false;  // (and what waits, if anything, still waits)
    const auto alike = [&] {
        if (g.target != &target || target.width() != g.kept_width ||
            target.height() != g.kept_height || target.samples() != g.kept_samples ||
            calls.size() != size_t(g.draws_used))
            return false;
        for (size_t i = 0; i < calls.size(); ++i)
            if (!calls[i].mesh || !calls[i].shader || !(Geometry(calls[i]) == g.draws[i]->geometry))
                return false;
        return true;
    };
    // Once stopped, nothing is drawn, as queue() and flush() draw nothing.
    const bool match = alike();
    if (match && !stopped()) {
        // Each draw's own state and fragment inputs, as queue() sets them
        // up, on the vertices, setups and bins the kept one made.
        for (size_t i = 0; i < calls.size(); ++i) {
            QueuedDraw& d = *g.draws[i];
            set_context(d, calls[i], target, kernels_->isa);
            ++stats.draws;
            ++stats.draws_redrawn;
            stats.vertices_shaded += d.geometry.vertex_count;  // once, for both passes
        }
        rasterize_binned(g, *pool_, *kernels_, *this, stats);
    }
    drop_queued(g);
    g.draws_used = 0;
    complete_clears(g, *pool_, *kernels_);
    return match;
}

Geometry::Geometry(const DrawCall& call)
    : mesh(call.mesh), shader(call.shader), params(call.params), textures(call.textures),
      texture_count(call.texture_count), model(call.model), view(call.view),
      projection(call.projection), camera_position(call.camera_position), lights(call.lights),
      light_count(call.light_count), shadows(call.shadows), time(call.time),
      image_height(call.image_height),
      first_row(call.first_row), cull(call.state.cull), front_ccw(call.state.front_ccw),
      subpixel_bits(call.state.subpixel_bits), topology(call.state.topology),
      wireframe(call.state.wireframe), line_width(call.state.line_width),
      point_size(call.state.point_size), depth_bias_constant(call.state.depth_bias_constant),
      depth_bias_slope(call.state.depth_bias_slope) {
    const auto take = [&](const MeshPart& part) {
        first_index = part.first_index, index_count = part.index_count;
        first_vertex = part.first_vertex, vertex_count = part.vertex_count;
    };
    if (call.part) take(*call.part);
    else if (call.mesh) take(call.mesh->whole_part());
}


void Pipeline::require_flushed(const Framebuffer& target, const char* what) const {
    if (queue_->chunks_used > 0 && !queue_->kept && queue_->target == &target)
        throw Error(ErrorCode::out_of_range,
                    std::string(what) + ": draws queued for the target wait; flush() first");
}

void Pipeline::clear(Framebuffer& target, const glm::vec4& color, float depth, uint8_t stencil) {
    require_flushed(target, "Pipeline::clear");
    DrawQueue& g = *queue_;
    // This target's entry, waiting or done, else one done, else a new one.
    PendingClear* c = nullptr;
    for (PendingClear& e : g.clears)
        if (e.target == &target || (!c && !e.waiting)) c = &e;
    if (!c) c = &g.clears.emplace_back();
    c->waiting = target.width() > 0 && target.height() > 0;
    c->target = &target;
    c->color = color;
    c->depth = depth;
    c->stencil = stencil;
    c->columns = tiles_across(target.width());
    c->rows = tiles_across(target.height());
    c->cleared.assign(size_t(c->columns) * size_t(c->rows), 0);
}

void Pipeline::resolve(Framebuffer& target) {
    require_flushed(target, "Pipeline::resolve");
    complete_clears(*queue_, *pool_, *kernels_);
    if (target.samples() == 1) return;
    FramebufferAccess::forget_cleared(target);
    const Kernels& k = *kernels_;
    for_row_bands(*pool_, target.height(),
                  [&](int first, int rows) { k.resolve_rows(target, first, rows); });
}

void Pipeline::sky(const SkyRows& sky) {
    require_flushed(*sky.target, "Pipeline::sky");
    complete_clears(*queue_, *pool_, *kernels_);
    FramebufferAccess::forget_cleared(*sky.target);
    const Kernels& k = *kernels_;
    for_row_bands(*pool_, sky.target->height(),
                  [&](int first, int rows) { k.sky_rows(sky, first, rows); });
}

void Pipeline::resolve_srgb8(const Framebuffer& target, std::vector<uint8_t>& out) {
    require_flushed(target, "Pipeline::resolve_srgb8");
    complete_clears(*queue_, *pool_, *kernels_);
    if (target.format() != ColorFormat::rgba16f && target.format() != ColorFormat::rgba32f) {
        target.resolve_srgb8(out);  // a copy (srgb8), or black (no colour)
        return;
    }
    out.resize(size_t(target.width()) * size_t(target.height()) * 4);
    const Kernels& k = *kernels_;
    for_row_bands(*pool_, target.height(),
                  [&](int first, int rows) { k.srgb8_rows(target, first, rows, out.data()); });
}

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
    fragments_depth_only += o.fragments_depth_only;
    shadow_passes += o.shadow_passes;
    shadow_maps_reused += o.shadow_maps_reused;
    shadow_casters_culled += o.shadow_casters_culled;
    prepasses += o.prepasses;
    depth_prepasses += o.depth_prepasses;
    draws_redrawn += o.draws_redrawn;
    ao_passes += o.ao_passes;
    shadows_needed |= o.shadows_needed;
    ao_needed |= o.ao_needed;
    milliseconds += o.milliseconds;
    ms_shadow += o.ms_shadow;
    ms_prepass += o.ms_prepass;
    ms_ao += o.ms_ao;
    ms_main += o.ms_main;
    ms_post += o.ms_post;
    post_passes += o.post_passes;
    for (int i = 0; i < kPostTimings; ++i) ms_post_pass[i] += o.ms_post_pass[i];
    return *this;
}

}  // namespace facet
