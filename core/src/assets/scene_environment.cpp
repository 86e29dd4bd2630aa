// A scene's `environment:` block (scene_environment.hpp).
#include "assets/scene_environment.hpp"

#include <bit>

namespace facet {

namespace {

namespace fs = std::filesystem;

using yaml::ensure;
using yaml::where;

fs::path file_of(const yaml::Context& ctx, const YAML::Node& value, const fs::path& folder) {
    return (folder / yaml::as<std::string>(ctx, value)).lexically_normal();
}

// The settings of the long form.
void read_settings(const yaml::Context& ctx, const YAML::Node& node, const fs::path& folder,
                   EnvironmentSettings& s) {
    yaml::check_map(ctx, node, "environment",
                    {"file", "faces", "rotation", "intensity", "use", "blur", "size", "samples"});
    const YAML::Node file = node["file"], faces = node["faces"];
    ensure(bool(file) != bool(faces), ctx, node, ErrorCode::config_invalid,
           "an environment takes `file` (one equirectangular image) or `faces` (six), one of them");
    if (file) s.files = {file_of(ctx, file, folder)};
    if (faces) {
        yaml::check_sequence(ctx, faces, "faces");
        ensure(faces.size() == 6, ctx, faces, ErrorCode::config_invalid,
               "faces are six files: +X, -X, +Y, -Y, +Z, -Z");
        for (const YAML::Node& f : faces) s.files.push_back(file_of(ctx, f, folder));
    }
    if (const YAML::Node r = node["rotation"])
        s.rotation = r.IsSequence() ? yaml::as<glm::vec3>(ctx, r)
                                    : glm::vec3(0.0f, yaml::as<float>(ctx, r), 0.0f);
    ensure(std::abs(s.rotation.x) <= 36000.0f && std::abs(s.rotation.y) <= 36000.0f &&
               std::abs(s.rotation.z) <= 36000.0f,
           ctx, where(node, "rotation"), ErrorCode::out_of_range,
           "rotation is in degrees, at most 36000 either way");
    yaml::read(ctx, node, "intensity", s.intensity);
    ensure(s.intensity >= 0.0f && s.intensity <= 1e6f, ctx, where(node, "intensity"),
           ErrorCode::out_of_range, "intensity must be 0..1e6");
    if (const YAML::Node use = node["use"])
        s.use = yaml::as_enum<EnvironmentUse>(ctx, use,
                                              {{"both", EnvironmentUse::both},
                                               {"background", EnvironmentUse::background},
                                               {"lighting", EnvironmentUse::lighting}});
    yaml::read(ctx, node, "blur", s.blur);
    ensure(s.blur >= 0.0f && s.blur <= 1.0f, ctx, where(node, "blur"), ErrorCode::out_of_range,
           "blur is a roughness, 0..1 (0: sharp)");
    yaml::read(ctx, node, "size", s.size);
    ensure(s.size == 0 || (s.size >= 8 && s.size <= 2048 && std::has_single_bit(unsigned(s.size))),
           ctx, where(node, "size"), ErrorCode::out_of_range,
           "size is a power of two 8..2048 (texels a side of a cube face), or 0: the image's");
    yaml::read(ctx, node, "samples", s.samples);
    ensure(s.samples >= 1 && s.samples <= 4096, ctx, where(node, "samples"),
           ErrorCode::out_of_range, "samples must be 1..4096 (GGX samples per texel)");
}

}  // namespace

Environment read_environment(const yaml::Context& ctx, const YAML::Node& node,
                             const fs::path& folder) {
    Environment e;
    if (node.IsScalar())
        e.settings.files = {file_of(ctx, node, folder)};
    else
        read_settings(ctx, node, folder, e.settings);
    try {
        e.maps = load_environment(e.settings);
    } catch (const Error& inner) {
        throw yaml::relocated(inner, ctx, node);
    }
    return e;
}

}  // namespace facet
