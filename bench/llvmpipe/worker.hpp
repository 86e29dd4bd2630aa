// facet-bench --llvmpipe: each llvmpipe measurement in a child process.
//
// llvmpipe reads LP_NUM_THREADS once per process, when OSMesa first makes
// its screen, so one process cannot measure it at 1 and at 2 threads. The
// parent (measure_llvmpipe) therefore runs this same program again as
//
//     facet-bench --llvmpipe-worker RESULT --scene S --size WxH --shader NAME
//                 --runs N --target T [--llvmpipe-coverage MASK]
//
// with LP_NUM_THREADS and GALLIUM_DRIVER=llvmpipe in its environment, and
// waits for it (at most LlvmpipeJob::timeout; then it kills it). The child
// builds the same scene as the parent (facet-bench's make_scene), times it
// with time_frames(), writes the result with write_result() and exits; the
// parent reads the files. The parent is idle while the child runs, so the
// two never compete for the cores.
//
// Files, in a folder of their own made with mkdtemp and removed with
// everything in it when measure_llvmpipe returns or throws: RESULT is text,
// "median_ms min_ms" on the first line and the GL renderer and version on
// the second; MASK is LlvmpipeRenderer::coverage(), one byte per pixel; the
// child's stdout and stderr go to a third file, quoted in the parent's
// error when the child fails (so the child logs its error as the bare
// message) and passed on to stderr when it succeeds.
#pragma once

#include "llvmpipe.hpp"

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace facet::bench {

// One configuration for a child to measure.
struct LlvmpipeJob {
    std::string scene, size, shader;  // as facet-bench's --scene, --size, --shader
    int runs = 5;                     // timed frames, after one warm-up frame
    int threads = 0;                  // LP_NUM_THREADS; 0: llvmpipe draws on the calling thread
    LlvmpipeTarget target = LlvmpipeTarget::rgba32f;
    bool coverage = false;            // also return the coverage of an unlit frame
    std::chrono::seconds timeout{600};  // then the child is killed and the job fails
};

struct LlvmpipeResult {
    double median_ms = 0.0, min_ms = 0.0;
    std::string renderer;            // GL_RENDERER and GL_VERSION
    std::vector<uint8_t> coverage;   // when the job asked for it
};

// The LP_NUM_THREADS that matches `facet_threads` threads of facet (counting
// the caller): 0 for one, so that llvmpipe, like facet, does everything on
// the calling thread; otherwise the same number of rasterizer threads (the
// caller then only runs llvmpipe's vertex stage and setup, and waits).
int llvmpipe_threads(int facet_threads);

// Parent: runs the job in a child process and returns what it measured.
// Throws std::runtime_error when the child cannot start, exits non-zero, is
// killed by a signal or times out, naming which and quoting its stderr.
LlvmpipeResult measure_llvmpipe(const LlvmpipeJob& job);

// Child: one warm-up frame, then `runs` frames; the median and the fastest.
LlvmpipeResult time_frames(LlvmpipeRenderer& renderer, const Scene& scene, int runs);

// Child: writes `result` to the files the parent named (mask_path may be
// empty). Throws std::runtime_error when it cannot.
void write_result(const LlvmpipeResult& result, const std::string& result_path,
                  const std::string& mask_path);

// "rgba32f" or "srgb8"; throws std::runtime_error for anything else.
LlvmpipeTarget parse_target(const std::string& name);
std::string target_name(LlvmpipeTarget target);

}  // namespace facet::bench
