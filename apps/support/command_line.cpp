#include "facet/command_line.hpp"

#include "facet/framebuffer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
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

}  // namespace

std::optional<glm::ivec2> parse_size(std::string_view text) {
    int width = 0, height = 0;
    char x = 0, rest = 0;
    const std::string s(text);
    if (std::sscanf(s.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 ||
        (x != 'x' && x != 'X'))
        return std::nullopt;
    if (width < 1 || height < 1 || width > Framebuffer::kMaxSize || height > Framebuffer::kMaxSize)
        return std::nullopt;
    return glm::ivec2(width, height);
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

}  // namespace facet
