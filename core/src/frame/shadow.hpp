// Shadow maps.
//
// Takes: the scene, and the objects that cast shadows.
// Gives: one depth map per shadow-casting directional or spot light, seen
// from the light, with the facet_shadow_map that describes it to shaders;
// a map whose light, casters and (directional) fitted bounds did not change
// since the last frame is kept, not drawn again.
// A directional light's map is orthographic, fitted around the camera's view
// frustum (up to render.shadow_distance) and deep enough to hold every
// caster; a spot light's is perspective, over its cone. Point lights cast no
// shadow map (that would take a cube map).
#pragma once

#include "facet/framebuffer.hpp"
#include "facet/pipeline.hpp"
#include "facet/scene.hpp"

#include <facet/shader_abi.h>

#include <memory>
#include <vector>

namespace facet {

// What a map's depth is a function of: its projection and size, and each
// caster it drew (its mesh, held so that a new mesh never takes an old
// one's address, and its transform). Lights and cameras matter only
// through the projection.
struct ShadowMapKey {
    struct Caster {
        std::shared_ptr<const Mesh> mesh;
        glm::mat4 model;
        bool operator==(const Caster& o) const { return mesh == o.mesh && model == o.model; }
    };
    int size = 0;
    glm::mat4 view_projection{0.0f};
    std::vector<Caster> casters;
    bool operator==(const ShadowMapKey& o) const = default;
};

// The maps of one frame: `abi` is the contiguous array shaders receive, and
// abi[i].depth points into depth[i], whose contents key[i] describes;
// `distances` is the same array of maps as 16-bit distances from the light
// (ABI 1.3), each in distance_texels[i], with its border. Storage is reused
// from frame to frame.
struct ShadowMaps {
    std::vector<facet_shadow_map> abi;
    std::vector<facet_shadow_distances> distances;
    std::vector<Framebuffer> depth;
    std::vector<std::vector<uint16_t>> distance_texels;
    std::vector<ShadowMapKey> key;
    ShadowMapKey next;               // scratch: this frame's key of one map
    std::vector<glm::vec3> corners;  // scratch for fitting
};

// Makes one map per light with casts_shadow that is directional or spot;
// afterwards maps.abi holds exactly those. Each map draws the casters its
// projection can see, and is drawn again only when its key changed:
// stats.shadow_passes counts the maps drawn, shadow_maps_reused those kept
// from an earlier frame, and shadow_casters_culled the casters a drawn map
// left out.
void render_shadow_maps(const Scene& scene, const std::vector<const Object*>& casters,
                        Pipeline& pipeline, ShadowMaps& maps, FrameStats& stats);

}  // namespace facet
