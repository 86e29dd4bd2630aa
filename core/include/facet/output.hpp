// Output files that appear only when whole (facet/png.hpp's PngWriter
// writes every image through one; core/src/base/output_file.hpp says how):
// what a program that a signal ends, or one that resumes a killed run, does
// about the partial files.
#pragma once

#include <filesystem>
#include <vector>

namespace facet {

// Removes the partial files of every output not yet finished, using only
// async-signal-safe calls: for a program that a signal ends (facet's
// programs call it on SIGINT, SIGTERM and SIGHUP, and on a crash).
void remove_partial_outputs() noexcept;

// The partial files in `folder` whose writer no longer runs (a process that
// SIGKILL or a power cut ended), each with the image it was for.
struct AbandonedPartial {
    std::filesystem::path file, image;
};
std::vector<AbandonedPartial> abandoned_partials(const std::filesystem::path& folder);

// Removes the partial files of `image` that writers no longer running left
// (abandoned_partials), saying so in the log; returns how many. Programs
// call it before they write one image (a sequence's frames: --resume).
size_t remove_abandoned_partials(const std::filesystem::path& image);

}  // namespace facet
