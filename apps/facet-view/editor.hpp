// facet-view's editor: a Dear ImGui panel over the picture.
//
//   Objects   select (the selection is outlined in the picture), move,
//             rotate, scale, show or hide, and choose a material file
//   Material  the selected object's parameters, as widgets made from its
//             shader's schema: colour pickers, sliders within the schema's
//             ranges, checkboxes, choices, textures with their filter and wrap
//   Lights    colour, intensity, position, direction, cone, shadows
//   Render    samples, shadows, AO, post chain, wireframe, clear colour
//   Frame     a graph of the last frames' time, per pass
//   Save      writes every edited value back into its scene or material
//             file in place (facet/yaml_patch.hpp): key order, comments and
//             the rest of the text stay as written. Hot reload then reads
//             the files back, to the same picture.
//
// A change applies on the next frame. Edits are kept per file until saved;
// when a file changes on disk first, the viewer drops them (and says so).
#pragma once

#include "playback.hpp"

#include "imgui_sdl.hpp"

#include <facet/material.hpp>
#include <facet/pipeline.hpp>
#include <facet/plugin.hpp>
#include <facet/scene.hpp>
#include <facet/texture.hpp>
#include <facet/yaml_patch.hpp>

#include <SDL.h>

#include <deque>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace facet::view {

// What the panel edits; the viewer owns it all.
struct EditorTarget {
    Scene& scene;
    RenderSettings& settings;  // the viewer's: the scene's with its toggles
    int& selected;             // index into scene.objects
    PluginRegistry& registry;
    TextureCache& textures;
    const std::filesystem::path& materials;  // the folder the material choice lists
    Playback& playback;                      // the time the scene is posed at
};

// What one frame of the panel did.
struct EditorResult {
    bool redraw = false;             // something drawn changed
    bool selection_changed = false;
    bool materials_changed = false;  // an object took a material file not watched yet
    bool save = false;               // Save was pressed
    bool time_changed = false;       // the playback was scrubbed: pose the scene again
    std::vector<std::string> errors; // a value the shader or the loader refused
};

class Editor {
public:
    Editor(SDL_Window* window, SDL_Renderer* renderer);

    bool visible() const { return visible_; }
    void set_visible(bool visible) { visible_ = visible; }
    // Feeds an event to the panel; true when the panel takes it.
    bool handle(const SDL_Event& event);
    // Adds a frame to the time graph.
    void record(const FrameStats& stats);
    // Builds and draws the panel over the renderer's picture.
    EditorResult show(EditorTarget& target);
    // True when the panel needs another frame to finish what input began
    // (a click whose release it has not yet seen).
    bool wants_frame() const { return visible_ && imgui_.needs_frame(); }

    // Values edited and not yet saved, and the files they go to.
    size_t unsaved() const;
    std::vector<std::filesystem::path> unsaved_files() const;
    // Writes each file's edits (to a temporary file, renamed over it, with
    // the old file's permissions). Returns the files written; a file that
    // fails keeps its edits and its error goes to `errors`.
    std::vector<std::filesystem::path> save(std::vector<std::string>& errors);
    // Drops the edits of every file, or of one (which changed on disk);
    // returns how many values were dropped.
    size_t forget_unsaved();
    size_t forget_unsaved(const std::filesystem::path& file);
    // The scene was replaced (opened, reloaded): what the panel keeps about
    // its objects is forgotten.
    void scene_changed() { euler_of_ = -1; }
    // Object `object` of `scene` was given material file `file` by other
    // means (the viewer's M key): an edit, saved like the panel's own.
    void material_chosen(const Scene& scene, size_t object, const std::filesystem::path& file);

    // Where a widget was drawn in the last frame, in window points (tests
    // drive the panel with synthetic clicks): its label as the panel gives
    // it, e.g. "base_color", "intensity##light1", "Save".
    struct Rect {
        float x = 0, y = 0, w = 0, h = 0;
    };
    std::optional<Rect> widget(const std::string& label) const;

private:
    struct Edit {
        YamlPath path;
        std::string value;
    };

    void objects_panel(EditorTarget& t, EditorResult& r);
    void material_panel(EditorTarget& t, EditorResult& r);
    // The widget of material m's parameter k, whose value `v` (4 floats,
    // current_floats) the widget edits within [lo, hi], as a slider where
    // `bounded`; fills the parameter's new value and its YAML text, and
    // returns whether the user changed it.
    struct ParamRange {
        float* v;
        float lo, hi;
        bool bounded;
    };
    bool param_widget(Material& m, uint32_t k, const ParamRange& range, MaterialParam& p,
                      std::string& text, EditorResult& r);
    void lights_panel(EditorTarget& t, EditorResult& r);
    void render_panel(EditorTarget& t, EditorResult& r);
    void frame_panel();
    void animation_panel(EditorTarget& t, EditorResult& r);
    void clip_chooser(EditorTarget& t, EditorResult& r);
    // Sets parameter `desc` of `material` to `value` and binds it again;
    // records the edit where the material is written. False (and the old
    // value kept) if the shader refuses it.
    bool set_param(EditorTarget& t, Material& material, const facet_param_desc& desc,
                   MaterialParam value, const std::string& text, EditorResult& r);
    void edit(const std::filesystem::path& file, YamlPath path, std::string value);
    // The Euler angles the panel shows for object `i`: the file's own when
    // it gives three that make the object's rotation, else derived from it.
    glm::vec3 shown_euler(const Scene& scene, size_t i) const;
    void remember(const std::string& label);

    ImGuiSdl imgui_;
    bool visible_ = true;
    // Edits by file, in the order made; a later edit of the same path
    // replaces the earlier one.
    std::map<std::filesystem::path, std::vector<Edit>> pending_;
    std::map<std::string, Rect> widgets_;
    // The rotation of the selected object in Euler degrees as the panel
    // shows it (a quaternion has many), kept while it stays selected.
    int euler_of_ = -1;
    glm::vec3 euler_{0.0f};
    glm::quat euler_of_rotation_{1.0f, 0.0f, 0.0f, 0.0f};  // the rotation euler_ was made for
    std::string texture_path_;  // the texture field being typed
    size_t material_choice_ = 0;  // which of the selected object's materials the panel shows
    int material_choice_of_ = -1;  // ... for this object
    static constexpr size_t kHistory = 120;
    std::deque<FrameStats> history_;
};

// A texture parameter as the editor writes it back: its file (or a cube
// map's faces) relative to `folder`, filter and wrap, and what else it sets
// (anisotropy, transform, UV set), as a YAML flow map.
std::string texture_yaml(const MaterialParam& p, const std::filesystem::path& folder);

// Euler angles in degrees (applied X, then Y, then Z) of a rotation, the
// inverse of euler_degrees() (facet/math.hpp).
glm::vec3 to_euler_degrees(const glm::quat& q);

}  // namespace facet::view
