#include "support.hpp"

#include <atomic>
#include <chrono>

namespace facet::test {

Mesh make_mesh(std::vector<glm::vec3> positions, std::vector<uint32_t> indices,
               std::vector<glm::vec4> colors) {
    Mesh m;
    m.source = "test";
    m.positions = std::move(positions);
    m.indices = std::move(indices);
    m.colors = std::move(colors);
    m.bounds = compute_bounds(m.positions);
    return m;
}

DrawCall clip_space_call(const Mesh& mesh, const ShaderPlugin& shader) {
    DrawCall call;
    call.mesh = &mesh;
    call.shader = &shader;
    call.state.cull = CullMode::none;
    call.state.depth_compare = DepthCompare::always;
    return call;
}

glm::vec3 window_to_ndc(glm::dvec2 window, int width, int height) {
    return {float(window.x / width * 2.0 - 1.0), float(1.0 - window.y / height * 2.0), 0.5f};
}

std::filesystem::path temp_dir(const std::string& tag) {
    static std::atomic<int> counter{0};
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                ("facet-test-" + tag + "-" + std::to_string(stamp) + "-" +
                                 std::to_string(counter++));
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace facet::test
