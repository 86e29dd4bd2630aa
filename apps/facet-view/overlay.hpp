// What facet-view's overlay says, as text, and drawing it over a frame with
// the bitmap font of apps/support (facet/text.hpp). Composing the text is separate
// from drawing it so the tests can read it.
#pragma once

#include <facet/isa.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/text.hpp>

#include <chrono>
#include <string>
#include <vector>

namespace facet::view {

// A line shown for a few seconds: a hot-reload event, a screenshot, an
// error.
struct Message {
    std::string text;
    bool error = false;
    std::chrono::steady_clock::time_point until;
};

// Everything the statistics panel reports about the last frame.
struct OverlayInfo {
    FrameStats stats;
    double frame_ms = 0.0;       // render and conversion to sRGB8
    int threads = 1;
    Isa isa = Isa::portable;     // the renderer's instruction-set path
    RenderSettings settings;     // as rendered (size, MSAA, wireframe, passes)
    std::vector<std::string> post_passes;  // the scene's post chain, by name, in order
    uint64_t idle_wakeups = 0;   // times the viewer woke and found nothing to render
    std::string selected;        // "name: material"
    bool flying = false;
    float fly_speed = 0.0f;
    std::string animation;       // the time and frame, if the scene moves
};

// The statistics panel, one line per '\n'.
std::string stats_text(const OverlayInfo& info);

// The help panel: every key and mouse binding.
std::string help_text();

// Draws a panel of `text` with its top-left corner at (x, y): a translucent
// backdrop, then the text. Returns the panel's height in pixels.
int draw_panel(ImageView image, int x, int y, const std::string& text, Rgba8 color, int scale);

// Messages still showing at `now`, newest last, under the panel at y.
void draw_messages(ImageView image, int x, int y, const std::vector<Message>& messages,
                   int scale);

}  // namespace facet::view
