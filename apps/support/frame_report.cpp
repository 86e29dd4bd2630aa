#include "facet/frame_report.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

namespace facet {

std::string count_text(uint64_t n, Counts form) {
    if (form == Counts::short_form) {
        if (n >= 10'000'000) return fmt::format("{:.1f}M", double(n) / 1e6);
        if (n >= 100'000) return fmt::format("{:.1f}k", double(n) / 1e3);
    }
    return std::to_string(n);
}

std::vector<std::string> passes_run(const FrameStats& s) {
    std::vector<std::string> out;
    const auto add = [&](uint64_t n, const char* one, const char* many, double ms) {
        if (n) out.push_back(fmt::format("{} {} {:.2f} ms", n, n == 1 ? one : many, ms));
    };
    add(s.shadow_passes, "shadow map", "shadow maps", s.ms_shadow);
    add(s.prepasses + s.depth_prepasses, "pre-pass", "pre-passes", s.ms_prepass);
    add(s.ao_passes, "AO", "AO", s.ms_ao);
    return out;
}

std::vector<std::string> post_passes_run(const FrameStats& s, const std::vector<PostPass>& passes) {
    std::vector<std::string> out;
    const size_t timed = std::min<size_t>(FrameStats::kPostTimings, passes.size());
    for (size_t i = 0; i < std::min<size_t>(s.post_passes, timed); ++i)
        out.push_back(fmt::format("{} {:.2f} ms", passes[i].name, s.ms_post_pass[i]));
    if (s.post_passes > timed) out.push_back(fmt::format("{} more", s.post_passes - timed));
    return out;
}

std::vector<std::string> work_skipped(const FrameStats& s, const RenderSettings& settings,
                                      Counts form, bool post_chain) {
    std::vector<std::string> out;
    const auto pass = [&](const char* name, bool needed, bool enabled, uint64_t ran) {
        if (ran) return;
        if (!needed) out.push_back(std::string(name) + " (not needed)");
        else if (!enabled) out.push_back(std::string(name) + " (off)");
    };
    const auto counted = [&](uint64_t n, const char* one, const char* many) {
        if (n) out.push_back(count_text(n, form) + " " + (n == 1 ? one : many));
    };
    // Kept maps are no pass drawn, but the shadows still came.
    pass("shadow maps", s.shadows_needed, settings.shadows,
         s.shadow_passes + s.shadow_maps_reused);
    pass("AO", s.ao_needed, settings.ao, s.ao_passes);
    if (post_chain && !settings.post) out.push_back("post chain (off)");
    counted(s.shadow_maps_reused, "shadow map unchanged", "shadow maps unchanged");
    counted(s.shadow_casters_culled, "caster out of light", "casters out of light");
    counted(s.objects_culled, "object out of view", "objects out of view");
    counted(s.fragments_depth_rejected, "fragment hidden (early depth test)",
            "fragments hidden (early depth test)");
    counted(s.fragments_depth_only, "depth-only fragment (no shader)",
            "depth-only fragments (no shader)");
    counted(s.draws_redrawn, "draw on the pre-pass's triangles (no vertex stage or setup)",
            "draws on the pre-pass's triangles (no vertex stage or setup)");
    return out;
}

std::string join(const std::vector<std::string>& parts, const std::string& none) {
    if (parts.empty()) return none;
    std::string out;
    for (size_t k = 0; k < parts.size(); ++k) out += (k ? ", " : "") + parts[k];
    return out;
}

}  // namespace facet
