// facet-render-mpi: facet-render's sequences and band-split images across
// processes and machines, with Open MPI.
//
//     mpirun -np N facet-render-mpi SCENE.yaml --frames A..B|all [--fps F] [--resume] -o out_%04d.png
//     mpirun -np N facet-render-mpi SCENE.yaml --size 32768x32768 --band-rows 256 -o poster.png
//          [--time T] [--msaa N] [--threads N] [--max-memory SIZE] [--plugin-path DIR]...
//          [--plugin-timeout SECONDS] [--no-probe]
//
// Every rank loads the scene itself (assets on shared storage). Rank 0
// hands out the work one item at a time, as ranks ask for it, so a slow
// frame never holds up the others; it renders too, on a thread of its own.
//  - Frames: each rank writes the frames it renders (the output folder on
//    shared storage), each file moved into place only when complete.
//  - Bands: each rank renders a band of rows and encodes it as PNG
//    segments (facet/png.hpp); rank 0 writes them into the one PNG in
//    order as they arrive, holding at most a few bands. The image is never
//    whole in any process's memory.
// The output is bit for bit what facet-render writes for the same command.
// A rank that fails is reported with its frame or band: the frames already
// written stay; a band image is not written. A rank that crashes says what
// it was rendering on stderr before mpirun ends the job.
#include <facet/command_line.hpp>
#include <facet/error.hpp>
#include <facet/interrupts.hpp>
#include <facet/isa.hpp>
#include <facet/plugin.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/sequence.hpp>
#include <facet/tool.hpp>

#include <mpi.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <sched.h>
#include <unistd.h>
#include <vector>

namespace {

struct Options {
    std::string scene;
    std::string output;
    std::string size;
    std::string camera;
    int msaa = 0;
    bool wireframe = false;
    int threads = 0;  // 0: this machine's hardware threads shared by its ranks
    std::vector<std::string> plugin_paths;
    std::string max_memory;
    std::optional<double> time;
    std::string frames;
    double fps = 0.0;
    bool resume = false;
    int band_rows = 0;
    facet::PluginGuards plugin_guards;
    std::chrono::milliseconds probe_time{0};  // of a new plugin (PluginRegistry)
};

constexpr int kTagReport = 1;  // worker to rank 0: a result, and a request for work
constexpr int kTagWork = 2;    // rank 0 to worker: the next item, or kNoMore
constexpr long kNoMore = -1;

// ---- What a rank was doing when it crashed ------------------------------------

char g_crash_note[256] = "";

void on_fault(int signal) {
    if (g_crash_note[0]) {
        const ssize_t ignored = write(2, g_crash_note, std::strlen(g_crash_note));
        (void)ignored;
    }
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

void note_work(int rank, const char* what, long item) {
    const bool frame = std::strcmp(what, "frame") == 0;
    std::snprintf(g_crash_note, sizeof g_crash_note,
                  "facet-render-mpi: rank %d failed on %s %ld (it crashed); %s\n", rank, what,
                  item, frame ? "the frames already written are kept" : "no image is written");
}

// ---- Messages --------------------------------------------------------------------

// ready: the first request; stopped: SIGINT or SIGTERM cut the item short.
enum class Kind : int32_t { ready, done, failed, stopped };

// A report: its kind, the item, how long it took, and its payload (a band's
// segments, or why it failed).
struct Report {
    Kind kind = Kind::ready;
    long item = kNoMore;
    double seconds = 0.0;
    std::string payload;
};

template <class T>
void put(std::string& out, const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
T get(std::string_view& in) {
    T v;
    if (in.size() < sizeof v) throw std::length_error("a truncated message");
    std::memcpy(&v, in.data(), sizeof v);
    in.remove_prefix(sizeof v);
    return v;
}

std::string to_bytes(const Report& r) {
    std::string out;
    put(out, int32_t(r.kind));
    put(out, int64_t(r.item));
    put(out, r.seconds);
    out += r.payload;
    return out;
}

Report from_bytes(std::string_view in) {
    Report r;
    r.kind = Kind(get<int32_t>(in));
    r.item = long(get<int64_t>(in));
    r.seconds = get<double>(in);
    r.payload.assign(in);
    return r;
}

std::string segments_to_bytes(const std::vector<facet::PngSegment>& segments) {
    std::string out;
    put(out, uint32_t(segments.size()));
    for (const facet::PngSegment& s : segments) {
        put(out, int32_t(s.rows));
        put(out, s.adler);
        put(out, s.raw_bytes);
        put(out, uint64_t(s.deflated.size()));
        out += s.deflated;
    }
    return out;
}

std::vector<facet::PngSegment> segments_from_bytes(std::string_view in) {
    std::vector<facet::PngSegment> out(get<uint32_t>(in));
    for (facet::PngSegment& s : out) {
        s.rows = get<int32_t>(in);
        s.adler = get<uint32_t>(in);
        s.raw_bytes = get<uint64_t>(in);
        const auto size = get<uint64_t>(in);
        if (size > in.size()) throw std::length_error("a truncated message");
        s.deflated.assign(in.substr(0, size));
        in.remove_prefix(size);
    }
    return out;
}

// ---- The work ----------------------------------------------------------------------

// What every rank renders: a frame of a sequence, or a band of one image.
struct Job {
    Options opt;
    facet::Scene scene;
    bool frames = false;
    facet::FrameRange range;   // frames
    double fps = 30.0;
    int rows = 0, bands = 0;   // bands

    const char* what() const { return frames ? "frame" : "band"; }
    long first() const { return frames ? range.first : 0; }
    long end() const { return frames ? range.last + 1 : bands; }
    std::string describe(long item) const {
        if (frames) return "frame " + std::to_string(item);
        const int first_row = int(item) * rows;
        return "band " + std::to_string(item) + " (rows " + std::to_string(first_row) + ".." +
               std::to_string(std::min(scene.settings.height, first_row + rows) - 1) + ")";
    }
};

// Renders one item; the report says how it went.
Report render_item(const Job& job, facet::Scene& scene, facet::Renderer& renderer, long item,
                   int rank, facet::Framebuffer& target, std::vector<uint8_t>& rgba) {
    note_work(rank, job.what(), item);
    const auto start = std::chrono::steady_clock::now();
    Report r;
    r.item = item;
    try {
        if (job.frames) {
            facet::render_frame_to_png(renderer, scene, item, job.fps,
                                       facet::frame_path(job.opt.output, item), target, rgba);
        } else {
            r.payload = segments_to_bytes(
                facet::render_band(renderer, scene, int(item), job.rows, target, rgba));
        }
        r.kind = Kind::done;
    } catch (const facet::Error& e) {
        r.kind = e.code() == facet::ErrorCode::interrupted ? Kind::stopped : Kind::failed;
        r.payload = e.what();
    } catch (const std::exception& e) {
        r.kind = Kind::failed;
        r.payload = e.what();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    g_crash_note[0] = '\0';
    return r;
}

// Rank 0's book of the work: what is handed out, what came back, and the
// band image's writer. Its methods run on rank 0's MPI thread and its
// render thread, under one lock.
class Coordinator {
public:
    Coordinator(const Job& job, int ranks)
        : job_(job), next_(job.first()), progress_(job.what(), job.end() - job.first()),
          per_rank_(size_t(ranks)) {
        if (!job.frames) {
            facet::remove_abandoned_partials(job.opt.output);  // what a killed run left
            png_.emplace(job.opt.output, job.scene.settings.width, job.scene.settings.height);
            window_ = 2 * ranks;
        }
    }

    // The next item for `rank`, kNoMore when none is left, or nullopt when
    // it must wait (a band image holds only so many bands ahead of the one
    // it writes next).
    std::optional<long> next_item(int rank) {
        const std::lock_guard<std::mutex> hold(mutex_);
        if (stopped_) return kNoMore;
        if (job_.frames && job_.opt.resume)
            while (next_ < job_.end() &&
                   std::filesystem::exists(facet::frame_path(job_.opt.output, next_))) {
                progress_.skipped();
                ++next_;
            }
        if (next_ >= job_.end()) return kNoMore;
        if (!job_.frames && next_ >= next_band_ + window_) return std::nullopt;
        spdlog::debug("rank {}: {}", rank, job_.describe(next_));
        return next_++;
    }

    // A rank's report. Never throws: what goes wrong (the PNG cannot be
    // written) is a failure, which stops the work.
    void take(int rank, const Report& r) {
        const std::lock_guard<std::mutex> hold(mutex_);
        if (r.kind == Kind::ready) return;
        if (r.kind == Kind::stopped) {
            stopped_ = interrupted_ = true;
            return;
        }
        if (r.kind == Kind::failed) {
            fail(rank, job_.describe(r.item), r.payload);
            if (!job_.frames) stopped_ = true;  // the image cannot be whole
            return;
        }
        PerRank& mine = per_rank_[size_t(rank)];
        ++mine.items;
        mine.seconds += r.seconds;
        progress_.done(job_.describe(r.item) + " on rank " + std::to_string(rank), r.seconds);
        if (job_.frames || stopped_) return;
        try {
            bands_[r.item] = segments_from_bytes(r.payload);
            // Write every band that is next in line.
            for (auto it = bands_.begin(); it != bands_.end() && it->first == next_band_;
                 it = bands_.erase(it), ++next_band_)
                for (const facet::PngSegment& s : it->second) png_->add(s);
        } catch (const std::exception& e) {
            fail(0, "writing " + job_.describe(r.item), e.what());
            stopped_ = true;
        }
    }

    // Hands out no more work: an interrupt, or rank 0's own thread failed.
    void stop(bool interrupted) {
        const std::lock_guard<std::mutex> hold(mutex_);
        stopped_ = true;
        interrupted_ |= interrupted;
    }
    void failed(int rank, const std::string& what, const std::string& why) {
        const std::lock_guard<std::mutex> hold(mutex_);
        fail(rank, what, why);
        stopped_ = true;
    }

    // After every rank has stopped: the image finished, and a summary.
    // Returns the exit status.
    int finish(double seconds) {
        const std::lock_guard<std::mutex> hold(mutex_);
        for (size_t r = 0; r < per_rank_.size(); ++r)
            spdlog::info("rank {}: {} {}s in {}", r, per_rank_[r].items, job_.what(),
                         facet::format_duration(per_rank_[r].seconds));
        spdlog::info("{} {}s in {} on {} ranks", progress_.finished(), job_.what(),
                     facet::format_duration(seconds), per_rank_.size());
        if (interrupted_) {
            spdlog::warn("stopped; {}", job_.frames ? "the frames written are kept (--resume "
                                                      "goes on from them)"
                                                    : "no image was written");
            return 130;
        }
        if (!failures_.empty()) {
            std::string list;
            for (const std::string& f : failures_) list += (list.empty() ? "" : "; ") + f;
            spdlog::error("{} failed: {}{}", failures_.size() == 1 ? "one item" : std::to_string(failures_.size()) + " items", list,
                          job_.frames ? "; the frames written are kept"
                                      : "; no image was written");
            return 1;
        }
        if (png_) {
            png_->finish();
            spdlog::info("wrote {}", job_.opt.output);
        }
        return 0;
    }

private:
    void fail(int rank, const std::string& what, const std::string& why) {
        spdlog::error("rank {} failed on {}: {}", rank, what, why);
        failures_.push_back("rank " + std::to_string(rank) + ", " + what);
    }

    struct PerRank {
        long items = 0;
        double seconds = 0.0;
    };
    const Job& job_;
    std::mutex mutex_;
    long next_;
    bool stopped_ = false;
    bool interrupted_ = false;
    facet::Progress progress_;
    std::vector<PerRank> per_rank_;
    std::vector<std::string> failures_;
    std::optional<facet::PngWriter> png_;
    std::map<long, std::vector<facet::PngSegment>> bands_;  // arrived ahead of their turn
    long next_band_ = 0;
    long window_ = 0;
};

void send_item(int rank, long item) {
    const int64_t v = item;
    MPI_Send(&v, 1, MPI_INT64_T, rank, kTagWork, MPI_COMM_WORLD);
}

// Rank 0: hands out work to the other ranks over MPI, and to its own render
// thread, until all is done.
int coordinate(Job& job, facet::Renderer& renderer, int ranks,
               const facet::Interrupts& interrupts) {
    const auto start = std::chrono::steady_clock::now();
    Coordinator book(job, ranks);
    std::mutex lock;
    std::condition_variable wake;
    std::thread local([&] {
        try {
            facet::Framebuffer target;
            std::vector<uint8_t> rgba;
            for (;;) {
                std::optional<long> item;
                {
                    std::unique_lock<std::mutex> hold(lock);
                    wake.wait_for(hold, std::chrono::milliseconds(50),
                                  [&] { return (item = book.next_item(0)).has_value(); });
                }
                if (!item) continue;
                if (*item == kNoMore) break;
                book.take(0, render_item(job, job.scene, renderer, *item, 0, target, rgba));
            }
        } catch (const std::exception& e) {
            book.failed(0, "its render thread", e.what());
        }
    });
    int active = ranks - 1;
    std::deque<int> waiting;  // ranks that asked for work and wait for it
    std::string buffer;
    try {
    while (active > 0) {
        if (interrupts.stopped()) book.stop(true);
        int pending = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, kTagReport, MPI_COMM_WORLD, &pending, &status);
        if (pending) {
            int size = 0;
            MPI_Get_count(&status, MPI_BYTE, &size);
            buffer.resize(size_t(size));
            MPI_Recv(buffer.data(), size, MPI_BYTE, status.MPI_SOURCE, kTagReport, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            book.take(status.MPI_SOURCE, from_bytes(buffer));
            waiting.push_back(status.MPI_SOURCE);
            wake.notify_all();
        }
        bool gave = false;
        for (size_t i = 0; i < waiting.size();) {
            const std::optional<long> item = book.next_item(waiting[i]);
            if (!item) {
                ++i;
                continue;
            }
            send_item(waiting[i], *item);
            if (*item == kNoMore) --active;
            waiting.erase(waiting.begin() + long(i));
            gave = true;
        }
        if (!pending && !gave) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    } catch (const std::exception& e) {
        // The output cannot be written (a full disk): every rank stops.
        spdlog::error("rank 0: {}", e.what());
        std::fflush(nullptr);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    local.join();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int status = book.finish(seconds);
    // Stopped by a signal that reached another rank and not this one: 130.
    return status == 130 && interrupts.stopped() ? interrupts.exit_code() : status;
}

// Any other rank: asks rank 0 for work, renders it, reports, asks again.
void work(Job& job, facet::Renderer& renderer, int rank) {
    facet::Framebuffer target;
    std::vector<uint8_t> rgba;
    Report report;  // ready
    for (;;) {
        const std::string bytes = to_bytes(report);
        MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, 0, kTagReport, MPI_COMM_WORLD);
        int64_t item = kNoMore;
        MPI_Recv(&item, 1, MPI_INT64_T, 0, kTagWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (item == kNoMore) return;
        report = render_item(job, job.scene, renderer, long(item), rank, target, rgba);
    }
}

// This machine's ranks, to share its hardware threads among them.
int ranks_on_this_machine() {
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
    int size = 1;
    MPI_Comm_size(local, &size);
    MPI_Comm_free(&local);
    return size;
}

// The cores this process may run on (its affinity, which mpirun sets).
int cores_allowed() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return int(std::thread::hardware_concurrency());
    return std::max(1, CPU_COUNT(&set));
}

// Loads the scene and applies the command line; every rank does the same,
// and so fails the same way on bad input.
void prepare(Job& job, facet::PluginRegistry& registry) {
    const Options& opt = job.opt;
    for (const std::string& dir : opt.plugin_paths) registry.add_scene_path(dir);
    job.scene = facet::load_scene(opt.scene, registry);
    facet::RenderSettings& s = job.scene.settings;
    if (!opt.size.empty()) {
        const std::optional<glm::ivec2> size = facet::parse_size(opt.size);
        if (!size)
            throw facet::Error(facet::ErrorCode::config_invalid,
                               "expected WxH with each side 1.." +
                                   std::to_string(facet::Framebuffer::kMaxSize),
                               "--size " + opt.size);
        s.width = size->x;
        s.height = size->y;
    }
    if (!opt.camera.empty()) {
        const auto camera = facet::parse_camera(opt.camera, job.scene.camera);
        if (!camera)
            throw facet::Error(facet::ErrorCode::config_invalid,
                               "expected X,Y,Z,TX,TY,TZ[,FOV]", "--camera " + opt.camera);
        job.scene.set_camera(*camera);
    }
    if (opt.msaa) s.msaa = opt.msaa;
    if (opt.wireframe) s.wireframe = true;
    job.frames = !opt.frames.empty();
    facet::RenderSettings needed = s;
    if (job.frames) {
        std::tie(job.range, job.fps) =
            facet::frames_to_render(opt.frames, opt.fps, job.scene.timeline);
    } else {
        if (opt.time) job.scene.pose(*opt.time);
        job.rows = facet::band_rows(opt.band_rows > 0 ? opt.band_rows : facet::kDefaultBandRows);
        job.bands = facet::band_count(s.height, job.rows);
        needed.height = std::min(s.height, job.rows);
        facet::check_band(s.width, needed.height);
    }
    facet::require_frame_within_budget(needed);
}

int run(Job& job, const facet::Interrupts& interrupts, int rank, int ranks) {
    if (!facet::apply_max_memory(job.opt.max_memory, job.opt.threads)) return 2;
    facet::PluginRegistry registry;
    registry.probe_first_loads(job.opt.probe_time);
    // Every rank reads the scene; rank 0 alone says what it thinks of it.
    if (rank != 0) spdlog::set_level(spdlog::level::err);
    std::string problem;
    try {
        prepare(job, registry);
    } catch (const facet::Error& e) {
        problem = e.what();
    }
    // A bad scene fails on every rank alike: stop together, rank 0 says why.
    int bad = problem.empty() ? 0 : 1, any_bad = 0;
    MPI_Allreduce(&bad, &any_bad, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (any_bad) {
        // Rank 0 says why; another rank only when its problem is its own.
        int bad0 = rank == 0 ? bad : 0;
        MPI_Bcast(&bad0, 1, MPI_INT, 0, MPI_COMM_WORLD);
        if (!problem.empty() && (rank == 0 || !bad0)) spdlog::error("rank {}: {}", rank, problem);
        return 1;
    }
    // Collective: every rank counts its machine's ranks.
    const int local_ranks = ranks_on_this_machine();
    // mpirun binds a rank to a core by default (to one core per rank for two
    // ranks or fewer): more threads than the cores a rank may run on only
    // take turns.
    const int cores = cores_allowed();
    const int threads =
        job.opt.threads > 0                ? job.opt.threads
        : std::getenv("FACET_NUM_THREADS") ? facet::default_threads()
        : std::clamp(int(std::thread::hardware_concurrency()) / local_ranks, 1, cores);
    if (threads > cores)
        spdlog::warn("rank {}: {} threads on the {} core{} it is bound to; mpirun --bind-to none "
                     "lets them spread",
                     rank, threads, cores, cores == 1 ? "" : "s");
    facet::Renderer renderer(threads);
    renderer.pipeline().stop_when(&interrupts.stop());
    if (rank == 0) {
        spdlog::info("{} ranks, {} threads each on rank 0 ({} path on {})", ranks, threads,
                     facet::isa_name(renderer.isa()), facet::cpu_name());
        if (job.frames)
            spdlog::info("frames {}..{} at {} fps to {}", job.range.first, job.range.last, job.fps,
                         job.opt.output);
        else
            spdlog::info("{}x{} in {} bands of {} rows to {}", job.scene.settings.width,
                         job.scene.settings.height, job.bands, job.rows, job.opt.output);
        return coordinate(job, renderer, ranks, interrupts);
    }
    work(job, renderer, rank);
    return interrupts.exit_code();  // 0, or 130 or 143 if a signal cut its item short
}

}  // namespace

int main(int argc, char** argv) {
    // Before MPI starts its threads, which would otherwise take SIGTERM
    // (mpirun's, when its job is stopped) with the default action: killed
    // at once, leaving its partial file.
    const facet::Interrupts interrupts("facet-render-mpi");
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    for (int s : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) std::signal(s, on_fault);
    facet::report_plugin_faults();  // runs first, then on_fault

    Job job;
    Options& opt = job.opt;
    CLI::App app{"Renders a facet sequence, or one image in bands, across MPI ranks.",
                 "facet-render-mpi"};
    app.add_option("scene", opt.scene, "scene file (YAML), or a model file")->required();
    app.add_option("-o,--output", opt.output,
                   "output: a pattern with %d for the frames (out_%04d.png), or the PNG")
        ->required();
    app.add_option("--size", opt.size, "image size WxH, overriding the scene's");
    app.add_option("--camera", opt.camera, "camera X,Y,Z,TX,TY,TZ[,FOV]");
    app.add_option("--msaa", opt.msaa, "samples per pixel")->check(CLI::IsMember({1, 2, 4, 8}));
    app.add_flag("--wireframe", opt.wireframe, "draw triangle edges over the shading");
    app.add_option("--threads", opt.threads,
                   "render threads per rank; 0: this machine's hardware threads over its ranks")
        ->check(CLI::Range(0, 256));
    app.add_option("--max-memory", opt.max_memory, "memory budget per rank, e.g. 8G");
    app.add_option("--plugin-path", opt.plugin_paths, "extra folder to search for shaders");
    CLI::Option* time =
        app.add_option("--time", opt.time, "seconds: pose the scene at this time (one image)")
            ->check(CLI::Range(0.0, 1e9));
    CLI::Option* frames =
        app.add_option("--frames", opt.frames, "frames A..B, N or all of the scene's animation")
            ->excludes(time);
    app.add_option("--fps", opt.fps, "frames a second (default: the scene's, or 30)")
        ->check(CLI::Range(0.001, 1000.0))
        ->needs(frames);
    app.add_flag("--resume", opt.resume, "skip frames whose files exist")->needs(frames);
    app.add_option("--band-rows", opt.band_rows,
                   "rows per band of one image (rounded up to a multiple of 64; default 256)")
        ->check(CLI::Range(1, facet::Framebuffer::kMaxSize))
        ->excludes(frames);
    facet::add_plugin_guard_options(app, opt.plugin_guards);
    facet::Verbosity verbosity;
    facet::add_common_options(app, verbosity);
    int status = 0;
    bool abort = false;  // a rank stops alone: the others would wait on it
    if (const std::optional<int> parsed = facet::parse_command_line(app, argc, argv)) {
        status = *parsed;
    } else {
        facet::start_logging(verbosity);
        // A stalled rank ends, and mpirun ends the job: the others would wait on it.
        opt.probe_time = facet::start_plugin_guards(
            opt.plugin_guards, facet::PluginWatchdog::OnStall::end_process);
        if (const std::string bad = facet::check_finite_times(opt.time, opt.fps); !bad.empty()) {
            if (rank == 0) spdlog::error("{}", bad);
            status = 2;
        } else if (job.frames = !opt.frames.empty(); job.frames) {
            if (const std::string error = facet::check_frame_pattern(opt.output); !error.empty()) {
                if (rank == 0) spdlog::error("-o: {}", error);
                status = 2;
            }
        }
        if (status == 0) {
            try {
                status = run(job, interrupts, rank, ranks);
            } catch (const facet::Error& e) {
                spdlog::error("rank {}: {}", rank, e.what());
                status = 1;
                abort = true;
            } catch (const std::bad_alloc&) {
                spdlog::error("rank {}: {}", rank, facet::out_of_memory_text());
                status = 1;
                abort = true;
            } catch (const std::exception& e) {
                spdlog::error("rank {}: unexpected error: {}", rank, e.what());
                status = 1;
                abort = true;
            }
        }
    }
    if (abort && ranks > 1) {
        std::fflush(nullptr);
        MPI_Abort(MPI_COMM_WORLD, status);
    }
    MPI_Finalize();
    return status;
}
