// Parsing of the values the command-line tools share (facet-render,
// facet-view, facet-bench), so each tool reads them the same way.
#pragma once

#include "facet/scene.hpp"

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace facet {

// "1280x720" -> {1280, 720}; nothing if malformed or a side is outside
// 1..Framebuffer::kMaxSize.
std::optional<glm::ivec2> parse_size(std::string_view text);

// "px,py,pz,tx,ty,tz" or "px,py,pz,tx,ty,tz,fov": `base` with the position,
// target and (optionally) vertical field of view replaced; nothing if
// malformed, non-finite, looking along the camera's up axis (or with the
// target on the position), or with fov outside (0, 180).
std::optional<Camera> parse_camera(std::string_view text, const Camera& base);

// --max-memory: sets the memory budget (facet/memory.hpp) from `text`, or
// when it is empty from FACET_MAX_MEMORY, if set, and caps the address
// space to match (cap_address_space, with room for `threads` render
// threads; 0: one per hardware thread). False, having logged which of the
// two is wrong and what was expected, when it is no size.
bool apply_max_memory(std::string_view text, int threads);

// What to say when an allocation failed (std::bad_alloc): the address
// space cap, if one is set, else how to set the budget.
std::string out_of_memory_text();

}  // namespace facet
