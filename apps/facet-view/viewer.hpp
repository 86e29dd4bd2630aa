// facet-view: an SDL2 window onto facet's renderer.
//
// The viewer keeps one Scene and renders it with the core into a
// Framebuffer, then shows it through an SDL streaming texture with the
// overlay drawn over it by the core's bitmap font. It renders only when
// something changed (camera, window size, a key that changes what is drawn,
// a hot-reloaded plugin or config); otherwise it sleeps in SDL_WaitEvent,
// woken by input or by the file watcher, and uses no CPU.
//
// Bad input never stops it: a scene that fails to load at start falls back
// to the default scene, a dropped or reloaded file that fails leaves the
// last good state rendering, and every error shows in the overlay and the
// log.
//
// Only this folder touches SDL; the core stays free of any window system.
#pragma once

#include "camera_controller.hpp"
#include "editor.hpp"
#include "outline.hpp"
#include "overlay.hpp"
#include "playback.hpp"

#include <facet/error.hpp>
#include <facet/framebuffer.hpp>
#include <facet/hot_reload.hpp>
#include <facet/plugin.hpp>
#include <facet/rebuild.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>
#include <facet/texture.hpp>

#include <SDL.h>

#include <array>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace facet::view {

struct Options {
    std::string scene;                     // empty: the default scene
    std::optional<glm::ivec2> size;        // window size in points; default: the scene's
    std::string camera;                    // X,Y,Z,TX,TY,TZ[,FOV] (command_line.hpp)
    std::vector<std::string> plugin_paths;
    int threads = 0;                       // 0: one per hardware thread
    int msaa = 0;                          // 0: the scene's
    bool rebuild = false;                  // rebuild built-in shaders when sources change
    std::filesystem::path materials;       // default: configs/materials of the source tree
    std::filesystem::path screenshots = "."; // where P writes its PNGs
    std::chrono::milliseconds message_time{5000};  // how long overlay messages show
    bool editor = true;                    // the editor panel shows at start (E toggles it)
    std::string select;                    // the object selected at start, by name
    // How long a new plugin's probe frame may take (PluginRegistry::
    // probe_first_loads); 0: no probe.
    std::chrono::milliseconds probe_time{0};
    // While true, frames stop (Pipeline::stop_when) and pump() returns
    // false: SIGINT and SIGTERM (facet/interrupts.hpp). Null: never.
    const std::atomic<bool>* stop = nullptr;
};

class Viewer {
public:
    // Opens the window and loads the scene. Throws Error if SDL cannot open
    // a window, or if neither the scene nor the default scene loads.
    explicit Viewer(Options options);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // Until the window closes or Esc: sleeps until an event, handles it,
    // renders if anything changed.
    void run();
    // Handles the queued events without waiting, then frame(). False once
    // the viewer was asked to quit.
    bool pump();
    // Applies hot reload and fly motion, then renders and presents if
    // anything changed. Returns true if it rendered.
    bool frame();
    // Handles one event; false if it asks to quit.
    bool handle(const SDL_Event& event);
    // Marks the scene as changed, so the next frame() renders it.
    void invalidate() { scene_dirty_ = true; }
    // How long run() may sleep before the next frame() has work: -1 until an
    // event arrives (idle), 0 now, else milliseconds (a file settling, a
    // build running, a message due to fade, a fly key held).
    int wait_ms() const;
    // Writes the last rendered image (no overlay) as PNG; throws Error.
    void save_screenshot(const std::filesystem::path& path) const;
    // From now on, keeps a copy of each presented window (overlay and editor
    // panel included) for save_window(); off by default (it costs a read).
    void keep_window(bool keep) { keep_window_ = keep; }
    // Writes the last presented window as PNG; throws Error if none is kept.
    void save_window(const std::filesystem::path& path) const;
    // "facet-YYYYMMDD-HHMMSS.png" in the screenshots folder, not yet taken.
    std::filesystem::path screenshot_name() const;

    const CameraController& controller() const { return controller_; }
    const Scene& scene() const { return scene_; }
    const RenderSettings& settings() const { return settings_; }
    const Framebuffer& framebuffer() const { return framebuffer_; }
    // The last image presented: the frame in sRGB8 with the overlay on it.
    const std::vector<uint8_t>& shown() const { return shown_; }
    const std::vector<Message>& messages() const { return messages_; }
    const OverlayInfo& overlay() const { return info_; }
    int selected() const { return selected_; }
    uint64_t frames_rendered() const { return frames_; }
    // Why the last frame failed (its Error); none if it rendered.
    const std::optional<Error>& frame_error() const { return frame_error_; }
    uint64_t frames_presented() const { return presents_; }
    bool overlay_visible() const { return show_overlay_; }
    Editor& editor() { return *editor_; }
    // Animation: the time the scene is posed at, playing or not (Space
    // toggles it, the arrow keys step a frame, Home goes to the start, the
    // editor's slider scrubs). While the scene's camera is animated, the
    // view follows it until the camera is moved by hand (R follows again).
    const Playback& playback() const { return playback_; }
    void set_playing(bool playing);
    void seek(double t);
    bool following_camera() const { return follow_camera_; }
    // Writes the editor's unsaved values into their files (Ctrl+S, Save).
    void save_edits();
    bool help_visible() const { return show_help_; }

private:
    bool handle_key(const SDL_KeyboardEvent& key);
    void handle_drag(const SDL_MouseMotionEvent& motion);
    void handle_window(const SDL_WindowEvent& window);
    void handle_drop(const char* file);
    void hold(SDL_Keycode key, bool down);
    glm::vec3 flight() const;  // the fly keys held, as view axes
    void apply_reload();
    void advance_flight();
    void advance_animation();
    void pose();  // the scene at the playback's time, the view following its camera
    void render();
    void present();
    void resize_texture();
    glm::ivec2 drawable_size() const;
    void cycle_material(int step);
    void take_screenshot();
    void select_next();
    void open_scene(const std::filesystem::path& path);
    void adopt_scene(Scene fresh);
    void show_title();
    void message(std::string text, bool error, bool log = true);  // log: also to spdlog
    void update_selected_label();
    void show_editor();
    bool may_quit();
    int outline_width() const;

    // SDL's video subsystem, held for the viewer's lifetime (declared first,
    // so it goes last).
    struct SdlVideo {
        SdlVideo();
        ~SdlVideo();
    };
    template <class T, void (*Destroy)(T*)>
    struct SdlDeleter {
        void operator()(T* p) const { Destroy(p); }
    };

    Options options_;
    SdlVideo video_;
    std::unique_ptr<SDL_Window, SdlDeleter<SDL_Window, SDL_DestroyWindow>> window_;
    std::unique_ptr<SDL_Renderer, SdlDeleter<SDL_Renderer, SDL_DestroyRenderer>> sdl_renderer_;
    std::unique_ptr<SDL_Texture, SdlDeleter<SDL_Texture, SDL_DestroyTexture>> texture_;
    std::unique_ptr<Editor> editor_;  // after the renderer it draws with, so it goes first
    glm::ivec2 texture_size_{0};

    PluginRegistry registry_;
    TextureCache textures_;
    Scene scene_;
    std::unique_ptr<HotReload> reload_;
    std::unique_ptr<ShaderRebuilder> rebuilder_;
    int building_ = 0;  // shader builds running (--rebuild)
    Renderer renderer_;
    Outline outline_;
    Framebuffer framebuffer_;
    std::vector<uint8_t> image_;    // the frame in sRGB8
    std::vector<uint8_t> shown_;    // the frame with the overlay
    bool keep_window_ = false;
    std::vector<uint8_t> window_image_;  // the last window presented (keep_window)
    glm::ivec2 window_size_{0};

    CameraController controller_;
    Playback playback_;
    bool follow_camera_ = false;  // the view is the scene's animated camera
    bool pose_due_ = false;       // the scene is not posed at the playback's time
    RenderSettings settings_;       // the scene's, with the viewer's toggles
    OverlayInfo info_;
    std::vector<Message> messages_;
    int selected_ = 0;
    bool show_overlay_ = true;
    bool show_help_ = false;
    bool scene_dirty_ = true;
    bool stalled_ = false;  // a shader stalled: no frames until the scene or a shader changes
    std::optional<Error> frame_error_;  // why the last frame failed; none if it rendered
    bool overlay_dirty_ = true;
    uint64_t frames_ = 0;
    uint64_t idle_wakeups_ = 0;
    std::chrono::steady_clock::time_point last_flight_;
    std::chrono::steady_clock::time_point fade_at_ =  // when the next message fades
        std::chrono::steady_clock::time_point::max();
    uint64_t presents_ = 0;
    std::chrono::steady_clock::time_point quit_armed_until_{};  // may_quit()
    // Fly keys held (W A S D Space LShift RShift), kept from events rather
    // than SDL's keyboard state so synthetic events drive them too.
    std::array<bool, 7> held_{};
};

}  // namespace facet::view
