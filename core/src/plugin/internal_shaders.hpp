// Shaders the core itself uses for its passes, written with the same SDK as
// any plugin but compiled into the core.
#pragma once

#include "facet/plugin.hpp"

#include <facet/shader.hpp>

#include <memory>

namespace facet::internal {

// Depth only: shadow maps.
struct DepthOnly {
    FACET_VARYINGS()
    FACET_PARAMS()
    static constexpr const char* name = "facet_depth_only";
    static constexpr const char* version = "internal";
    static constexpr uint32_t needs = 0;
    static Varyings vertex(const sdk::VertexIn& in, const sdk::Draw& d, const Params&,
                           sdk::Vec4& clip) {
        clip = d.model_view_projection() * sdk::Vec4(in.position, 1.0f);
        return {};
    }
    static sdk::Vec4 fragment(const Varyings&, sdk::Fragment&, const sdk::Draw&, const Params&) {
        return sdk::Vec4(sdk::splat(0.0f));
    }
};

template <class S>
const ShaderPlugin& plugin() {
    static const std::shared_ptr<ShaderPlugin> p =
        ShaderPlugin::from_descriptor(sdk::describe<S>(), "facet core");
    return *p;
}

}  // namespace facet::internal
