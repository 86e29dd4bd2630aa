#include "overlay.hpp"

#include <facet/frame_report.hpp>

#include <spdlog/fmt/fmt.h>

#include <algorithm>

namespace facet::view {

namespace {

std::string count(uint64_t n) { return count_text(n, Counts::short_form); }

std::string skipped_line(const OverlayInfo& i) {
    std::vector<std::string> parts =
        work_skipped(i.stats, i.settings, Counts::short_form, !i.post_passes.empty());
    parts.push_back(count(i.idle_wakeups) + " idle wake-ups");
    return "skipped   " + join(parts, "");
}

}  // namespace

std::string stats_text(const OverlayInfo& i) {
    const FrameStats& s = i.stats;
    const RenderSettings& r = i.settings;
    const double fps = i.frame_ms > 0.0 ? 1000.0 / i.frame_ms : 0.0;
    std::string t;
    t += fmt::format("frame     {:.1f} ms ({:.0f} fps)  render {:.1f} ms  {} threads, {}\n",
                     i.frame_ms, fps, s.milliseconds, i.threads, isa_name(i.isa));
    t += fmt::format("passes    shadow {:.1f}  pre {:.1f}  main {:.1f}  AO {:.1f}  post {:.1f} ms\n",
                     s.ms_shadow, s.ms_prepass, s.ms_main, s.ms_ao, s.ms_post);
    if (s.post_passes) {  // each screen pass of the chain
        std::string line = "post     ";
        const size_t timed = std::min<size_t>({FrameStats::kPostTimings, i.post_passes.size(),
                                                size_t(s.post_passes)});
        for (size_t k = 0; k < timed; ++k)
            line += fmt::format(" {} {:.1f}", i.post_passes[k], s.ms_post_pass[k]);
        t += line + " ms\n";
    }
    t += fmt::format("triangles in {}  culled {} (back {}, frustum {}, tiny {})\n",
                     count(s.triangles_in),
                     count(s.triangles_culled_backface + s.triangles_culled_frustum +
                           s.triangles_culled_degenerate),
                     count(s.triangles_culled_backface), count(s.triangles_culled_frustum),
                     count(s.triangles_culled_degenerate));
    t += fmt::format("          clipped {}  rasterized {}  invalid {}\n",
                     count(s.triangles_clipped), count(s.triangles_rasterized),
                     count(s.triangles_invalid));
    t += skipped_line(i) + "\n";
    t += fmt::format("view      {}x{}  MSAA {}x  wireframe {}  shadows {}  AO {}  post {}\n",
                     r.width, r.height, r.msaa, r.wireframe ? "on" : "off",
                     r.shadows ? "on" : "off", r.ao ? "on" : "off", r.post ? "on" : "off");
    t += i.flying ? fmt::format("camera    fly, speed {:.2f}/s\n", i.fly_speed)
                  : std::string("camera    orbit\n");
    t += "selected  " + i.selected + "\n";
    if (!i.animation.empty()) t += "time      " + i.animation + "\n";
    t += "H: help";
    return t;
}

std::string help_text() {
    return "mouse     left drag: orbit (fly: look)   right/middle drag, shift+left: pan\n"
           "          wheel: zoom\n"
           "F         fly mode: W A S D move, Space up, Shift down, + - speed\n"
           "R         reset the camera to the scene's (and follow its animation)\n"
           "G         frame the selected object\n"
           "Space     play / pause the animation   Left, Right  a frame   Home  its start\n"
           "Tab       select the next object\n"
           "M, shift+M next / previous material from configs/materials\n"
           "L         wireframe          N  MSAA 1, 2, 4, 8\n"
           "1         shadow passes      2  AO passes      3  post chain\n"
           "P, F12    screenshot (PNG, named by time)\n"
           "O         overlay            H, F1  this help\n"
           "E         editor panel       Ctrl+S  save its edits into the files\n"
           "drop      a scene file (.yaml) on the window to open it\n"
           "Esc       quit";
}

int draw_panel(ImageView image, int x, int y, const std::string& text, Rgba8 color, int scale) {
    const int pad = 3 * scale;
    const int w = text_width(text, scale) + 2 * pad, h = text_height(text, scale) + 2 * pad;
    fill_rect(image, x, y, w, h, {0, 0, 0, 170});
    draw_text(image, x + pad, y + pad, text, color, scale);
    return h;
}

void draw_messages(ImageView image, int x, int y, const std::vector<Message>& messages,
                   int scale) {
    const auto now = std::chrono::steady_clock::now();
    const int max_chars = std::max(20, image.width / (kCellWidth * scale) - 4);
    for (const Message& m : messages) {
        if (m.until <= now) continue;
        std::string line = m.text.substr(0, m.text.find('\n'));  // the first line only
        if (int(line.size()) > max_chars) line = line.substr(0, size_t(max_chars - 3)) + "...";
        const Rgba8 color = m.error ? Rgba8{255, 110, 90, 255} : Rgba8{140, 230, 140, 255};
        y += draw_panel(image, x, y, line, color, scale) + scale;
    }
}

}  // namespace facet::view
