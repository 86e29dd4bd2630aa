// The viewer's window, loop and frames. Input handling is in input.cpp.
#include "viewer.hpp"

#include <facet/command_line.hpp>
#include <facet/error.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>

namespace facet::view {

namespace fs = std::filesystem;

namespace {

bool same_camera(const Camera& a, const Camera& b) {
    return a.position == b.position && a.target == b.target && a.up == b.up &&
           a.orthographic == b.orthographic && a.fov_y == b.fov_y &&
           a.ortho_height == b.ortho_height && a.near == b.near && a.far == b.far;
}

// An SDL event type of our own: "a watched file changed", pushed from the
// file watcher's thread (SDL_PushEvent is thread-safe) to end SDL_WaitEvent.
Uint32 wake_event() {
    static const Uint32 type = SDL_RegisterEvents(1);
    return type;
}

void wake() {
    SDL_Event e{};
    e.type = wake_event();
    SDL_PushEvent(&e);
}

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Puts a camera and settings into a scene for as long as it lives, then
// gives the scene back its own.
class ViewOf {
public:
    ViewOf(Scene& scene, const Camera& camera, const RenderSettings& settings)
        : scene_(scene), camera_(scene.camera), settings_(scene.settings) {
        scene.camera = camera;
        scene.settings = settings;
    }
    ~ViewOf() {
        scene_.camera = camera_;
        scene_.settings = settings_;
    }
    ViewOf(const ViewOf&) = delete;
    ViewOf& operator=(const ViewOf&) = delete;

private:
    Scene& scene_;
    const Camera camera_;
    const RenderSettings settings_;
};

Scene load_or_default(const Options& o, PluginRegistry& registry, std::string& error) {
    if (!o.scene.empty()) {
        try {
            return load_scene(o.scene, registry);
        } catch (const Error& e) {
            error = std::string(e.what()) + " (showing the default scene)";
        }
    }
    return load_scene(default_scene_path(), registry);
}

}  // namespace

Viewer::SdlVideo::SdlVideo() {
    // SIGINT and SIGTERM are the program's (Options::stop), not SDL's.
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
    const auto no_display = [](const std::string& why) {
        return Error(ErrorCode::display_failed,
                     why + "; facet-view needs a desktop session (or xvfb-run); facet-render "
                           "draws a scene to a PNG without one");
    };
    const char* forced = std::getenv("SDL_VIDEODRIVER");
    const bool any_display = std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY");
    if (!forced && !any_display) throw no_display("no display: DISPLAY and WAYLAND_DISPLAY are unset");
    // Without a reachable display SDL falls back to drivers that show nothing
    // (offscreen, dummy): the viewer would wait for input that never comes.
    // A display server that is busy may refuse a connection for a moment:
    // three tries, 0.2 s apart.
    std::string driver;
    for (int attempt = 0;; ++attempt) {
        if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) throw no_display(SDL_GetError());
        driver = SDL_GetCurrentVideoDriver() ? SDL_GetCurrentVideoDriver() : "";
        if (forced || (driver != "offscreen" && driver != "dummy" && driver != "evdev")) break;
        SDL_QuitSubSystem(SDL_INIT_VIDEO);
        if (attempt == 2) {
            const char* display = std::getenv("DISPLAY");
            throw no_display(std::string("cannot open the display ") +
                             (display ? "DISPLAY=" + std::string(display)
                                      : "WAYLAND_DISPLAY=" + std::string(std::getenv("WAYLAND_DISPLAY"))));
        }
        spdlog::debug("SDL chose the {} video driver: trying the display again", driver);
        SDL_Delay(200);
    }
    spdlog::debug("SDL video driver: {}", driver);
}

Viewer::SdlVideo::~SdlVideo() { SDL_QuitSubSystem(SDL_INIT_VIDEO); }

Viewer::Viewer(Options options)
    : options_(std::move(options)), renderer_(options_.threads), outline_(options_.threads) {
    renderer_.pipeline().stop_when(options_.stop);
    for (const std::string& dir : options_.plugin_paths) registry_.add_scene_path(dir);
    registry_.probe_first_loads(options_.probe_time);
    if (options_.materials.empty()) options_.materials = default_scene_path().parent_path() / "materials";
    std::string error;
    adopt_scene(load_or_default(options_, registry_, error));
    if (!error.empty()) message(error, true);
    if (!options_.select.empty()) {
        const auto& objects = scene_.objects;
        const auto it = std::find_if(objects.begin(), objects.end(),
                                     [&](const Object& o) { return o.name == options_.select; });
        if (it != objects.end()) selected_ = int(it - objects.begin());
        else message("--select: the scene has no object named '" + options_.select + "'", true);
        update_selected_label();
    }
    if (!options_.camera.empty()) {
        if (const auto camera = parse_camera(options_.camera, scene_.camera)) {
            controller_.reset(*camera);
            follow_camera_ = false;  // a camera put by hand stays
        }
        else message("--camera: expected X,Y,Z,TX,TY,TZ[,FOV]; using the scene's camera", true);
    }

    const glm::ivec2 size = options_.size.value_or(glm::ivec2(settings_.width, settings_.height));
    window_.reset(SDL_CreateWindow("facet-view", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                   size.x, size.y, SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI));
    if (window_) sdl_renderer_.reset(SDL_CreateRenderer(window_.get(), -1, 0));
    if (!sdl_renderer_) throw Error(ErrorCode::display_failed, SDL_GetError());
    editor_ = std::make_unique<Editor>(window_.get(), sdl_renderer_.get());
    editor_->set_visible(options_.editor);
    show_title();
    resize_texture();

    HotReload::Options reload;
    reload.watcher.on_change = wake;
    reload_ = std::make_unique<HotReload>(registry_, scene_, reload);
    if (options_.rebuild) {
        FileWatcher::Options watch;
        watch.on_change = wake;
        std::vector<ShaderProject> projects = rebuild_projects(registry_.search_path());
        if (projects.empty()) message(nothing_to_rebuild(), true);
        rebuilder_ = std::make_unique<ShaderRebuilder>(std::move(projects), watch);
    }
}

// Members go in reverse order: the watchers (which push SDL events) stop
// before the texture, renderer, window and video subsystem go.
Viewer::~Viewer() {
    if (editor_ && editor_->unsaved())
        spdlog::warn("{} values edited in the editor were not saved", editor_->unsaved());
}

// Takes `fresh` as the scene: the camera goes home to the file's camera,
// the viewer's toggles start from the file's settings.
void Viewer::adopt_scene(Scene fresh) {
    if (editor_) {
        if (const size_t dropped = editor_->forget_unsaved())
            message(std::to_string(dropped) + " unsaved values dropped with the old scene", true);
        editor_->scene_changed();
    }
    scene_ = std::move(fresh);
    settings_ = scene_.settings;
    if (options_.msaa) settings_.msaa = options_.msaa;
    controller_.reset(scene_.camera);
    playback_.reset(scene_.timeline);
    follow_camera_ = !scene_.camera_tracks.empty();
    pose_due_ = true;
    selected_ = 0;
    if (reload_) reload_->rewatch();
    show_title();
    update_selected_label();
    scene_dirty_ = true;
}

void Viewer::show_title() {
    if (!window_) return;  // not open yet: the constructor shows it
    const std::string title = "facet-view - " + scene_.source.filename().string();
    SDL_SetWindowTitle(window_.get(), title.c_str());
}

void Viewer::message(std::string text, bool error, bool log) {
    if (log && error) spdlog::error("{}", text);
    else if (log) spdlog::info("{}", text);
    const auto until = std::chrono::steady_clock::now() + options_.message_time;
    messages_.push_back({std::move(text), error, until});
    if (messages_.size() > 8) messages_.erase(messages_.begin());
    fade_at_ = std::min(fade_at_, until);
    overlay_dirty_ = true;
}

void Viewer::run() {
    while (true) {
        const int wait = wait_ms();
        SDL_Event e;
        const bool got = wait < 0 ? SDL_WaitEvent(&e) : SDL_WaitEventTimeout(&e, wait);
        if (got && !handle(e)) return;
        if (!pump()) return;
    }
}

bool Viewer::pump() {
    const auto stopped = [&] { return options_.stop && options_.stop->load(); };
    SDL_Event e;
    while (SDL_PollEvent(&e))
        if (!handle(e)) return false;
    if (stopped()) return false;
    if (!frame()) ++idle_wakeups_;
    return !stopped();
}

// Forever when idle; otherwise until the next thing that needs a frame.
int Viewer::wait_ms() const {
    if (scene_dirty_ || overlay_dirty_ || pose_due_ || playback_.playing()) return 0;
    if (controller_.flying() && flight() != glm::vec3(0.0f)) return 1;  // moving
    if (editor_->wants_frame()) return 0;  // the panel has a click to finish
    if (reload_->pending()) return 20;  // a changed file is settling
    if (building_ > 0) return 200;
    if (fade_at_ == std::chrono::steady_clock::time_point::max()) return -1;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        fade_at_ - std::chrono::steady_clock::now());
    return int(std::max<int64_t>(0, left.count() + 1));  // present when a message fades
}

void Viewer::apply_reload() {
    const Camera before = scene_.camera_rest;  // the file's: posing never changes it
    const bool updated = reload_->update();
    const std::vector<ReloadEvent> events = reload_->take_events();
    // Edits of a file that changed on disk (not by the editor's own save,
    // which hot reload passes over) no longer match what is loaded.
    for (const ReloadEvent& e : events) {
        if (e.kind != ReloadEvent::Kind::config_reloaded) continue;
        const bool scene_file = fs::weakly_canonical(e.subject) == fs::weakly_canonical(scene_.source);
        if (const size_t dropped = scene_file ? editor_->forget_unsaved()
                                              : editor_->forget_unsaved(e.subject))
            message(std::to_string(dropped) + " unsaved values dropped: " + e.subject +
                        " changed on disk",
                    true);
        if (scene_file) editor_->scene_changed();
    }
    if (updated) {
        scene_dirty_ = true;
        stalled_ = false;  // a new shader version, or a new scene
        // A reloaded scene file keeps the viewer's camera unless the file's
        // camera itself changed.
        if (!same_camera(scene_.camera_rest, before)) controller_.reset(scene_.camera);
        // A reloaded scene is posed at its start; the playback goes on.
        playback_.retime(scene_.timeline);
        if (scene_.camera_tracks.empty()) follow_camera_ = false;
        pose_due_ = true;
        const RenderSettings toggles = settings_;
        settings_ = scene_.settings;
        settings_.msaa = toggles.msaa;
        settings_.wireframe = toggles.wireframe;
        settings_.shadows = toggles.shadows;
        settings_.ao = toggles.ao;
        settings_.post = toggles.post;
        selected_ = std::min(selected_, std::max(0, int(scene_.objects.size()) - 1));
        update_selected_label();
    }
    for (const ReloadEvent& e : events) message(e.message, e.refused(), false);
    if (!rebuilder_) return;
    for (const ReloadEvent& e : rebuilder_->update()) {  // logged by the rebuilder
        if (e.kind == ReloadEvent::Kind::build_started) ++building_;
        if (e.kind == ReloadEvent::Kind::build_succeeded || e.kind == ReloadEvent::Kind::build_failed)
            building_ = std::max(0, building_ - 1);
        message(e.message, e.refused(), false);
    }
}

void Viewer::set_playing(bool playing) {
    playback_.set_playing(playing);
    overlay_dirty_ = true;
}

void Viewer::seek(double t) {
    playback_.seek(t);
    pose_due_ = true;
}

void Viewer::pose() {
    scene_.pose(playback_.time());
    if (follow_camera_) controller_.reset(scene_.camera);
    scene_dirty_ = true;
    pose_due_ = false;
}

void Viewer::advance_animation() {
    if (playback_.advance()) pose_due_ = true;
    if (pose_due_) pose();
}

bool Viewer::frame() {
    apply_reload();
    advance_flight();
    advance_animation();
    if (std::chrono::steady_clock::now() >= fade_at_) overlay_dirty_ = true;
    const bool render_now = scene_dirty_,
               present_now = scene_dirty_ || overlay_dirty_ || editor_->wants_frame();
    scene_dirty_ = overlay_dirty_ = false;  // present() may ask again
    if (render_now && !stalled_) render();
    if (present_now) present();
    return render_now;
}

void Viewer::render() {
    const auto start = std::chrono::steady_clock::now();
    const glm::ivec2 size = drawable_size();  // pixels, not points (HiDPI)
    settings_.width = size.x;
    settings_.height = size.y;
    {
        // Render with the viewer's camera and settings; the scene keeps
        // the file's, which hot reload compares against.
        const ViewOf view(scene_, controller_.camera(), settings_);
        try {
            info_.stats = renderer_.render(scene_, framebuffer_);
            frame_error_.reset();
        } catch (const Error& e) {  // the last good frame stays on screen
            frame_error_ = e;       // the target holds what the failed frame left
            stalled_ = e.code() == ErrorCode::plugin_stalled;
            message(std::string(e.what()) +
                        (stalled_ ? "; frames wait for a change to the scene or its shaders"
                                  : "; showing the last good frame"),
                    true);
            return;
        }
    }
    renderer_.pipeline().resolve_srgb8(framebuffer_, image_);  // a copy: the target is 8-bit sRGB
    if (editor_->visible() && !scene_.objects.empty()) {
        const auto outline_start = std::chrono::steady_clock::now();
        try {  // into the shown image only: the frame stays as rendered
            outline_.draw(scene_.objects[size_t(selected_)], controller_.camera(), settings_,
                          registry_, textures_, image_, outline_width());
        } catch (const Error& e) {
            message(std::string("selection outline: ") + e.what(), true);
        }
        spdlog::debug("frame {}: rendered in {:.2f} ms, selection outline {:.2f} ms", frames_ + 1,
                      info_.stats.milliseconds, ms_since(outline_start));
    }
    editor_->record(info_.stats);
    ++frames_;
    info_.threads = renderer_.threads();
    info_.isa = renderer_.isa();
    info_.settings = settings_;
    info_.post_passes.clear();
    for (const PostPass& p : scene_.post) info_.post_passes.push_back(p.name);
    info_.frame_ms = ms_since(start);
}

// The drawable size in pixels, as the framebuffer can hold it.
glm::ivec2 Viewer::drawable_size() const {
    int w = 0, h = 0;
    SDL_GetRendererOutputSize(sdl_renderer_.get(), &w, &h);
    return {std::clamp(w, 1, Framebuffer::kMaxSize), std::clamp(h, 1, Framebuffer::kMaxSize)};
}

void Viewer::present() {
    if (drawable_size() != texture_size_) resize_texture();
    if (image_.size() != size_t(texture_size_.x) * texture_size_.y * 4) {
        scene_dirty_ = true;  // the window changed since the last render
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    std::erase_if(messages_, [&](const Message& m) { return m.until <= now; });
    fade_at_ = std::chrono::steady_clock::time_point::max();
    for (const Message& m : messages_) fade_at_ = std::min(fade_at_, m.until);
    shown_ = image_;
    const int h = texture_size_.y;
    int points_w = 0, points_h = 0;
    SDL_GetWindowSize(window_.get(), &points_w, &points_h);
    const int scale = std::max(1, (texture_size_.x + points_w / 2) / std::max(1, points_w)) *
                      (points_h >= 1200 ? 2 : 1);  // HiDPI, and large windows
    ImageView view{shown_.data(), texture_size_.x, texture_size_.y};
    info_.idle_wakeups = idle_wakeups_;
    info_.flying = controller_.flying();
    info_.fly_speed = controller_.speed();
    info_.animation.clear();
    if (scene_.animated()) {
        const Timeline& line = scene_.timeline;
        info_.animation = fmt::format("{:.3f} s of {:g}..{:g} s  frame {}  {:g} fps  {}{}",
                                      playback_.time(), line.start, line.end,
                                      line.frame_at(playback_.time()),
                                      line.fps, playback_.playing() ? "playing" : "paused (Space)",
                                      scene_.camera_tracks.empty() || follow_camera_
                                          ? ""
                                          : "  camera free (R follows)");
    }
    if (show_overlay_) {
        const int y = 4 * scale + draw_panel(view, 4 * scale, 4 * scale, stats_text(info_),
                                             {235, 235, 235, 255}, scale);
        draw_messages(view, 4 * scale, y + 2 * scale, messages_, scale);
    }
    if (show_help_)
        draw_panel(view, 4 * scale, std::max(0, h - text_height(help_text(), scale) - 10 * scale),
                   help_text(), {255, 230, 150, 255}, scale);
    SDL_UpdateTexture(texture_.get(), nullptr, shown_.data(), texture_size_.x * 4);
    SDL_RenderClear(sdl_renderer_.get());
    SDL_RenderCopy(sdl_renderer_.get(), texture_.get(), nullptr, nullptr);
    if (editor_->visible()) show_editor();
    if (keep_window_) {
        window_size_ = drawable_size();
        window_image_.resize(size_t(window_size_.x) * window_size_.y * 4);
        if (SDL_RenderReadPixels(sdl_renderer_.get(), nullptr, SDL_PIXELFORMAT_RGBA32,
                                 window_image_.data(), window_size_.x * 4) != 0)
            window_image_.clear();
    }
    SDL_RenderPresent(sdl_renderer_.get());
    ++presents_;
}

// The editor's panel over the picture; what it changed renders next frame.
void Viewer::show_editor() {
    EditorTarget target{scene_,    settings_,          selected_, registry_,
                        textures_, options_.materials, playback_};
    const int before = selected_;
    const EditorResult r = editor_->show(target);
    if (r.redraw) scene_dirty_ = true, stalled_ = false;  // an edit may cure a stalled shader
    if (r.time_changed) pose_due_ = true;
    if (r.materials_changed) reload_->rewatch();
    if (r.selection_changed || selected_ != before) {
        update_selected_label();
        scene_dirty_ = true;  // the outline moves
    }
    for (const std::string& e : r.errors) message(e, true);
    if (r.save) save_edits();
}

void Viewer::save_edits() {
    if (!editor_->unsaved()) {
        message("nothing to save", false);
        return;
    }
    std::vector<std::string> errors;
    for (const fs::path& file : editor_->save(errors)) {
        reload_->written_by_us(file);  // memory holds what it says already
        message("saved " + file.string(), false);
    }
    for (const std::string& e : errors) message(e, true);
}

// Two points wide, in pixels.
int Viewer::outline_width() const {
    int points_w = 0;
    SDL_GetWindowSize(window_.get(), &points_w, nullptr);
    return std::max(2, 2 * int(std::lround(double(texture_size_.x) / std::max(1, points_w))));
}

void Viewer::resize_texture() {
    const glm::ivec2 size = drawable_size();
    texture_.reset(SDL_CreateTexture(sdl_renderer_.get(), SDL_PIXELFORMAT_RGBA32,
                                     SDL_TEXTUREACCESS_STREAMING, size.x, size.y));
    if (!texture_) throw Error(ErrorCode::display_failed, SDL_GetError());
    texture_size_ = size;
    scene_dirty_ = true;
}

void Viewer::save_screenshot(const std::filesystem::path& path) const {
    if (frame_error_)
        throw Error(frame_error_->code(),
                    "no screenshot: the last frame failed: " + frame_error_->detail(),
                    path.string());
    framebuffer_.write_png(path);
}

void Viewer::save_window(const std::filesystem::path& path) const {
    if (window_image_.empty())
        throw Error(ErrorCode::display_failed, "no window image kept (keep_window)", path.string());
    write_png(path, window_size_.x, window_size_.y, window_image_);
}

std::filesystem::path Viewer::screenshot_name() const {
    const std::time_t now = std::time(nullptr);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
    std::filesystem::path path = options_.screenshots / (std::string("facet-") + stamp + ".png");
    for (int n = 2; std::filesystem::exists(path); ++n)
        path = options_.screenshots / (std::string("facet-") + stamp + "-" + std::to_string(n) + ".png");
    return path;
}

}  // namespace facet::view
