// Fuzz target: glTF 2.0 and GLB files, end to end as a scene uses them:
// load_mesh() (assimp's glTF reader, then facet's flattening of nodes and
// parts, core/src/assets/mesh.cpp), the materials mapped from the file's
// (mesh_materials.cpp) bound to the build's shaders with their embedded
// images decoded, and the node animation (mesh_animation.cpp).
//
// Input: a flags byte (bit 0: the file is .glb, else .gltf), then the file,
// written to the sandbox (support.hpp). Seeds: fuzz/seeds/gltf/, made by
// fuzz/seeds/make_gltf_seeds.py. As in mesh_import, each input is imported
// in a fork first, and one on which assimp itself crashes is passed over
// (facet's programs import in facet-sandbox, which contains it). The
// memory budget is 4 MiB, for the embedded images.
//
// Checks:
//  - load_mesh() returns a mesh or throws facet::Error with an id mesh.hpp
//    documents;
//  - the mesh keeps mesh.hpp's invariants (check_mesh), and validate_mesh()
//    agrees: parts tile the triangles, material indices are in range;
//  - nodes come after their parents, and in every clip, at times before,
//    inside and past its end, every part's pose is a finite matrix and
//    every deformed part's positions, normals and bounds are finite; each
//    clip's end is finite and not negative;
//  - each material the file gives binds to its shader, with its images,
//    or throws facet::Error; a bound one holds check_bound's rules.
#include "mesh_support.hpp"
#include "support.hpp"

#include "assets/material_yaml.hpp"

#include <facet/error.hpp>
#include <facet/memory.hpp>
#include <facet/mesh.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace facet::fuzz {

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// A posed mesh keeps its vertices, and its positions, normals and bounds
// are finite (a vertex moved past float's range stays at rest).
void check_posed(const Mesh& m, const Mesh& posed) {
    check(posed.positions.size() == m.positions.size() && posed.normals.size() == m.normals.size(),
          "posing changed the vertex count");
    for (const glm::vec3& p : posed.positions) check(finite(p), "a posed position is not finite");
    for (const glm::vec3& n : posed.normals) check(finite(n), "a posed normal is not finite");
    check(finite(posed.bounds.min) && finite(posed.bounds.max), "a posed mesh's bounds are not finite");
}

void check_nodes(const Mesh& m) {
    for (size_t i = 0; i < m.nodes.size(); ++i)
        check(m.nodes[i].parent < int(i), "a node comes before its parent");
    for (const MeshPart& p : m.parts)
        check(p.node >= -1 && p.node < int(m.nodes.size()), "a part's node is out of range");
    check(m.deformations.empty() || m.deformations.size() == m.parts.size(),
          "deformations are not one a part");
    if (m.nodes.empty()) return;
    std::vector<glm::mat4> poses;
    Mesh posed = m;
    // Every clip and none (-1), at times before, inside and past its end.
    for (int clip = -1; clip < int(m.clips.size()); ++clip) {
        const double end = animation_end(m, clip);
        check(std::isfinite(end) && end >= 0.0, "a clip's end is not a finite time");
        for (const double t : {-1.0, 0.0, end * 0.37, end, end + 1.0, 1e9}) {
            pose_parts(m, clip, t, poses);
            check(poses.size() == m.part_count(), "pose_parts gives no pose for some part");
            for (const glm::mat4& pose : poses)
                for (int c = 0; c < 4; ++c)
                    for (int r = 0; r < 4; ++r)
                        check(std::isfinite(pose[c][r]), "a part's pose is not finite");
            pose_mesh(m, clip, t, {}, posed);
            check_posed(m, posed);
        }
    }
}

void check_materials(const Mesh& m) {
    PluginRegistry registry{std::vector<std::filesystem::path>{}};
    add_shaders(registry);
    TextureCache textures;
    for (size_t i = 0; i < m.images.size(); ++i)
        if (m.images[i]) textures.add_encoded(m.source + "#" + std::to_string(i), m.images[i]);
    for (const ImportedMaterial& im : m.materials) {
        if (!im.problem.empty()) continue;  // an error when a part is drawn with it
        std::shared_ptr<Material> material;
        try {
            material = imported_material(im, m.source + ": material '" + im.name + "'",
                                         std::filesystem::path(m.source).parent_path(), registry,
                                         textures);
        } catch (const Error&) {
            continue;
        } catch (const std::exception& e) {
            unexpected("imported_material", e);
        }
        check(material != nullptr, "imported_material returned no material");
        check_bound(*material);
    }
}

}  // namespace

void gltf(const uint8_t* data, size_t size) {
    if (size == 0) return;
    set_memory_budget(uint64_t(4) << 20);
    const char* name = data[0] & 1 ? "input.glb" : "input.gltf";
    const InputFile input(sandbox() / "meshes" / name, data + 1, size - 1);
    const std::shared_ptr<const Mesh> mesh = import_checked(input.path());
    if (!mesh) return;
    check_mesh(*mesh);
    try {
        validate_mesh(*mesh);
    } catch (const Error& e) {
        fail(std::string("a loaded mesh fails validate_mesh: ") + e.what());
    }
    check_nodes(*mesh);
    check_materials(*mesh);
}

}  // namespace facet::fuzz
