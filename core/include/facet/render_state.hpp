// The fixed-function modes a material or a scene chooses and the pipeline
// applies (PipelineState, facet/pipeline.hpp): face culling, blending and
// the depth test. Plain enums, so that assets name them without depending
// on the pipeline.
#pragma once

namespace facet {

enum class CullMode { none, back, front };
enum class BlendMode { opaque, alpha, additive };
enum class DepthCompare { never, less, less_equal, greater, greater_equal, equal, always };

}  // namespace facet
