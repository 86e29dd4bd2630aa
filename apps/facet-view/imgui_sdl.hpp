// Dear ImGui on an SDL window drawn through SDL_Renderer: the input it reads
// and the triangles it draws.
//
// Input comes only from the SDL events handed to handle(), never from SDL's
// global mouse or keyboard state, so synthetic events (the viewer's tests,
// under Xvfb) drive the widgets exactly as a user's do. A press and release
// within one frame still count as a click: presses are held for a frame.
// Drawing is one SDL_RenderGeometryRaw call per ImGui draw command, with its
// clip rectangle, after the frame's picture.
#pragma once

#include <SDL.h>

#include <array>
#include <cstdint>

struct ImGuiContext;

namespace facet::view {

class ImGuiSdl {
public:
    // Creates an ImGui context of its own (no imgui.ini is written).
    ImGuiSdl(SDL_Window* window, SDL_Renderer* renderer);
    ~ImGuiSdl();
    ImGuiSdl(const ImGuiSdl&) = delete;
    ImGuiSdl& operator=(const ImGuiSdl&) = delete;

    // Feeds an event to ImGui. True when ImGui takes it: the pointer is over
    // a panel or a widget is active, or a text field has the keyboard.
    bool handle(const SDL_Event& event);
    // Starts a frame (ImGui::NewFrame) with the window's size and the time
    // since the last one.
    void new_frame();
    // Ends the frame and draws it over what the renderer holds.
    void render();
    // A button was pressed and released before the last frame: ImGui saw it
    // down, and needs one more frame to see it up (and so the click).
    bool needs_frame() const { return release_pending_; }

private:
    SDL_Window* window_;
    SDL_Renderer* renderer_;
    ImGuiContext* context_;
    SDL_Texture* font_ = nullptr;
    uint64_t last_ = 0;
    std::array<bool, 5> held_{};     // buttons down now
    std::array<bool, 5> pressed_{};  // pressed since the last frame
    bool release_pending_ = false;
};

}  // namespace facet::view
