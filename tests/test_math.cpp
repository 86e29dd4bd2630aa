// The maths conventions (facet/math.hpp): projections and their depth
// ranges, look_at, model and normal matrices.
#include <facet/math.hpp>

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

using namespace facet;

namespace {

float depth_of(const glm::mat4& proj, float view_z) {
    const glm::vec4 c = proj * glm::vec4(0.0f, 0.0f, view_z, 1.0f);
    return c.z / c.w;
}

}  // namespace

TEST_CASE("projections map near and far to the configured depth range", "[math]") {
    const glm::mat4 rev = perspective(glm::radians(60.0f), 1.5f, 0.5f, 40.0f, true);
    CHECK(depth_of(rev, -0.5f) == Approx(1.0f));
    CHECK(depth_of(rev, -40.0f) == Approx(0.0f).margin(1e-6));
    const glm::mat4 fwd = perspective(glm::radians(60.0f), 1.5f, 0.5f, 40.0f, false);
    CHECK(depth_of(fwd, -0.5f) == Approx(0.0f).margin(1e-6));
    CHECK(depth_of(fwd, -40.0f) == Approx(1.0f));
    const glm::mat4 ortho = orthographic(4.0f, 2.0f, 1.0f, 11.0f, true);
    CHECK(depth_of(ortho, -1.0f) == Approx(1.0f));
    CHECK(depth_of(ortho, -6.0f) == Approx(0.5f));
    CHECK((ortho * glm::vec4(4.0f, 2.0f, -3.0f, 1.0f)).x == Approx(1.0f));
    // Field of view: a point on the top edge of the frustum lands at y = 1.
    const float t = std::tan(glm::radians(30.0f));
    const glm::vec4 top = rev * glm::vec4(0.0f, 2.0f * t, -2.0f, 1.0f);
    CHECK(top.y / top.w == Approx(1.0f));
}

TEST_CASE("look_at and model matrices follow the conventions", "[math]") {
    const glm::mat4 view = look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
    CHECK((view * glm::vec4(0, 0, 0, 1)).z == Approx(-5.0f));   // target straight ahead
    CHECK((view * glm::vec4(1, 0, 0, 1)).x == Approx(1.0f));    // +X to the right
    Transform tr;
    tr.translation = {1, 2, 3};
    tr.rotation = euler_degrees({0, 90, 0});
    tr.scale = {2, 1, 1};
    const glm::vec4 p = tr.matrix() * glm::vec4(1, 0, 0, 1);   // scale, then rotate, then move
    CHECK(p.x == Approx(1.0f).margin(1e-6));
    CHECK(p.z == Approx(1.0f));
    // Normals stay perpendicular to surfaces under non-uniform scale.
    const glm::mat4 squash = glm::scale(glm::mat4(1.0f), glm::vec3(4, 1, 1));
    const glm::vec3 tangent = glm::vec3(squash * glm::vec4(1, -1, 0, 0));
    const glm::vec3 normal = normal_matrix(squash) * glm::vec3(1, 1, 0);
    CHECK(glm::dot(tangent, normal) == Approx(0.0f).margin(1e-6));
}
