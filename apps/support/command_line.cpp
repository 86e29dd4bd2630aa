#include "facet/command_line.hpp"

#include "facet/framebuffer.hpp"
#include "facet/memory.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace facet {

namespace {

// Comma-separated finite numbers; nothing if any field is not one.
std::optional<std::vector<double>> numbers(std::string_view text) {
    std::vector<double> out;
    const std::string s(text);
    size_t at = 0;
    while (at <= s.size()) {
        const size_t comma = std::min(s.find(',', at), s.size());
        const std::string field = s.substr(at, comma - at);
        char* end = nullptr;
        const double v = std::strtod(field.c_str(), &end);
        if (field.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
        out.push_back(v);
        at = comma + 1;
    }
    return out;
}

// One side of a size: decimal digits only (no sign, space or exponent),
// 1..Framebuffer::kMaxSize; digits are checked before any arithmetic, so
// that no number wraps around.
std::optional<int> side(std::string_view digits) {
    if (digits.empty() || digits.size() > 5) return std::nullopt;
    int value = 0;
    for (const char c : digits) {
        if (c < '0' || c > '9') return std::nullopt;
        value = value * 10 + (c - '0');
    }
    if (value < 1 || value > Framebuffer::kMaxSize) return std::nullopt;
    return value;
}

}  // namespace

std::optional<glm::ivec2> parse_size(std::string_view text) {
    const size_t x = text.find_first_of("xX");
    if (x == std::string_view::npos) return std::nullopt;
    const std::optional<int> width = side(text.substr(0, x)), height = side(text.substr(x + 1));
    if (!width || !height) return std::nullopt;
    return glm::ivec2(*width, *height);
}

std::optional<Camera> parse_camera(std::string_view text, const Camera& base) {
    const auto n = numbers(text);
    if (!n || (n->size() != 6 && n->size() != 7)) return std::nullopt;
    Camera c = base;
    c.position = glm::vec3((*n)[0], (*n)[1], (*n)[2]);
    c.target = glm::vec3((*n)[3], (*n)[4], (*n)[5]);
    if (n->size() == 7) c.fov_y = float((*n)[6]);
    const glm::vec3 forward = c.target - c.position;
    if (glm::length(glm::cross(forward, c.up)) <= 1e-6f * glm::length(forward) ||
        !(c.fov_y > 0.0f && c.fov_y < 180.0f))
        return std::nullopt;  // no view direction, looking along up, or a bad fov
    return c;
}

bool apply_max_memory(std::string_view text, int threads) {
    const char* env = std::getenv("FACET_MAX_MEMORY");
    const bool from_env = text.empty() && env && *env;
    if (from_env) text = env;
    if (text.empty()) return true;
    const std::optional<uint64_t> bytes = parse_memory_size(text);
    if (!bytes) {
        spdlog::error("{}: expected a size such as 8G, 8GB, 8GiB, 512M or 1000000, got '{}'",
                      from_env ? "FACET_MAX_MEMORY" : "--max-memory", text);
        return false;
    }
    set_memory_budget(*bytes);
    // What the budget does not see (a plugin's allocations) stops at the cap.
    if (const uint64_t cap = cap_address_space(threads))
        spdlog::debug("address space capped at {} (the budget, {}, and what the program maps)",
                      memory_text(cap), memory_text(*bytes));
    return true;
}

std::string out_of_memory_text() {
    if (const uint64_t cap = address_space_cap())
        return "out of memory: the address space is capped at " + memory_text(cap) +
               " (the memory budget, " + memory_text(memory_budget()) +
               ", and what the program maps; --max-memory or FACET_MAX_MEMORY sets it)";
    return "out of memory; --max-memory (or FACET_MAX_MEMORY) sets the budget that facet "
           "checks sizes against";
}

}  // namespace facet
