#include "editor.hpp"

#include <facet/error.hpp>
#include <facet/math.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <imgui.h>
#include <imgui_stdlib.h>
#include <spdlog/fmt/fmt.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

namespace facet::view {

namespace fs = std::filesystem;

namespace {

const char* const kFilters[] = {"nearest", "bilinear", "trilinear", "anisotropic"};
const char* const kWraps[] = {"repeat", "clamp", "mirror"};

std::string filter_text(Filter f) { return kFilters[int(f)]; }
std::string wrap_text(Wrap w) { return kWraps[int(w)]; }

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorCode::file_not_found, "cannot read it to save", path.string());
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Writes `text` over `path` at once: a temporary file beside it, renamed
// (a watcher sees one complete file; a failure leaves the old one).
void write_file(const fs::path& path, const std::string& text) {
    const fs::path temporary = path.string() + ".facet-save";
    std::error_code error;
    const fs::perms perms = fs::status(path, error).permissions();
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out << text;
        if (!out.flush()) {
            fs::remove(temporary, error);
            throw Error(ErrorCode::output_failed, "cannot write " + temporary.string(),
                        path.string());
        }
    }
    if (perms != fs::perms::unknown) fs::permissions(temporary, perms, error);
    fs::rename(temporary, path, error);
    if (error) {
        const std::string why = error.message();
        fs::remove(temporary, error);
        throw Error(ErrorCode::output_failed, "cannot replace it: " + why, path.string());
    }
}

bool finite(const float* v, int n) {
    for (int i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

// The text `rotation:` has for object `i` in the scene file, if three numbers.
std::optional<glm::vec3> written_rotation(const fs::path& scene_file, size_t i) {
    try {
        const YAML::Node r = YAML::LoadFile(scene_file.string())["objects"][i]["rotation"];
        if (r.IsSequence() && r.size() == 3)
            return glm::vec3(r[0].as<float>(), r[1].as<float>(), r[2].as<float>());
    } catch (const YAML::Exception&) {
    }
    return std::nullopt;
}

// The material files the choice offers: the materials folder's and those
// the scene already uses.
std::vector<fs::path> material_choices(const EditorTarget& t) {
    std::vector<fs::path> out;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(t.materials, ec))
        if (e.path().extension() == ".yaml") out.push_back(fs::weakly_canonical(e.path()));
    for (const auto& [file, material] : t.scene.material_files)
        if (std::find(out.begin(), out.end(), file) == out.end()) out.push_back(file);
    std::sort(out.begin(), out.end());
    return out;
}

bool is_inline(const Material& m, const Scene& scene) {
    std::error_code ec;
    return fs::equivalent(m.file, scene.source, ec);
}

// Where the panel can save an edit of material `m` of object `o`: its own
// file, or the object's inline `material:`. Not a part's inline material
// under `materials:`, nor one a mesh file gives (those are shown only).
enum class Saved { in_file, inline_object, nowhere };

Saved where_saved(const Material& m, const Object& o, const Scene& scene) {
    if (is_inline(m, scene)) return &m == o.material.get() ? Saved::inline_object : Saved::nowhere;
    for (const auto& [file, material] : scene.material_files)
        if (material.get() == &m) return Saved::in_file;
    return Saved::nowhere;
}

// A material's name in the panel.
std::string material_label(const Material& m, const Scene& scene) {
    if (is_inline(m, scene)) return "inline (" + m.source + ")";
    for (const auto& [file, material] : scene.material_files)
        if (material.get() == &m) return file.filename().string();
    return m.source;  // a mesh file's: "FILE: material 'NAME'"
}

// The parameter `name` as written, if it is.
const MaterialParam* written(const Material& m, const std::string& name) {
    for (const MaterialParam& p : m.params)
        if (p.name == name) return &p;
    return nullptr;
}

// A parameter's current floats: as written, else the schema's default.
void current_floats(const Material& m, const facet_param_desc& d, float out[4]) {
    for (int i = 0; i < 4; ++i) out[i] = d.default_value[i];
    if (const MaterialParam* p = written(m, d.name))
        for (size_t i = 0; i < p->numbers.size() && i < 4; ++i) out[i] = float(p->numbers[i]);
}

// An ImGui id scope for as long as it lives (so that a panel's widgets and
// another's of the same name stay apart, however the panel returns).
struct ScopedId {
    explicit ScopedId(const char* id) { ImGui::PushID(id); }
    explicit ScopedId(int id) { ImGui::PushID(id); }
    ~ScopedId() { ImGui::PopID(); }
    ScopedId(const ScopedId&) = delete;
    ScopedId& operator=(const ScopedId&) = delete;
};

// Widgets shown but not usable while it lives (when `disabled`).
struct ScopedDisabled {
    explicit ScopedDisabled(bool disabled) { ImGui::BeginDisabled(disabled); }
    ~ScopedDisabled() { ImGui::EndDisabled(); }
    ScopedDisabled(const ScopedDisabled&) = delete;
    ScopedDisabled& operator=(const ScopedDisabled&) = delete;
};

// Runs one panel; an error from it (none is expected: every value is
// checked before it is written) is reported, not let out of the frame.
template <class Panel>
void guarded(EditorResult& r, Panel&& panel) {
    try {
        panel();
    } catch (const Error& e) {
        r.errors.push_back(e.what());
    }
}

double ms_of(const FrameStats& s, int pass) {
    switch (pass) {
        case 0: return s.milliseconds;
        case 1: return s.ms_shadow;
        case 2: return s.ms_prepass + s.ms_ao;
        case 3: return s.ms_main;
        default: return s.ms_post;
    }
}

}  // namespace

std::string texture_yaml(const MaterialParam& p, const fs::path& folder) {
    const auto name = [&](const fs::path& f) {
        return yaml_string(f.lexically_relative(folder).generic_string());
    };
    std::string text = "{";
    if (p.cube_faces.empty()) {
        text += "file: " + name(p.texture_file);
    } else {
        text += "faces: [";
        for (size_t i = 0; i < p.cube_faces.size(); ++i)
            text += (i ? ", " : "") + name(p.cube_faces[i]);
        text += "]";
    }
    text += ", filter: " + filter_text(p.filter) + ", wrap: " + wrap_text(p.wrap);
    if (p.filter == Filter::anisotropic && p.anisotropy != kMaxAnisotropy)
        text += ", anisotropy: " + std::to_string(p.anisotropy);
    if (p.uv_set != 0) text += ", uv_set: " + std::to_string(p.uv_set);
    const UvTransform& t = p.transform;
    if (!t.identity())
        text += fmt::format(", transform: {{offset: [{}, {}], rotation: {}, scale: [{}, {}]}}",
                            t.offset.x, t.offset.y, t.rotation, t.scale.x, t.scale.y);
    return text + "}";
}

glm::vec3 to_euler_degrees(const glm::quat& q) {
    // R = Rz(c) Ry(b) Rx(a): R[2][0] = -sin b, R[2][1] = cos b sin a,
    // R[2][2] = cos b cos a, R[1][0] = sin c cos b, R[0][0] = cos c cos b
    // (row, column; glm indexes column first).
    const glm::dmat3 m = glm::mat3_cast(glm::dquat(q));
    const double cb = std::hypot(m[0][0], m[0][1]);
    glm::dvec3 r;
    r.y = std::atan2(-m[0][2], cb);
    if (cb > 1e-4) {  // below, float rounding decides X and Z: gimbal lock
        r.x = std::atan2(m[1][2], m[2][2]);
        r.z = std::atan2(m[0][1], m[0][0]);
    } else {  // gimbal lock: put the whole turn about Z into X
        r.x = std::atan2(-m[2][1], m[1][1]);
        r.z = 0.0;
    }
    return glm::vec3(glm::degrees(r));
}

Editor::Editor(SDL_Window* window, SDL_Renderer* renderer) : imgui_(window, renderer) {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 4.0f;
    style.Colors[ImGuiCol_WindowBg].w = 0.88f;
}

bool Editor::handle(const SDL_Event& event) {
    if (!visible_) return false;
    return imgui_.handle(event);
}

void Editor::record(const FrameStats& stats) {
    history_.push_back(stats);
    if (history_.size() > kHistory) history_.pop_front();
}

void Editor::remember(const std::string& label) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    widgets_[label] = {a.x, a.y, b.x - a.x, b.y - a.y};
}

std::optional<Editor::Rect> Editor::widget(const std::string& label) const {
    const auto it = widgets_.find(label);
    if (it == widgets_.end()) return std::nullopt;
    return it->second;
}

glm::vec3 Editor::shown_euler(const Scene& scene, size_t i) const {
    const glm::quat q = scene.objects[i].rest.rotation;
    if (const std::optional<glm::vec3> file = written_rotation(scene.source, i)) {
        const glm::quat f = euler_degrees(*file);
        if (std::abs(glm::dot(f, q)) > 1.0f - 1e-6f) return *file;  // the same rotation
    }
    return to_euler_degrees(q);
}

void Editor::material_chosen(const Scene& scene, size_t object, const fs::path& file) {
    if (object >= scene.objects.size()) return;
    // Relative to the scene's folder as the loader joins it: lexically, on
    // the paths as given (a `..` across a symbolic link stays right).
    edit(scene.source, {"objects", object, "material"},
         yaml_string(fs::absolute(file).lexically_normal()
                         .lexically_relative(fs::absolute(scene.source).lexically_normal().parent_path())
                         .generic_string()));
}

size_t Editor::forget_unsaved() {
    const size_t n = unsaved();
    pending_.clear();
    return n;
}

size_t Editor::forget_unsaved(const fs::path& file) {
    const auto it = pending_.find(fs::weakly_canonical(file));
    if (it == pending_.end()) return 0;
    const size_t n = it->second.size();
    pending_.erase(it);
    return n;
}

void Editor::edit(const fs::path& file, YamlPath path, std::string value) {
    // A model opened with no scene file: the change shows, and nothing is
    // written into the model.
    if (is_model_file(file)) return;
    std::vector<Edit>& edits = pending_[fs::weakly_canonical(file)];
    std::erase_if(edits, [&](const Edit& e) { return e.path == path; });
    edits.push_back({std::move(path), std::move(value)});
}

size_t Editor::unsaved() const {
    size_t n = 0;
    for (const auto& [file, edits] : pending_) n += edits.size();
    return n;
}

std::vector<fs::path> Editor::unsaved_files() const {
    std::vector<fs::path> out;
    for (const auto& [file, edits] : pending_) out.push_back(file);
    return out;
}

std::vector<fs::path> Editor::save(std::vector<std::string>& errors) {
    std::vector<fs::path> saved;
    for (auto it = pending_.begin(); it != pending_.end();) {
        const fs::path& file = it->first;
        try {
            std::string text = read_file(file);
            for (const Edit& e : it->second) text = yaml_set(text, e.path, e.value, file.string());
            write_file(file, text);
            saved.push_back(file);
            it = pending_.erase(it);
        } catch (const Error& e) {
            errors.push_back(e.what());
            ++it;
        }
    }
    return saved;
}

EditorResult Editor::show(EditorTarget& t) {
    EditorResult r;
    if (!visible_) return r;
    imgui_.new_frame();
    const ImGuiIO& io = ImGui::GetIO();
    const float width = std::min(380.0f, io.DisplaySize.x * 0.45f);
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - width - 6.0f, 6.0f), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(width, io.DisplaySize.y - 12.0f), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("facet editor (E hides)")) {
        ImGui::PushItemWidth(-150.0f);
        const size_t n = unsaved();
        ImGui::BeginDisabled(n == 0);
        if (ImGui::Button("Save")) r.save = true;
        remember("Save");
        ImGui::EndDisabled();
        ImGui::SameLine();
        if (n) ImGui::Text("%zu unsaved value%s (Ctrl+S)", n, n == 1 ? "" : "s");
        else if (is_model_file(t.scene.source)) ImGui::TextDisabled("a model, no scene: nothing is saved");
        else ImGui::TextDisabled("nothing to save");
        const bool clips = std::any_of(t.scene.objects.begin(), t.scene.objects.end(),
                                       [](const Object& o) { return o.mesh && !o.mesh->clips.empty(); });
        if ((t.scene.animated() || clips) &&
            ImGui::CollapsingHeader("Animation", ImGuiTreeNodeFlags_DefaultOpen))
            guarded(r, [&] { animation_panel(t, r); });
        if (ImGui::CollapsingHeader("Objects", ImGuiTreeNodeFlags_DefaultOpen))
            guarded(r, [&] { objects_panel(t, r); });
        if (ImGui::CollapsingHeader("Material", ImGuiTreeNodeFlags_DefaultOpen))
            guarded(r, [&] { material_panel(t, r); });
        const bool lights = ImGui::CollapsingHeader("Lights");
        remember("Lights");
        if (lights) guarded(r, [&] { lights_panel(t, r); });
        const bool render = ImGui::CollapsingHeader("Render");
        remember("Render");
        if (render) guarded(r, [&] { render_panel(t, r); });
        if (ImGui::CollapsingHeader("Frame time", ImGuiTreeNodeFlags_DefaultOpen)) frame_panel();
        ImGui::PopItemWidth();
    }
    ImGui::End();
    imgui_.render();
    return r;
}

namespace {

// `o` where its rest place, which the editor edits as the file holds it,
// puts it: there, and for an animated object, animated to `time`.
void moved(Object& o, double time) {
    o.transform = o.rest;
    o.pose(time);
}

}  // namespace

void Editor::objects_panel(EditorTarget& t, EditorResult& r) {
    const ScopedId scope("objects");
    std::vector<Object>& objects = t.scene.objects;
    if (objects.empty()) {
        ImGui::TextDisabled("(no objects)");
        return;
    }
    if (ImGui::BeginListBox("##objects", ImVec2(-FLT_MIN, 5.5f * ImGui::GetTextLineHeightWithSpacing()))) {
        for (int i = 0; i < int(objects.size()); ++i) {
            const std::string label = objects[size_t(i)].name + "##object" + std::to_string(i);
            if (ImGui::Selectable(label.c_str(), i == t.selected) && i != t.selected) {
                t.selected = i;
                r.selection_changed = true;
            }
            remember("object" + std::to_string(i));
        }
        ImGui::EndListBox();
    }
    t.selected = std::clamp(t.selected, 0, int(objects.size()) - 1);
    Object& o = objects[size_t(t.selected)];
    const size_t i = size_t(t.selected);
    const fs::path& file = t.scene.source;
    if (euler_of_ != t.selected || o.rest.rotation != euler_of_rotation_) {
        euler_ = shown_euler(t.scene, i);  // a new selection, or turned by other means
        euler_of_ = t.selected;
        euler_of_rotation_ = o.rest.rotation;
    }
    if (ImGui::Checkbox("visible", &o.visible)) {
        edit(file, {"objects", i, "visible"}, o.visible ? "true" : "false");
        r.redraw = true;
    }
    const auto refused = [&](const char* what) {
        r.errors.push_back(std::string(what) + ": not a finite number; kept the old value");
    };
    glm::vec3 position = o.rest.translation;
    if (ImGui::DragFloat3("position", &position.x, 0.01f)) {
        if (!finite(&position.x, 3)) {
            refused("position");
        } else {
            o.rest.translation = position;
            moved(o, t.scene.time);
            edit(file, {"objects", i, "position"}, yaml_sequence(&position.x, 3));
            r.redraw = true;
        }
    }
    remember("position");
    glm::vec3 euler = euler_;
    if (ImGui::DragFloat3("rotation", &euler.x, 0.5f, -360.0f, 360.0f, "%.1f deg",
                          ImGuiSliderFlags_AlwaysClamp)) {
        euler_ = euler;
        o.rest.rotation = euler_of_rotation_ = euler_degrees(euler_);
        moved(o, t.scene.time);
        edit(file, {"objects", i, "rotation"}, yaml_sequence(&euler_.x, 3));
        r.redraw = true;
    }
    glm::vec3 scale = o.rest.scale;
    if (ImGui::DragFloat3("scale", &scale.x, 0.005f, -1e4f, 1e4f, "%.3f",
                          ImGuiSliderFlags_AlwaysClamp)) {
        // Never 0 (the loader refuses it); a mirrored axis keeps its sign.
        for (int k = 0; k < 3; ++k)
            if (std::abs(scale[k]) < 1e-4f) scale[k] = std::copysign(1e-4f, o.rest.scale[k]);
        o.rest.scale = scale;
        moved(o, t.scene.time);
        const glm::vec3& s = o.rest.scale;
        edit(file, {"objects", i, "scale"},
             s.x == s.y && s.y == s.z ? yaml_number(s.x) : yaml_sequence(&s.x, 3));
        r.redraw = true;
    }
    // The material file the object uses (an inline material is its own).
    if (o.material && !is_inline(*o.material, t.scene)) {
        const std::vector<fs::path> files = material_choices(t);
        const fs::path current = fs::weakly_canonical(o.material->source);
        const std::string shown = current.filename().string();
        if (ImGui::BeginCombo("material", shown.c_str())) {
            for (const fs::path& f : files) {
                if (!ImGui::Selectable(f.filename().string().c_str(), f == current) || f == current)
                    continue;
                try {
                    std::shared_ptr<Material>& shared = t.scene.material_files[f];
                    if (!shared) shared = load_material(f, t.registry, t.textures);
                    o.material = shared;
                    material_chosen(t.scene, i, f);
                    r.redraw = r.materials_changed = true;
                } catch (const Error& e) {
                    t.scene.material_files.erase(f);
                    r.errors.push_back(e.what());
                }
            }
            ImGui::EndCombo();
        }
    }
}

bool Editor::set_param(EditorTarget& t, Material& material, const facet_param_desc& desc,
                       MaterialParam value, const std::string& text, EditorResult& r) {
    const std::vector<MaterialParam> before = material.params;
    value.name = desc.name;
    auto at = std::find_if(material.params.begin(), material.params.end(),
                           [&](const MaterialParam& p) { return p.name == desc.name; });
    if (at != material.params.end()) {
        value.line = at->line;
        value.column = at->column;
        *at = value;
    } else {
        material.params.push_back(value);
    }
    try {
        bind(material, material.plugin, t.textures);
    } catch (const Error& e) {
        material.params = before;
        r.errors.push_back(e.what());
        return false;
    }
    const Object& o = t.scene.objects[size_t(t.selected)];
    switch (where_saved(material, o, t.scene)) {
        case Saved::inline_object:
            edit(t.scene.source, {"objects", size_t(t.selected), "material", "params", std::string(desc.name)}, text);
            break;
        case Saved::in_file: edit(material.source, {"params", std::string(desc.name)}, text); break;
        case Saved::nowhere: break;  // the panel shows such materials without widgets that change
    }
    r.redraw = true;
    return true;
}

namespace {

// A texture parameter's widgets: its file, filter and wrap. What it sets
// besides is kept as written.
bool texture_widget(const Material& m, const std::string& name, MaterialParam& p,
                    std::string& text, EditorResult& r) {
    bool changed = false;
    const MaterialParam* w = written(m, name);
    p.kind = MaterialParam::Kind::texture;
    if (w) {
        p.texture_file = w->texture_file;
        p.cube_faces = w->cube_faces;
        p.filter = w->filter;
        p.anisotropy = w->anisotropy;
        p.wrap = w->wrap;
        p.transform = w->transform;
        p.uv_set = w->uv_set;
    }
    const fs::path folder = fs::path(m.source).parent_path();
    std::string file = p.texture_file.empty()
                           ? ""
                           : p.texture_file.lexically_relative(folder).generic_string();
    ImGui::Text("%s", name.c_str());
    const std::string field = "file##" + name;
    if (ImGui::InputText(field.c_str(), &file, ImGuiInputTextFlags_EnterReturnsTrue)) {
        p.texture_file = (folder / file).lexically_normal();
        p.cube_faces.clear();  // a file typed in replaces a cube map's faces
        changed = !file.empty();
    }
    int filter = int(p.filter), wrap = int(p.wrap);
    if (ImGui::Combo(("filter##" + name).c_str(), &filter, kFilters, 4)) changed = true;
    if (ImGui::Combo(("wrap##" + name).c_str(), &wrap, kWraps, 3)) changed = true;
    p.filter = Filter(filter);
    p.wrap = Wrap(wrap);
    if (p.filter == Filter::anisotropic &&
        ImGui::SliderInt(("anisotropy##" + name).c_str(), &p.anisotropy, 2, kMaxAnisotropy))
        changed = true;
    if (changed && p.texture_file.empty() && p.cube_faces.empty()) {
        r.errors.push_back(name + ": type the texture's file first");
        changed = false;
    }
    text = texture_yaml(p, folder);
    return changed;
}

// A choice parameter's combo box, of the names its schema gives.
bool choice_widget(const Material& m, uint32_t k, MaterialParam& p, std::string& text) {
    const facet_param_desc& d = m.plugin->schema().params[k];
    const std::string name = d.name;
    bool changed = false;
    const std::vector<std::string> names =
        m.plugin->schema().choices && m.plugin->schema().choices[k]
            ? choice_names(m.plugin->schema().choices[k])
            : std::vector<std::string>{};
    const MaterialParam* w = written(m, name);
    std::string current = w ? w->word : "";
    if (current.empty() && !names.empty())
        current = names[std::min(names.size() - 1, size_t(std::max(0.0f, d.default_value[0])))];
    if (ImGui::BeginCombo(name.c_str(), current.c_str())) {
        for (const std::string& c : names)
            if (ImGui::Selectable(c.c_str(), c == current) && c != current) {
                current = c;
                changed = true;
            }
        ImGui::EndCombo();
    }
    p.kind = MaterialParam::Kind::word;
    p.word = current;
    text = yaml_string(current);
    return changed;
}

}  // namespace

bool Editor::param_widget(Material& m, uint32_t k, const ParamRange& range, MaterialParam& p,
                          std::string& text, EditorResult& r) {
    const facet_param_desc& d = m.plugin->schema().params[k];
    const std::string name = d.name;
    float* v = range.v;
    const float lo = range.lo, hi = range.hi;
    const bool bounded = range.bounded;
    bool changed = false;
    switch (d.type) {
        case FACET_PARAM_FLOAT:
            changed = bounded ? ImGui::SliderFloat(name.c_str(), v, lo, hi, "%.3f",
                                                   ImGuiSliderFlags_AlwaysClamp)
                              : ImGui::DragFloat(name.c_str(), v, 0.01f, lo, hi, "%.3f",
                                                 ImGuiSliderFlags_AlwaysClamp);
            if (!std::isfinite(v[0])) break;
            p.numbers = {v[0]};
            text = yaml_number(v[0]);
            break;
        case FACET_PARAM_INT: {
            int i = int(std::lround(v[0]));
            changed = bounded ? ImGui::SliderInt(name.c_str(), &i, int(lo), int(hi), "%d",
                                                 ImGuiSliderFlags_AlwaysClamp)
                              : ImGui::DragInt(name.c_str(), &i, 0.2f);
            p.numbers = {double(i)};
            p.is_integer = true;
            text = std::to_string(i);
            break;
        }
        case FACET_PARAM_BOOL: {
            const MaterialParam* w = written(m, name);
            bool on = w ? (w->kind == MaterialParam::Kind::boolean ? w->flag : w->numbers.size() && w->numbers[0] != 0)
                        : d.default_value[0] != 0.0f;
            changed = ImGui::Checkbox(name.c_str(), &on);
            p.kind = MaterialParam::Kind::boolean;
            p.flag = on;
            text = on ? "true" : "false";
            break;
        }
        case FACET_PARAM_VEC2:
        case FACET_PARAM_VEC3:
        case FACET_PARAM_VEC4: {
            const int n = int(d.type - FACET_PARAM_VEC2) + 2;
            changed = ImGui::DragScalarN(name.c_str(), ImGuiDataType_Float, v, n, 0.01f,
                                         &lo, &hi, "%.3f", ImGuiSliderFlags_AlwaysClamp);
            if (!finite(v, n)) break;
            p.kind = MaterialParam::Kind::vector;
            p.numbers.assign(v, v + n);
            text = yaml_sequence(v, n);
            break;
        }
        case FACET_PARAM_COLOR3:
        case FACET_PARAM_COLOR4: {
            const int n = d.type == FACET_PARAM_COLOR3 ? 3 : 4;
            const ImGuiColorEditFlags flags = ImGuiColorEditFlags_Float |
                                              (hi > 1.0f ? ImGuiColorEditFlags_HDR : 0);
            changed = n == 3 ? ImGui::ColorEdit3(name.c_str(), v, flags)
                             : ImGui::ColorEdit4(name.c_str(), v, flags);
            for (int c = 0; c < n; ++c) v[c] = std::clamp(v[c], std::max(lo, 0.0f), hi);
            if (!finite(v, n)) break;
            p.kind = MaterialParam::Kind::vector;
            p.numbers.assign(v, v + n);
            text = yaml_sequence(v, n);
            break;
        }
        case FACET_PARAM_CHOICE: changed = choice_widget(m, k, p, text); break;
        case FACET_PARAM_TEXTURE: changed = texture_widget(m, name, p, text, r); break;
        default: ImGui::TextDisabled("%s (%s)", name.c_str(), std::string(param_type_name(d.type)).c_str());
    }
    return changed;
}

void Editor::material_panel(EditorTarget& t, EditorResult& r) {
    if (t.scene.objects.empty()) return;
    const Object& o = t.scene.objects[size_t(t.selected)];
    // The materials its parts are drawn with; a mesh of several parts may
    // have several, chosen here.
    const std::vector<Material*> materials = o.materials();
    if (materials.empty()) {
        ImGui::TextDisabled("(no material)");
        return;
    }
    if (material_choice_of_ != t.selected || material_choice_ >= materials.size())
        material_choice_ = 0;
    material_choice_of_ = t.selected;
    if (materials.size() > 1) {
        const std::string shown = material_label(*materials[material_choice_], t.scene);
        const bool open = ImGui::BeginCombo("part material", shown.c_str());
        remember("part material");
        if (open) {
            for (size_t i = 0; i < materials.size(); ++i)
                if (ImGui::Selectable((material_label(*materials[i], t.scene) + "##" + std::to_string(i)).c_str(),
                                      i == material_choice_))
                    material_choice_ = i;
            ImGui::EndCombo();
        }
    }
    Material& m = *materials[material_choice_];
    if (!m.plugin) {
        ImGui::TextDisabled("(not bound)");
        return;
    }
    ImGui::TextWrapped("%s: shader '%s'", material_label(m, t.scene).c_str(), m.plugin->name().c_str());
    const bool editable = where_saved(m, o, t.scene) != Saved::nowhere;
    if (!editable)
        ImGui::TextWrapped("Shown only: name a material for these parts in the scene "
                           "(materials:) to edit it.");
    const ScopedDisabled disabled(!editable);
    const facet_schema& desc = m.plugin->schema();
    const ScopedId scope("material");
    for (uint32_t k = 0; k < desc.param_count; ++k) {
        const facet_param_desc& d = desc.params[k];
        const std::string name = d.name;
        const bool bounded = std::isfinite(d.min_value) && std::isfinite(d.max_value) &&
                             d.max_value - d.min_value <= 1000.0f;
        const float lo = std::isfinite(d.min_value) ? d.min_value : -FLT_MAX;
        const float hi = std::isfinite(d.max_value) ? d.max_value : FLT_MAX;
        float v[4];
        current_floats(m, d, v);
        MaterialParam p;
        std::string text;
        bool changed = param_widget(m, k, {v, lo, hi, bounded}, p, text, r);
        if (d.type != FACET_PARAM_TEXTURE) remember(name);
        if (d.doc && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", d.doc);
        if (changed && d.type != FACET_PARAM_TEXTURE && d.type != FACET_PARAM_CHOICE &&
            d.type != FACET_PARAM_BOOL && !finite(v, 4)) {
            r.errors.push_back(name + ": not a finite number; kept the old value");
            changed = false;
        }
        if (changed && editable) set_param(t, m, d, std::move(p), text, r);
    }
}

void Editor::lights_panel(EditorTarget& t, EditorResult& r) {
    const ScopedId scope("lights");
    const fs::path& file = t.scene.source;
    for (size_t i = 0; i < t.scene.lights.size(); ++i) {
        Light& l = t.scene.lights[i];
        const std::string id = "##light" + std::to_string(i);
        const char* type = l.type == LightType::directional ? "directional"
                           : l.type == LightType::point     ? "point"
                                                            : "spot";
        const ScopedId light_scope{int(i)};
        ImGui::Separator();
        ImGui::Text("light %zu: %s", i + 1, type);
        const auto changed = [&](bool did, const std::string& key, const std::string& value) {
            if (!did) return;
            edit(file, {"lights", i, key}, value);
            r.redraw = true;
        };
        glm::vec3 colour = l.color;
        if (ImGui::ColorEdit3(("color" + id).c_str(), &colour.x,
                              ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR) &&
            finite(&colour.x, 3)) {
            l.color = glm::max(colour, glm::vec3(0.0f));
            changed(true, "color", yaml_sequence(&l.color.x, 3));
        }
        remember("color" + id);
        const bool intensity = ImGui::DragFloat(("intensity" + id).c_str(), &l.intensity, 0.02f,
                                                0.0f, 1e4f, "%.3f", ImGuiSliderFlags_AlwaysClamp);
        changed(intensity, "intensity", yaml_number(l.intensity));
        remember("intensity" + id);
        glm::vec3 position = l.position;
        if (l.type != LightType::directional &&
            ImGui::DragFloat3(("position" + id).c_str(), &position.x, 0.02f) &&
            finite(&position.x, 3)) {
            l.position = position;
            changed(true, "position", yaml_sequence(&l.position.x, 3));
        }
        if (l.type != LightType::point) {
            glm::vec3 d = l.direction;
            if (ImGui::DragFloat3(("direction" + id).c_str(), &d.x, 0.01f) && finite(&d.x, 3) &&
                glm::length(d) > 1e-6f) {
                l.direction = glm::normalize(d);
                changed(true, "direction", yaml_sequence(&l.direction.x, 3));
            }
        }
        if (l.type == LightType::spot) {
            float inner = l.spot_inner, outer = l.spot_outer;
            // The loader's rule: 0 <= inner <= outer <= 90 degrees.
            if (ImGui::SliderFloat(("cone inner" + id).c_str(), &inner, 0.0f, outer, "%.1f deg",
                                   ImGuiSliderFlags_AlwaysClamp) &&
                std::isfinite(inner)) {
                l.spot_inner = std::clamp(inner, 0.0f, l.spot_outer);
                changed(true, "spot_inner", yaml_number(l.spot_inner));
            }
            if (ImGui::SliderFloat(("cone outer" + id).c_str(), &outer, std::max(inner, 0.1f),
                                   89.0f, "%.1f deg", ImGuiSliderFlags_AlwaysClamp) &&
                std::isfinite(outer)) {
                l.spot_outer = std::clamp(outer, std::max(l.spot_inner, 0.1f), 89.0f);
                changed(true, "spot_outer", yaml_number(l.spot_outer));
            }
        }
        changed(ImGui::Checkbox(("casts shadow" + id).c_str(), &l.casts_shadow), "casts_shadow",
                l.casts_shadow ? "true" : "false");
    }
    if (t.scene.lights.empty()) ImGui::TextDisabled("(no lights)");
}

void Editor::render_panel(EditorTarget& t, EditorResult& r) {
    const ScopedId scope("render");
    RenderSettings& s = t.settings;
    const fs::path& file = t.scene.source;
    const auto changed = [&](bool did, const std::string& key, const std::string& value) {
        if (!did) return;
        edit(file, {"render", key}, value);
        r.redraw = true;
    };
    const char* const samples[] = {"1", "2", "4", "8"};
    int msaa = s.msaa >= 8 ? 3 : s.msaa >= 4 ? 2 : s.msaa >= 2 ? 1 : 0;
    if (ImGui::Combo("msaa", &msaa, samples, 4)) {
        s.msaa = 1 << msaa;
        changed(true, "msaa", std::to_string(s.msaa));
    }
    changed(ImGui::Checkbox("shadows", &s.shadows), "shadows", s.shadows ? "true" : "false");
    ImGui::SameLine();
    changed(ImGui::Checkbox("ao", &s.ao), "ao", s.ao ? "true" : "false");
    ImGui::SameLine();
    changed(ImGui::Checkbox("post", &s.post), "post", s.post ? "true" : "false");
    changed(ImGui::Checkbox("wireframe", &s.wireframe), "wireframe", s.wireframe ? "true" : "false");
    ImGui::SameLine();
    changed(ImGui::Checkbox("depth pre-pass", &s.depth_prepass), "depth_prepass",
            s.depth_prepass ? "true" : "false");
    glm::vec4 clear = s.clear_color;
    if (ImGui::ColorEdit4("clear colour", &clear.x,
                          ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR) &&
        finite(&clear.x, 4)) {
        s.clear_color = glm::max(clear, glm::vec4(0.0f));
        changed(true, "clear_color", yaml_sequence(&s.clear_color.x, 4));
    }
    int map = s.shadow_map_size;
    if (ImGui::SliderInt("shadow map", &map, 256, 8192, "%d texels", ImGuiSliderFlags_Logarithmic)) {
        s.shadow_map_size = std::clamp((map + 15) / 16 * 16, 16, 8192);
        changed(true, "shadow_map_size", std::to_string(s.shadow_map_size));
    }
    bool half = s.ao_half_resolution;
    if (ImGui::Checkbox("AO at half resolution", &half)) {
        s.ao_half_resolution = half;
        changed(true, "ao_resolution", half ? "half" : "full");
    }
    if (ImGui::SliderFloat("AO radius", &s.ao_radius, 0.01f, 10.0f, "%.2f",
                           ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp)) {
        s.ao_radius = std::max(0.01f, s.ao_radius);
        changed(true, "ao_radius", yaml_number(s.ao_radius));
    }
    if (ImGui::SliderInt("AO samples", &s.ao_samples, 1, 64)) {
        s.ao_samples = std::clamp(s.ao_samples, 1, 256);
        changed(true, "ao_samples", std::to_string(s.ao_samples));
    }
}

// Play and pause, the time as a slider, and the frame it is.
void Editor::animation_panel(EditorTarget& t, EditorResult& r) {
    Playback& p = t.playback;
    const Timeline& line = p.timeline();
    if (ImGui::Button(p.playing() ? "Pause" : "Play")) {
        p.set_playing(!p.playing());
        r.redraw = true;  // the overlay says so
    }
    remember("Play");
    ImGui::SameLine();
    ImGui::Text("frame %ld at %g fps (Space, arrows)", line.frame_at(p.time()), line.fps);
    float time = float(p.time());
    if (ImGui::SliderFloat("time", &time, float(line.start), float(line.end), "%.3f s")) {
        p.seek(time);
        r.time_changed = true;
    }
    remember("time");
    clip_chooser(t, r);
}

// The selected object's clip, when its mesh file has clips: `none` or one
// of them, saved as its index.
void Editor::clip_chooser(EditorTarget& t, EditorResult& r) {
    if (t.selected < 0 || size_t(t.selected) >= t.scene.objects.size()) return;
    const size_t i = size_t(t.selected);
    Object& o = t.scene.objects[i];
    if (!o.mesh || o.mesh->clips.empty()) return;
    const auto name = [&](int c) { return c < 0 ? std::string("none") : o.mesh->clips[size_t(c)].name; };
    if (ImGui::BeginCombo(("clip of " + o.name).c_str(), name(o.clip).c_str())) {
        for (int c = -1; c < int(o.mesh->clips.size()); ++c) {
            const std::string label = name(c) + "##clip" + std::to_string(c);
            if (ImGui::Selectable(label.c_str(), c == o.clip) && c != o.clip) {
                o.clip = c;
                moved(o, t.scene.time);
                // A longer clip plays to its end.
                Timeline& line = t.scene.timeline;
                if (animation_end(*o.mesh, c) > line.end) {
                    line.end = animation_end(*o.mesh, c);
                    t.playback.retime(line);
                }
                edit(t.scene.source, {"objects", i, "animate", "clip"},
                     c < 0 ? "none" : std::to_string(c));
                r.redraw = true;
            }
            remember(label);
        }
        ImGui::EndCombo();
    }
    remember("clip");
}

void Editor::frame_panel() {
    if (history_.empty()) {
        ImGui::TextDisabled("(no frame yet)");
        return;
    }
    static const char* const kNames[] = {"frame", "shadow maps", "pre-pass + AO", "main",
                                         "resolve + post"};
    float values[kHistory];
    for (int pass = 0; pass < 5; ++pass) {
        double peak = 0.0;
        int n = 0;
        for (const FrameStats& s : history_) {
            values[n] = float(ms_of(s, pass));
            peak = std::max(peak, double(values[n++]));
        }
        if (pass > 0 && peak == 0.0) continue;  // a pass this scene never ran
        char overlay[64];
        std::snprintf(overlay, sizeof overlay, "%s %.2f ms", kNames[pass], ms_of(history_.back(), pass));
        ImGui::PlotLines(("##time" + std::to_string(pass)).c_str(), values, n, 0, overlay, 0.0f,
                         float(peak) * 1.1f, ImVec2(-FLT_MIN, pass == 0 ? 48.0f : 32.0f));
    }
}

}  // namespace facet::view
