// What a frame ran and what it skipped, in words: facet-render's log and
// facet-view's overlay both say it from the same FrameStats, so they give
// the same counts.
#pragma once

#include <facet/pipeline.hpp>
#include <facet/scene.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace facet {

// How counts are written: in full ("1234567"), or short enough for the
// overlay's panel ("1.2M", "45.7k").
enum class Counts { full, short_form };
std::string count_text(uint64_t n, Counts form);

// The passes a frame ran besides the main pass, each with its count and
// time: "2 shadow maps 37.69 ms", "1 pre-pass 1.20 ms", "1 AO 12.00 ms".
std::vector<std::string> passes_run(const FrameStats& s);

// Each screen pass of the post chain that ran, with its time: "bloom 2.10
// ms" (named from `passes`, the scene's chain, in order).
std::vector<std::string> post_passes_run(const FrameStats& s, const std::vector<PostPass>& passes);

// The work a frame left out, and why: an optional pass that did not run
// ("AO (not needed)": no visible material asks for it; "shadow maps (off)":
// the render settings turned it off), shadow maps kept from an earlier
// frame, casters outside a light's frustum, objects outside the view,
// fragments the early depth test rejected before their shader ran, and
// depth written with no shader call; "post chain (off)" when the scene
// has one (`post_chain`) and the settings turned it off.
std::vector<std::string> work_skipped(const FrameStats& s, const RenderSettings& settings,
                                      Counts form, bool post_chain = false);

// "a, b, c", or `none` when `parts` is empty.
std::string join(const std::vector<std::string>& parts, const std::string& none);

}  // namespace facet
