// An object's clip and morph weights, from the scene (scene_clip.hpp).
#include "assets/scene_clip.hpp"

#include <cmath>
#include <set>
#include <string>

namespace facet {

namespace {

std::string clip_list(const Mesh& mesh) {
    std::string out;
    for (size_t i = 0; i < mesh.clips.size(); ++i)
        out += (i ? ", " : "") + std::to_string(i) + " '" + mesh.clips[i].name + "'";
    return out.empty() ? "none" : out;
}

std::set<std::string> target_names(const Mesh& mesh) {
    std::set<std::string> names;
    for (const PartDeformation& d : mesh.deformations)
        for (const MorphTarget& t : d.targets) names.insert(t.name);
    return names;
}

}  // namespace

int read_clip(const yaml::Context& ctx, const YAML::Node& node, const Mesh& mesh) {
    const std::string text = yaml::as<std::string>(ctx, node);
    if (text == "none") return -1;
    int clip = -1;
    if (yaml::is_integer_text(text) && yaml::parse_number(node)) {
        const double index = *yaml::parse_number(node);
        if (index >= 0.0 && index < double(mesh.clips.size())) clip = int(index);
    } else {
        clip = find_clip(mesh, text);
    }
    yaml::ensure(clip >= 0, ctx, node, ErrorCode::config_invalid,
                 "'" + text + "' is no clip of " + mesh.source + " (its clips: " +
                     clip_list(mesh) + "; or none)");
    return clip;
}

int choose_clip(const yaml::Context& ctx, const YAML::Node& animate, const YAML::Node& scene_clip,
                const Mesh& mesh) {
    if (animate && animate["clip"]) return read_clip(ctx, animate["clip"], mesh);
    if (mesh.clips.empty()) return -1;
    if (scene_clip) return read_clip(ctx, scene_clip, mesh);
    return 0;
}

std::vector<WeightOverride> read_weights(const yaml::Context& ctx, const YAML::Node& node,
                                         const Mesh& mesh) {
    yaml::check_map(ctx, node, "weights");
    const std::set<std::string> names = target_names(mesh);
    std::vector<WeightOverride> out;
    for (const auto& entry : node) {
        const std::string name = entry.first.Scalar();
        if (!names.count(name)) {
            std::string list;
            for (const std::string& n : names) list += (list.empty() ? "'" : ", '") + n + "'";
            throw yaml::error(ctx, entry.first, ErrorCode::config_invalid,
                              "'" + name + "' is no morph target of " + mesh.source +
                                  " (its targets: " + (list.empty() ? "none" : list) + ")");
        }
        const float w = yaml::as<float>(ctx, entry.second);
        yaml::ensure(std::abs(w) <= 10.0f, ctx, entry.second, ErrorCode::out_of_range,
                     "a morph weight must lie within [-10, 10]");
        out.push_back({name, w});
    }
    return out;
}

}  // namespace facet
