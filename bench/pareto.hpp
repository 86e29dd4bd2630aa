// facet-bench --pareto: run time against error for each quality knob.
//
// Every demo scene, one per shipped shader, each with the knobs that matter
// to it, swept over a grid of settings (the other settings stay as the
// scene file has them):
//   default (unlit, textured)  MSAA 1/2/4/8 x texture filter nearest/bilinear/
//           trilinear x sub-pixel bits 4/8
//   lit     the same x lighting per pixel or per vertex (per_pixel)
//   phong, toon  MSAA 1/2/4/8 x sub-pixel bits 2/4/6/8 (their other
//           parameters choose a look, not a cost)
//   shadow  shadow-map size 512..4096 x PCF kernel 1/3/5/7, at 4x MSAA
//   ao      AO samples 4..32 x AO radius 0.5/1/2 x the material's x AO at full
//           or half resolution, at 4x MSAA
//   environment  the environment's level-0 size 32..256 x its prefilter's GGX
//           samples 16/64/256 (image-based lighting; the reference is the
//           Monte Carlo one of tests/reference/environment.hpp, and the pass
//           time is the prefilter's, once at load)
// Each setting is rendered `runs` times, each frame drawing its shadow maps
// (median frame time, and the median time of the shadow or AO passes within
// it), and compared
// with the reference renderer's image of the scene as written (RMSE, max
// error and DSSIM on sRGB values, tests/reference/metrics.hpp). The CSV
// marks each scene's Pareto front (no other setting is both faster and
// more accurate by RMSE); bench/plot_pareto.py draws it.
#pragma once

#include <atomic>
#include <string>
#include <vector>

namespace facet::bench {

struct ParetoOptions {
    int width = 480, height = 270;
    int threads = 0;        // 0: default_threads() (FACET_NUM_THREADS, else every hardware thread)
    int runs = 7;
    int grid = 16;          // reference samples per pixel side
    int ao_grid = 8;        // ... for the AO scene, which traces ao_rays per sample
    int ao_rays = 32;
    int environment_rays = 512;  // the environment scene's Monte Carlo directions a pixel
    std::vector<std::string> scenes;  // the studies to run (names above); empty: all
    std::string csv = "pareto.csv";
    std::string plot = "pareto.png";
    // While true, the sweep stops at the next tile (Pipeline::stop_when),
    // keeping the CSV's rows so far. Null: never.
    const std::atomic<bool>* stop = nullptr;
};

// Returns the process exit code.
int run_pareto(const ParetoOptions& options);

}  // namespace facet::bench
