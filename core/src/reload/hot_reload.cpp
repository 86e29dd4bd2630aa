#include "facet/hot_reload.hpp"

#include "facet/error.hpp"
#include "facet/memory.hpp"
#include "base/isolated.hpp"
#include "base/file_digest.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <set>

namespace facet {

namespace fs = std::filesystem;

namespace {

fs::path canonical_or_same(const fs::path& p) {
    std::error_code ec;
    const fs::path c = fs::weakly_canonical(p, ec);
    return ec ? p : c;
}

// Every material the scene holds, each once: those its parts are drawn
// with, and each object's own, which its parts may all override now and
// not after an edit.
std::vector<Material*> materials_of(const Scene& scene) {
    std::vector<Material*> out = scene.materials();
    for (const Object& o : scene.objects)
        if (o.material && std::find(out.begin(), out.end(), o.material.get()) == out.end())
            out.push_back(o.material.get());
    return out;
}

// The files of the scene's meshes, of its materials' textures (not those a
// mesh file embeds, nor cube maps' faces) and of its environment, by
// canonical path.
std::set<fs::path> asset_files(const Scene& scene) {
    std::set<fs::path> out;
    const auto add = [&](const std::string& source) {
        std::error_code ec;
        if (fs::is_regular_file(source, ec)) out.insert(canonical_or_same(source));
    };
    for (const Object& o : scene.objects)
        if (o.mesh) add(o.mesh->source);
    for (const Material* m : materials_of(scene))
        for (const TextureBinding& b : m->textures)
            if (b.texture && b.texture->faces == 1) add(b.texture->source);
    for (const fs::path& file : scene.environment.settings.files) add(file.string());
    return out;
}

}  // namespace

HotReload::HotReload(PluginRegistry& registry, Scene& scene)
    : HotReload(registry, scene, Options{}) {}

HotReload::HotReload(PluginRegistry& registry, Scene& scene, Options options)
    : registry_(registry), scene_(scene), options_(options), watcher_(options.watcher) {
    watch_scene(true);
}

void HotReload::watch_scene(bool loaded_now) {
    const fs::path scene_file = canonical_or_same(scene_.source);
    watcher_.watch(scene_file.parent_path());
    remember(scene_file, loaded_now);
    for (const auto& [file, material] : scene_.material_files) {
        watcher_.watch(file.parent_path());
        remember(file, loaded_now);
    }
    assets_ = asset_files(scene_);
    for (const fs::path& file : assets_) {
        watcher_.watch(file.parent_path());
        remember(file, loaded_now);
    }
    for (const fs::path& folder : registry_.search_path()) watcher_.watch(folder);
    for (const Material* m : materials_of(scene_))
        if (m->plugin) remember(canonical_or_same(m->plugin->origin()), loaded_now);
    for (const PostPass& p : scene_.post)
        if (p.plugin) remember(canonical_or_same(p.plugin->origin()), loaded_now);
}

void HotReload::remember(const fs::path& path, bool loaded_now) {
    if (!loaded_now && content_.count(path)) return;
    if (const std::optional<uint64_t> digest = file_digest(path)) content_[path] = *digest;
}

bool HotReload::unchanged(const fs::path& path, std::optional<uint64_t> digest) const {
    const auto kept = content_.find(path);
    return digest && kept != content_.end() && kept->second == *digest;
}

void HotReload::report(ReloadEvent::Kind kind, std::string subject, std::string message) {
    const ReloadEvent e{kind, std::move(subject), std::move(message)};
    if (e.refused()) spdlog::error("hot reload: {}", e.message);
    else spdlog::info("hot reload: {}", e.message);
    events_.push_back(e);
}

std::vector<ReloadEvent> HotReload::take_events() {
    std::vector<ReloadEvent> out;
    out.swap(events_);
    return out;
}

// Records a changed file; it is applied once it has kept its size and time
// for `settle`.
void HotReload::note(const fs::path& path) {
    std::error_code ec;
    Pending p;
    p.size = fs::file_size(path, ec);
    p.time = fs::last_write_time(path, ec);
    p.since = std::chrono::steady_clock::now();
    if (ec) pending_.erase(path);  // removed: keep what is loaded
    else pending_[path] = p;
}

bool HotReload::update() {
    for (const fs::path& path : watcher_.take_changes()) note(path);
    const auto now = std::chrono::steady_clock::now();
    std::vector<fs::path> settled;
    for (auto& [path, p] : pending_) {
        std::error_code ec;
        const uintmax_t size = fs::file_size(path, ec);
        const fs::file_time_type time = fs::last_write_time(path, ec);
        if (ec) continue;
        if (size != p.size || time != p.time) {
            p = {size, time, now};  // still being written
        } else if (now - p.since >= options_.settle) {
            // A plugin a linker has paused in the middle of writing is not
            // refused (and reported) until it has not changed for a while.
            if (path.extension() == ".so" && !plugin_file_complete(path) &&
                fs::file_time_type::clock::now() - time < options_.unfinished) {
                p.since = now;
                continue;
            }
            settled.push_back(path);
        }
    }
    bool changed = false;
    for (const fs::path& path : settled) {
        pending_.erase(path);
        if (const auto own = ours_.find(path); own != ours_.end()) {
            std::error_code ec;
            const bool same = fs::file_size(path, ec) == own->second.first &&
                              fs::last_write_time(path, ec) == own->second.second && !ec;
            ours_.erase(own);
            if (same) continue;  // what memory already holds
        }
        const std::optional<uint64_t> digest = file_digest(path);
        if (unchanged(path, digest)) {  // what memory already holds
            spdlog::info("hot reload: {} was written again with the content already loaded; "
                         "nothing to reload", path.string());
            if (path == canonical_or_same(scene_.source)) scene_failed_ = false;
            continue;
        }
        const size_t before = events_.size();
        changed |= apply(path);
        const bool refused = std::any_of(events_.begin() + ptrdiff_t(before), events_.end(),
                                         [](const ReloadEvent& e) { return e.refused(); });
        if (digest && events_.size() > before && !refused) content_[path] = *digest;
    }
    return changed;
}

void HotReload::written_by_us(const fs::path& file) {
    std::error_code ec;
    const fs::path path = canonical_or_same(file);
    // A change by someone else still settling is not ours to pass over.
    if (pending_.count(path)) return;
    const uintmax_t size = fs::file_size(path, ec);
    const fs::file_time_type time = fs::last_write_time(path, ec);
    if (!ec) ours_[path] = {size, time};
    // Memory holds what was written: that is the content to tell changes by.
    if (const std::optional<uint64_t> digest = file_digest(path)) content_[path] = *digest;
}

bool HotReload::apply(const fs::path& path) {
    if (path == canonical_or_same(scene_.source)) return reload_scene();
    if (scene_.material_files.count(path)) return reload_material(path);
    if (assets_.count(path)) return reload_asset(path);
    const std::string name = path.stem().string();
    if (path.extension() == ".so" && canonical_or_same(registry_.locate(name)) == path)
        return reload_plugin(name);
    return false;
}

bool HotReload::reload_plugin(const std::string& name) {
    if (!registry_.is_loaded(name)) {
        report(ReloadEvent::Kind::plugin_added, name, "shader '" + name + "' is now available");
        return scene_failed_ && reload_scene();
    }
    const std::string kind = registry_.get(name)->is_post() ? "screen pass" : "shader";
    std::shared_ptr<ShaderPlugin> fresh;
    std::vector<std::pair<Material*, Material>> rebound;
    std::vector<std::pair<PostPass*, PostPass>> repassed;  // the post chain's passes
    try {
        if (const std::string failure = trial_frame(name); !failure.empty()) {
            report(ReloadEvent::Kind::plugin_refused, name,
                   "refused new version of " + kind + " '" + name + "', keeping the old one: " +
                       failure);
            return false;
        }
        fresh = registry_.load_fresh(name);
        for (Material* m : materials_of(scene_)) {
            if (m->shader != name) continue;
            Material copy = *m;
            bind(copy, fresh, textures_);
            rebound.emplace_back(m, std::move(copy));
        }
        for (PostPass& p : scene_.post) {
            if (p.name != name) continue;
            if (!fresh->is_post())
                throw Error(ErrorCode::wrong_type, "it is now a shader, and the scene's post "
                                                   "chain names it as a screen pass");
            PostPass copy = p;
            copy.block = bind_params(copy.params, *fresh, copy.file, textures_).block;
            copy.plugin = fresh;
            repassed.emplace_back(&p, std::move(copy));
        }
    } catch (const Error& e) {
        report(ReloadEvent::Kind::plugin_refused, name,
               "refused new version of " + kind + " '" + name + "', keeping the old one: " +
                   e.what());
        return false;
    }
    registry_.add(fresh);
    for (auto& [material, copy] : rebound) *material = std::move(copy);
    for (auto& [pass, copy] : repassed) *pass = std::move(copy);
    const std::string users = fresh->is_post()
                                  ? std::to_string(repassed.size()) + " pass(es) of the post chain"
                                  : std::to_string(rebound.size()) + " material(s)";
    report(ReloadEvent::Kind::plugin_reloaded, name,
           "reloaded " + std::string(fresh->is_post() ? "screen pass" : "shader") + " '" + name +
               "' (" + users + ") from " + fresh->origin());
    return true;
}

// Why a trial frame with the new version of `name` failed; "" when it
// rendered, or when no material of the scene uses the plugin. facet-sandbox
// loads the scene file with this registry's plugin folders (so the new
// version, which it loads first) and renders it. An Error (a plugin that
// will not load, a schema that no longer fits) is thrown as it was thrown
// there.
std::string HotReload::trial_frame(const std::string& name) {
    const std::vector<Material*> all = materials_of(scene_);
    const bool used =
        std::any_of(all.begin(), all.end(), [&](const Material* m) { return m->shader == name; }) ||
        std::any_of(scene_.post.begin(), scene_.post.end(),
                    [&](const PostPass& p) { return p.name == name; });
    if (!used || options_.trial_time.count() <= 0) return {};
    if (!sandbox_program()) {
        spdlog::warn("hot reload: facet-sandbox is not installed beside this program; shader "
                     "'{}' is loaded without a trial frame", name);
        return {};
    }
    const int width = std::max(1, options_.trial_width);
    std::vector<std::string> args = {canonical_or_same(scene_.source).string(), name,
                                     std::to_string(width)};
    for (const fs::path& folder : registry_.search_path()) args.push_back(folder.string());
    const IsolatedResult r =
        run_sandboxed("trial", args, {memory_budget(), options_.trial_time});
    if (r.end == IsolatedResult::End::finished) return {};
    if (r.end == IsolatedResult::End::error) throw *r.error;
    return "its " + std::to_string(width) + " pixels wide trial frame failed: " + r.output;
}

bool HotReload::reload_material(const fs::path& file) {
    try {
        std::shared_ptr<Material> fresh = load_material(file, registry_, textures_);
        *scene_.material_files.at(file) = std::move(*fresh);
    } catch (const Error& e) {
        report(ReloadEvent::Kind::config_refused, file.string(),
               std::string(e.what()) + " (keeping the previous version)");
        return false;
    }
    watch_scene(false);  // the textures it names now
    report(ReloadEvent::Kind::config_reloaded, file.string(), "reloaded " + file.string());
    return true;
}

// A mesh: the scene read again, whole (the mesh's parts, and the materials
// its file gives them, may have changed). A texture: read again and swapped
// into the materials that use it.
bool HotReload::reload_asset(const fs::path& path) {
    for (const Object& o : scene_.objects)
        if (o.mesh && canonical_or_same(o.mesh->source) == path) return reload_scene(path);
    bool environment = false;  // a file may be the environment and a texture too
    for (const fs::path& file : scene_.environment.settings.files)
        if (canonical_or_same(file) == path) {
            environment = reload_environment(path);
            break;
        }
    return reload_texture(path) || environment;
}

bool HotReload::reload_environment(const fs::path& path) {
    std::shared_ptr<const EnvironmentMaps> fresh;
    try {
        fresh = load_environment(scene_.environment.settings);
    } catch (const Error& e) {
        report(ReloadEvent::Kind::config_refused, path.string(),
               std::string(e.what()) + " (keeping the previous environment)");
        return false;
    }
    scene_.environment.maps = std::move(fresh);
    report(ReloadEvent::Kind::config_reloaded, path.string(),
           "reloaded environment " + path.string());
    return true;
}

bool HotReload::reload_texture(const fs::path& path) {
    std::vector<TextureBinding*> uses;
    size_t materials = 0;
    for (Material* m : materials_of(scene_)) {
        bool used = false;
        for (TextureBinding& b : m->textures) {
            if (!b.texture || b.texture->faces != 1 ||
                canonical_or_same(b.texture->source) != path)
                continue;
            uses.push_back(&b);
            used = true;
        }
        materials += used;
    }
    if (uses.empty()) return false;
    std::shared_ptr<const Texture> fresh[2];  // linear, sRGB: each loaded before either is used
    try {
        for (TextureBinding* b : uses) {
            const bool srgb = b->texture->srgb;
            if (!fresh[srgb]) fresh[srgb] = load_texture(path, srgb);
        }
    } catch (const Error& e) {
        report(ReloadEvent::Kind::config_refused, path.string(),
               std::string(e.what()) + " (keeping the previous version)");
        return false;
    }
    textures_.forget(path);  // a material read again later reads the file as it is now
    for (TextureBinding* b : uses) b->texture = fresh[b->texture->srgb];
    report(ReloadEvent::Kind::config_reloaded, path.string(),
           "reloaded texture " + path.string() + " (" + std::to_string(materials) +
               " material(s))");
    return true;
}

bool HotReload::reload_scene(const fs::path& cause) {
    try {
        Scene fresh = load_scene(scene_.source, registry_);
        fresh.pose(scene_.time);  // an animation goes on where it was
        scene_ = std::move(fresh);
    } catch (const Error& e) {
        scene_failed_ = true;
        report(ReloadEvent::Kind::config_refused, scene_.source.string(),
               std::string(e.what()) + " (keeping the previous version)");
        return false;
    }
    scene_failed_ = false;
    watch_scene(true);  // every file it read is what memory holds now
    report(ReloadEvent::Kind::config_reloaded, scene_.source.string(),
           "reloaded " + scene_.source.string() +
               (cause.empty() ? "" : " (" + cause.string() + " changed)"));
    return true;
}

}  // namespace facet
