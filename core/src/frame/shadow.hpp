// Shadow maps.
//
// Takes: the scene, and the objects that cast shadows.
// Gives: one depth map per shadow-casting directional or spot light, seen
// from the light, with the facet_shadow_map that describes it to shaders;
// a map whose light, casters and (directional) fitted bounds did not change
// since the last frame is kept, not drawn again.
// A directional light's map is orthographic, fitted around the camera's view
// frustum (up to render.shadow_distance) and deep enough to hold every
// caster; a spot light's is perspective, over its cone; a point light's is a
// cube of six perspective faces of 90 degrees, each drawn with a margin as
// wide as the distances' border, so that a filter kernel near a face's edge
// reads what lies past it. A light's shadow_map_size, if it has one,
// overrides the scene's.
#pragma once

#include "facet/framebuffer.hpp"
#include "facet/pipeline.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"

#include <facet/shader_abi.h>

#include <memory>
#include <vector>

namespace facet {

// What a map's depth is a function of: its projection and size, and each
// caster it drew (its mesh, held so that a new mesh never takes an old
// one's address, and its transform; for a cutout, whose shader runs to
// discard what its alpha cuts away, its material's parameters, which a
// reload replaces). Lights and cameras matter only through the projection.
struct ShadowMapKey {
    struct Caster {
        std::shared_ptr<const Mesh> mesh;
        const MeshPart* part = nullptr;    // of mesh, or null: all of it
        glm::mat4 model;
        const Material* cutout = nullptr;  // the material, if it discards
        std::shared_ptr<const ParamBlock> params;  // cutout: its parameters
        bool operator==(const Caster& o) const {
            return mesh == o.mesh && part == o.part && model == o.model && cutout == o.cutout && params == o.params;
        }
    };
    int size = 0;
    glm::mat4 view_projection{0.0f};
    std::vector<Caster> casters;
    // The scene's time, which a cutout's shader sees (and may cut by); 0
    // when no caster runs its shader.
    float time = 0.0f;
    bool operator==(const ShadowMapKey& o) const = default;
};

// The maps of one frame, as shaders receive them: `by_light` holds each
// light's shadow (facet_shadow), pointing into `faces`, where each map is
// described with its 16-bit distances from the light and the planes that
// bound them tile by tile. What each map (or cube face) was drawn from is
// by slot, in the order of the lights: its depth buffer, its distances with
// their border, their planes, and the key that describes them. Storage is
// reused from frame to frame.
struct ShadowMaps {
    std::vector<facet_shadow_map> faces;  // the maps, a cube's six together
    std::vector<facet_shadow> by_light;   // [lights]: each light's maps in `faces`
    std::vector<size_t> first_face;       // [lights]: where they start there
    Framebuffer depth;             // scratch: the map being drawn, before its distances
    std::vector<int> drawn_size;   // [slots]: the texels a side each was drawn at
    std::vector<std::vector<uint16_t>> distance_texels;
    std::vector<std::vector<float>> plane_tiles;
    std::vector<ShadowMapKey> key;
    ShadowMapKey next;               // scratch: this frame's key of one map
    std::vector<glm::vec3> corners;  // scratch for fitting
};

// Makes one map per light with casts_shadow that is directional or spot,
// and a cube per point light with casts_shadow; afterwards maps.by_light
// has a record for each of the scene's lights. Each map draws the casters its
// projection can see, and is drawn again only when its key changed:
// stats.shadow_passes counts the maps drawn, shadow_maps_reused those kept
// from an earlier frame, and shadow_casters_culled the casters a drawn map
// left out. Throws Error(over_budget), drawing nothing, when the maps
// need more memory than the budget (facet/memory.hpp).
void render_shadow_maps(const Scene& scene, const std::vector<DrawItem>& casters,
                        Pipeline& pipeline, ShadowMaps& maps, FrameStats& stats);

}  // namespace facet
