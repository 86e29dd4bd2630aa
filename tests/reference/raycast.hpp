// An exact ray caster: ground truth for shadows and ambient occlusion
// (tests and benchmarks only; facet itself never traces rays).
//
// It takes the world-space triangles of a scene's visible objects, builds a
// bounding-volume hierarchy (median split), and answers in double precision:
// which surface a camera ray hits, whether a point sees a light (hard
// shadows), and what fraction of cosine-weighted directions above a point
// travel a given distance without hitting anything (ambient occlusion, as
// the AO pass estimates it).
#pragma once

#include <facet/scene.hpp>

#include <glm/glm.hpp>

#include <optional>
#include <vector>

namespace facet::reference {

struct Hit {
    double t;
    glm::dvec3 point;
    glm::dvec3 normal;  // geometric, unit, facing the ray's origin
    int object;         // index in Scene::objects
};

class RayCaster {
public:
    explicit RayCaster(const Scene& scene);

    std::optional<Hit> first_hit(const glm::dvec3& origin, const glm::dvec3& dir,
                                 double t_max = 1e30) const;
    bool occluded(const glm::dvec3& origin, const glm::dvec3& dir, double t_max) const;

    // The ray from the camera through the centre of pixel (x, y) of a
    // width x height image (direction not normalised).
    static void camera_ray(const Scene& scene, double x, double y, glm::dvec3& origin,
                           glm::dvec3& dir);

    // The surface the camera sees at window point (x, y) (pixel centres are
    // at + 0.5), if any.
    std::optional<Hit> camera_hit(const Scene& scene, double x, double y) const;

    // Does point p (normal n) see `light`? (Point lights: towards position.)
    bool lit(const Light& light, const glm::dvec3& p, const glm::dvec3& n) const;

    // Fraction of `rays` cosine-weighted directions around n (a stratified
    // set) that travel `radius` from p without a hit.
    double ambient_visibility(const glm::dvec3& p, const glm::dvec3& n, double radius,
                              int rays) const;

private:
    struct Triangle {
        glm::dvec3 a, b, c;
        int object;
    };
    struct Node {
        glm::dvec3 lo, hi;
        int first, count;  // leaf: triangles [first, first + count); inner: count = 0
        int left, right;
    };
    int build(int first, int count);
    bool intersect(const Triangle& tri, const glm::dvec3& o, const glm::dvec3& d, double t_max,
                   double& t) const;

    std::vector<Triangle> triangles_;
    std::vector<Node> nodes_;
};

}  // namespace facet::reference
