// Scenes: camera, lights, objects and render settings, from YAML.
//
//     camera: {position: [0, 1, 3], target: [0, 0.5, 0], fov_y: 45, near: 0.1, far: 100}
//     render: {size: [960, 540], clear_color: [0.05, 0.05, 0.08, 1], cull: back,
//              shadow_map_size: 2048, shadow_distance: 20, msaa: 4, subpixel_bits: 8,
//              wireframe: false, shadows: true, ao: true, ao_radius: 0.5,
//              ao_samples: 8, color_format: srgb8}
//     plugin_paths: [my-shaders]          # extra plugin folders, relative to this file
//     lights:
//       - {type: directional, direction: [-1, -2, -1], color: [1, 1, 1], intensity: 2}
//       - {type: point, position: [0, 2, 0], casts_shadow: true, shadow_map_size: 512}
//         # also spot (spot_inner, spot_outer), range, attenuation; a light that
//         # casts shadows gets a map (a cube of six for a point light) of its own
//         # shadow_map_size, or the scene's
//     environment: {file: sky.hdr, rotation: 90, intensity: 1, use: both}
//                                         # an image all around the scene, behind it
//                                         # and lighting it (facet/environment_map.hpp)
//     post:                               # screen passes, in order (post.hpp in the SDK)
//       - {pass: bloom, threshold: 1, intensity: 0.08}
//       - {pass: tonemap, operator: aces, exposure: 0.5}
//     objects:
//       - name: spot
//         mesh: ../assets/spot/spot.obj   # relative to this file
//         material: materials/spot.yaml   # a file, or an inline map like a material file
//         materials:                      # per part (Mesh::parts), by the part's name
//           visor: materials/glass.yaml   # or by the name of the file's material,
//                                         # for every part drawn with it
//         position: [0, 0, 0]
//         rotation: [0, 30, 0]            # Euler degrees (X, then Y, then Z), or
//                                         # {axis: [0, 1, 0], angle: 30}
//         scale: 1                        # or [sx, sy, sz]
//         animate: {spin: 45}             # tracks and spins: facet/animation.hpp,
//                                         # which also has the camera's and the
//                                         # scene's `animation:` time line
//
// Every error names the file, line and column. Unknown keys are errors, so a
// typo never passes silently.
#pragma once

#include "facet/animation.hpp"
#include "facet/environment_map.hpp"
#include "facet/framebuffer.hpp"
#include "facet/material.hpp"
#include "facet/math.hpp"
#include "facet/mesh.hpp"
#include "facet/render_state.hpp"

#include <glm/glm.hpp>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace facet {

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 3.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    bool orthographic = false;
    float fov_y = 45.0f;         // degrees, perspective
    float ortho_height = 2.0f;   // world units, orthographic
    float near = 0.1f;
    float far = 100.0f;

    glm::mat4 view() const;
    glm::mat4 projection(float aspect, bool reversed_z) const;
};

enum class LightType { directional, point, spot };

struct Light {
    std::string name;  // as the file gives it, or empty: what embedding APIs find it by
    LightType type = LightType::directional;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  // normalised by the loader
    glm::vec3 color{1.0f};                   // linear RGB
    float intensity = 1.0f;
    float range = 0.0f;                      // 0: unlimited
    glm::vec3 attenuation{1.0f, 0.0f, 0.0f}; // constant, linear, quadratic
    float spot_inner = 20.0f;                // degrees, half-angles
    float spot_outer = 30.0f;
    bool casts_shadow = false;  // a directional or spot light's map, a point light's cube
    int shadow_map_size = 0;    // texels per side of its map (each cube face); 0: the scene's
};

struct RenderSettings {
    int width = 960;
    int height = 540;
    glm::vec4 clear_color{0.0f, 0.0f, 0.0f, 1.0f};  // linear
    uint8_t clear_stencil = 0;  // where a material uses the stencil buffer
    bool reversed_z = true;
    // The depth a target is cleared to, which means nothing was drawn.
    float far_depth() const { return reversed_z ? 0.0f : 1.0f; }
    DepthCompare depth_compare = DepthCompare::greater_equal;  // matches reversed_z
    CullMode cull = CullMode::back;
    bool front_ccw = true;  // counter-clockwise triangles (as seen) face the viewer
    // Texels per side of each shadow map, 16..8192 (rounded up to a multiple of 16).
    int shadow_map_size = 2048;
    float shadow_distance = 0.0f;  // directional shadows cover the view up to here; 0: far
    int msaa = 1;                  // samples per pixel: 1, 2, 4 or 8
    // The colour target (framebuffer.hpp): 8-bit sRGB, as a display or a
    // PNG takes it, or float (rgba16f, rgba32f) for HDR and accuracy work.
    // Shading and blending are in linear light either way.
    ColorFormat color_format = ColorFormat::srgb8;
    int subpixel_bits = 8;         // vertex snapping precision, 1..8 bits below the pixel
    bool wireframe = false;        // each triangle part's wire over it (PipelineState::wireframe)
    bool shadows = true;           // false: no shadow passes; shaders see no shadow maps
    bool ao = true;                // false: no AO passes; shaders see full visibility
    // AO computed at half the target's size per side and upsampled by depth
    // (ao_resolution: half), or at every pixel (full).
    bool ao_half_resolution = false;
    // The AO pass's reach (world units, > 0) and directions per texel
    // (1..256). One AO pass serves every material that asks for AO.
    float ao_radius = 0.5f;
    int ao_samples = 8;
    // Draw the opaque objects' depth first (no shading), then shade only the
    // fragments that pass depth equal: each pixel is shaded once, whatever
    // the overdraw. Pays for itself with heavy shaders and overdraw.
    bool depth_prepass = false;
    // false: the scene's post chain does not run (what it costs is the
    // difference), and the frame is drawn straight into its target.
    bool post = true;
};

// One screen pass of a scene's post chain: a plugin with a facet_pass_desc
// and the values of its parameters, checked against its schema.
struct PostPass {
    std::string name;                   // the plugin
    std::string file;                   // where the scene names it, for errors
    int line = 0;
    std::vector<MaterialParam> params;  // as written
    std::shared_ptr<ShaderPlugin> plugin;
    std::shared_ptr<const ParamBlock> block;
};

// A part's material as the scene loader found it (Object::material_of).
struct PartMaterial {
    std::shared_ptr<Material> material;  // null: the file has none for the part
    bool from_scene = false;             // the scene's `materials:` names it for the part
};

struct Object {
    std::string name;
    std::shared_ptr<const Mesh> mesh;
    Transform transform;
    // The scene's material for the whole object (`material:`), or null.
    std::shared_ptr<Material> material;
    bool visible = true;
    // Per part of the mesh, in its order: the scene's material for the part,
    // or the file's own (ImportedMaterial, bound). Empty: no part has one.
    std::vector<PartMaterial> part_materials = {};

    // The material part i is drawn with: the scene's for the part, else the
    // scene's for the object, else the file's; null if there is none.
    Material* material_of(size_t part) const;
    // Every material the object's parts are drawn with, each once.
    std::vector<Material*> materials() const;
    // Animation (animation.hpp): Scene::pose sets `transform` to `rest`
    // animated at its time, and `part_poses` to the motion of each part that
    // the mesh file's own node animation moves (empty: none does).
    TransformTracks animation = {};
    Transform rest = {};
    std::vector<glm::mat4> part_poses = {};
    // The mesh file's own animation: the clip that plays (into
    // Mesh::clips; -1: none, the file's nodes stay at rest), and the morph
    // weights the scene sets over the file's (`animate: {clip, weights}`).
    int clip = -1;
    std::vector<WeightOverride> weights = {};
    // The mesh as posed now, when its file deforms a part (a skin, morph
    // targets); null: the mesh as loaded is drawn.
    std::shared_ptr<const Mesh> posed = {};

    // Sets `transform`, `part_poses` and `posed` to their places at time t.
    void pose(double t);
    // The mesh that draws: posed, or as loaded.
    const std::shared_ptr<const Mesh>& drawn_mesh() const { return posed ? posed : mesh; }
    // Where part i is drawn: transform, after the part's own motion.
    glm::mat4 part_matrix(size_t part) const {
        return part_poses.empty() ? transform.matrix() : transform.matrix() * part_poses[part];
    }
    // Draws every part with `m`, forgetting the parts' own materials.
    void use_material(std::shared_ptr<Material> m) {
        material = std::move(m);
        part_materials.clear();
    }

    // pose()'s own: two copies of the mesh that it writes in turn, and the
    // mesh they copy. A pose never writes the copy drawn now, nor one that
    // something else (a shadow map's key) still holds.
    std::shared_ptr<Mesh> pose_buffers[2] = {};
    std::shared_ptr<const Mesh> posed_from = {};
};

struct Scene {
    std::filesystem::path source;
    Camera camera;
    std::vector<Light> lights;
    std::vector<Object> objects;
    std::vector<PostPass> post;  // run in order on the finished frame
    Environment environment;     // none unless the scene has `environment:`
    RenderSettings settings;
    std::vector<std::filesystem::path> plugin_paths;  // absolute
    // The material files the objects use, by canonical path; objects naming
    // the same file share one Material.
    std::map<std::filesystem::path, std::shared_ptr<Material>> material_files;

    // Animation (animation.hpp): the time the scene is posed at (every
    // draw's facet_draw.time), the stretch it plays, and the camera's tracks
    // over its place at rest.
    double time = 0.0;
    Timeline timeline;
    CameraTracks camera_tracks;
    Camera camera_rest;

    // Every material any object is drawn with, each once, in object order.
    std::vector<Material*> materials() const;
    // Sets the time, and the camera and every animated object to their
    // places at that time. A pure function of t and the scene as loaded.
    // Throws Error(out_of_range) for a time that is not finite.
    void pose(double t);
    // A camera put by hand (--camera): it stays, whatever the time.
    void set_camera(const Camera& c) {
        camera = camera_rest = c;
        camera_tracks = {};
    }
    bool animated() const { return timeline.animated(); }
};

// Parses a scene file, loads its meshes, materials and textures, and finds
// its shaders through `registry` (after adding the scene's plugin_paths).
// Throws Error naming file:line:column. Given a model file instead
// (is_model_file), renders it as load_model_scene does.
Scene load_scene(const std::filesystem::path& path, PluginRegistry& registry);

// Whether `path` names a model file: a format the importer reads, not YAML.
bool is_model_file(const std::filesystem::path& path);
// A scene of the model alone, with no scene file: the model with its own
// materials (a grey phong for parts it gives none), its first clip
// playing, lit by a three-light rig, and seen through the file's first
// camera, or framed (frame_object) when it has none. Errors name the model.
Scene load_model_scene(const std::filesystem::path& path, PluginRegistry& registry);
// A camera like `like` (its field of view and projection) that looks at
// `o` from in front, a little right and above, so that its bounds, as
// posed now, fill the view's height; near and far hold them.
Camera framed_camera(const Object& o, const Camera& like);
// The scene's camera framed on object `index` (`camera: {frame: NAME}`);
// its tracks are dropped.
void frame_object(Scene& scene, size_t index);
// The same from YAML text, read as if it were the file `origin` (whose
// folder resolves the files it names, and which errors name; it need not
// exist).
Scene load_scene_text(const std::string& yaml, const std::filesystem::path& origin,
                      PluginRegistry& registry);

// Reads `yaml`, a render map as a scene file writes it ("{shadows: false,
// msaa: 4}"), over `settings`: the keys it names replace their values, the
// others stay. Throws Error naming `origin` (where the text came from) and
// the line and column, and leaves `settings` unchanged, when it is bad.
void apply_render_settings(RenderSettings& settings, const std::string& yaml,
                           const std::string& origin);

// Throws Error(over_budget) when the frame `settings` ask for (its target,
// with its samples, and its 8-bit image) is over the memory budget
// (facet/memory.hpp). Programs check it once the command line has had its
// say (a scene's size may be overridden); Framebuffer::resize checks the
// target itself in any case.
void require_frame_within_budget(const RenderSettings& settings);

// The scene facet-render uses when given none: configs/default.yaml in
// data_dir() (facet/paths.hpp).
std::filesystem::path default_scene_path();

}  // namespace facet
