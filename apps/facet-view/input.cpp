// The viewer's input: keys, mouse, window events and dropped files.
#include "viewer.hpp"

#include <facet/error.hpp>
#include <facet/material.hpp>

#include <algorithm>

namespace facet::view {

namespace fs = std::filesystem;

namespace {

constexpr float kDegreesPerPoint = 0.3f;

// configs/materials/*.yaml, sorted, as canonical paths.
std::vector<fs::path> material_files(const fs::path& folder) {
    std::vector<fs::path> out;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(folder, ec))
        if (e.path().extension() == ".yaml") out.push_back(fs::weakly_canonical(e.path()));
    std::sort(out.begin(), out.end());
    return out;
}

int next_msaa(int samples) { return samples >= 8 ? 1 : samples * 2; }

}  // namespace

bool Viewer::handle(const SDL_Event& e) {
    // The editor's panel first: what it takes (a click on a widget, typing
    // into a field) goes no further.
    if (editor_->visible() && e.type != SDL_QUIT) {
        overlay_dirty_ = true;  // the panel shows hover and presses
        if (e.type == SDL_KEYUP) hold(e.key.keysym.sym, false);  // a fly key never sticks
        if (editor_->handle(e)) return true;
    }
    switch (e.type) {
        case SDL_QUIT: return !may_quit();
        case SDL_KEYDOWN: return handle_key(e.key);
        case SDL_KEYUP: hold(e.key.keysym.sym, false); break;
        case SDL_MOUSEMOTION: handle_drag(e.motion); break;
        case SDL_MOUSEWHEEL:
            controller_.zoom(float(e.wheel.direction == SDL_MOUSEWHEEL_FLIPPED ? -e.wheel.y
                                                                                : e.wheel.y));
            follow_camera_ = false;  // moved by hand
            scene_dirty_ = true;
            break;
        case SDL_WINDOWEVENT: handle_window(e.window); break;
        case SDL_DROPFILE:
            handle_drop(e.drop.file);
            SDL_free(e.drop.file);
            break;
        case SDL_DROPTEXT: SDL_free(e.drop.file); break;  // owned by us, unused
        default: break;  // includes the file watcher's wake-up
    }
    return true;
}

// The fly keys, in the order of held_, and the view axis each moves along.
constexpr SDL_Keycode kFlyKeys[7] = {SDLK_w,     SDLK_a,      SDLK_s,     SDLK_d,
                                     SDLK_SPACE, SDLK_LSHIFT, SDLK_RSHIFT};
const glm::vec3 kFlyAxes[7] = {{0, 0, 1}, {-1, 0, 0}, {0, 0, -1}, {1, 0, 0},
                               {0, 1, 0}, {0, -1, 0}, {0, -1, 0}};

void Viewer::hold(SDL_Keycode key, bool down) {
    for (size_t k = 0; k < held_.size(); ++k) {
        if (kFlyKeys[k] != key) continue;
        if (down && !held_[k]) last_flight_ = std::chrono::steady_clock::now();
        held_[k] = down;
    }
}

glm::vec3 Viewer::flight() const {
    glm::vec3 move(0.0f);
    for (size_t k = 0; k < held_.size(); ++k)
        if (held_[k]) move += kFlyAxes[k];
    return glm::clamp(move, glm::vec3(-1.0f), glm::vec3(1.0f));
}

void Viewer::advance_flight() {
    const auto now = std::chrono::steady_clock::now();
    const float seconds = std::min(0.1f, std::chrono::duration<float>(now - last_flight_).count());
    last_flight_ = now;
    const glm::vec3 move = flight();
    if (!controller_.flying() || move == glm::vec3(0.0f)) return;
    controller_.fly(move, seconds);
    follow_camera_ = false;
    scene_dirty_ = true;
}

bool Viewer::handle_key(const SDL_KeyboardEvent& key) {
    if (!key.repeat) hold(key.keysym.sym, true);
    const bool shift = key.keysym.mod & KMOD_SHIFT;
    bool redraw = true;  // false: only the overlay changes
    switch (key.keysym.sym) {
        case SDLK_ESCAPE:
            if (may_quit()) return false;
            break;
        case SDLK_h:
        case SDLK_F1: show_help_ = !show_help_; redraw = false; break;
        case SDLK_o: show_overlay_ = !show_overlay_; redraw = false; break;
        case SDLK_r:
            follow_camera_ = !scene_.camera_tracks.empty();
            controller_.reset(scene_.camera);
            break;
        case SDLK_SPACE:
            if (controller_.flying()) return true;  // a fly key (hold())
            if (!scene_.animated()) {
                message("the scene does not move: no animation: key, no animate: tracks", true);
                return true;
            }
            set_playing(!playback_.playing());
            redraw = false;
            break;
        case SDLK_LEFT:
        case SDLK_RIGHT:
            playback_.step(key.keysym.sym == SDLK_LEFT ? -1 : 1);
            pose_due_ = true;
            redraw = false;
            break;
        case SDLK_HOME:
            seek(playback_.timeline().start);
            redraw = false;
            break;
        case SDLK_f: controller_.set_flying(!controller_.flying()); redraw = false; break;
        case SDLK_g:
            if (scene_.objects.empty()) break;
            follow_camera_ = false;
            controller_.reset(framed_camera(scene_.objects[size_t(selected_)], scene_.camera));
            break;
        case SDLK_PLUS: case SDLK_EQUALS: case SDLK_KP_PLUS: controller_.faster(); redraw = false; break;
        case SDLK_MINUS: case SDLK_KP_MINUS: controller_.slower(); redraw = false; break;
        case SDLK_TAB: select_next(); redraw = editor_->visible(); break;  // the outline moves
        case SDLK_e: editor_->set_visible(!editor_->visible()); break;
        case SDLK_s:
            if (!(key.keysym.mod & KMOD_CTRL)) return true;  // a fly key (hold())
            save_edits();
            redraw = false;
            break;
        case SDLK_m: cycle_material(shift ? -1 : 1); break;
        case SDLK_l: settings_.wireframe = !settings_.wireframe; break;
        case SDLK_n: settings_.msaa = next_msaa(settings_.msaa); break;
        case SDLK_1: settings_.shadows = !settings_.shadows; break;
        case SDLK_2: settings_.ao = !settings_.ao; break;
        case SDLK_3: settings_.post = !settings_.post; break;
        case SDLK_p:
        case SDLK_F12: take_screenshot(); redraw = false; break;
        default: return true;
    }
    if (redraw) scene_dirty_ = true;
    overlay_dirty_ = true;
    return true;
}

// Quits at once unless the editor holds unsaved values: then the first
// request says so, and a second within five seconds quits.
bool Viewer::may_quit() {
    const auto now = std::chrono::steady_clock::now();
    if (!editor_->unsaved() || (options_.stop && options_.stop->load()) || now < quit_armed_until_)
        return true;
    quit_armed_until_ = now + std::chrono::seconds(5);
    message(std::to_string(editor_->unsaved()) +
                " unsaved values: Ctrl+S saves them; quit again to leave without saving",
            true);
    return false;
}

void Viewer::take_screenshot() {
    const fs::path path = screenshot_name();
    try {
        save_screenshot(path);
        message("saved " + path.string(), false);
    } catch (const Error& e) {
        message(e.what(), true);
    }
}

// Left drag orbits (looks, when flying); right or middle drag, or shift with
// left, pans.
void Viewer::handle_drag(const SDL_MouseMotionEvent& m) {
    const float dx = float(m.xrel), dy = float(m.yrel);
    const bool left = m.state & SDL_BUTTON_LMASK;
    const bool pan = (m.state & (SDL_BUTTON_RMASK | SDL_BUTTON_MMASK)) ||
                     (left && (SDL_GetModState() & KMOD_SHIFT));
    if (pan) {
        int height = 0;
        SDL_GetWindowSize(window_.get(), nullptr, &height);  // points, as the mouse moves
        controller_.pan(dx, dy, float(height));
    } else if (left && controller_.flying()) {
        controller_.look(-dx * kDegreesPerPoint, dy * kDegreesPerPoint);
    } else if (left) {
        controller_.orbit(-dx * kDegreesPerPoint, dy * kDegreesPerPoint);
    } else {
        return;  // a plain move changes nothing
    }
    follow_camera_ = false;  // moved by hand
    scene_dirty_ = true;
}

void Viewer::handle_window(const SDL_WindowEvent& w) {
    switch (w.event) {
        case SDL_WINDOWEVENT_SIZE_CHANGED:
        case SDL_WINDOWEVENT_DISPLAY_CHANGED: scene_dirty_ = true; break;  // maybe new DPI
        case SDL_WINDOWEVENT_EXPOSED: overlay_dirty_ = true; break;
        case SDL_WINDOWEVENT_FOCUS_LOST: held_.fill(false); break;
        default: break;
    }
}

void Viewer::handle_drop(const char* file) {
    const fs::path path(file ? file : "");
    if (path.extension() != ".yaml" && path.extension() != ".yml" && !is_model_file(path)) {
        message("not a scene file (.yaml) or a model file: " + path.string(), true);
        return;
    }
    open_scene(path);
}

void Viewer::open_scene(const fs::path& path) {
    try {
        adopt_scene(load_scene(path, registry_));
        message("opened " + path.string(), false);
    } catch (const Error& e) {
        message(std::string(e.what()) + " (keeping the current scene)", true);
    }
}

void Viewer::select_next() {
    if (scene_.objects.empty()) return;
    selected_ = (selected_ + 1) % int(scene_.objects.size());
    update_selected_label();
}

void Viewer::update_selected_label() {
    if (scene_.objects.empty()) {
        info_.selected = "(no objects)";
        return;
    }
    const Object& o = scene_.objects[size_t(selected_)];
    const std::string name = o.name.empty() ? "object " + std::to_string(selected_ + 1) : o.name;
    const std::string material = o.material ? fs::path(o.material->source).filename().string()
                                 : o.materials().empty() ? "(none)"
                                                         : "its mesh file's materials";
    info_.selected = name + ": " + material;
    overlay_dirty_ = true;
}

// Gives the selected object the next (step 1) or previous (-1) material
// file of the materials folder. A file that fails to load is reported and
// skipped over on the next press; the object keeps its material.
void Viewer::cycle_material(int step) {
    if (scene_.objects.empty()) {
        message("the scene has no object to give a material", true);
        return;
    }
    const std::vector<fs::path> files = material_files(options_.materials);
    if (files.empty()) {
        message("no materials (*.yaml) in " + options_.materials.string(), true);
        return;
    }
    Object& object = scene_.objects[size_t(selected_)];
    const fs::path current = object.material ? fs::weakly_canonical(object.material->source) : "";
    const auto at = std::find(files.begin(), files.end(), current);
    const int n = int(files.size());
    const int index = at == files.end() ? (step > 0 ? 0 : n - 1)
                                        : ((int(at - files.begin()) + step) % n + n) % n;
    const fs::path& file = files[size_t(index)];
    try {
        std::shared_ptr<Material>& shared = scene_.material_files[file];
        if (!shared) shared = load_material(file, registry_, textures_);
        object.material = shared;
        editor_->material_chosen(scene_, size_t(selected_), file);  // saved with the editor's edits
    } catch (const Error& e) {
        scene_.material_files.erase(file);
        message(e.what(), true);
        return;
    }
    reload_->rewatch();
    update_selected_label();
    message(info_.selected, false);
}

}  // namespace facet::view
