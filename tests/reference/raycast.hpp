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
    int part;           // the part of its mesh (Mesh::part)
    int triangle;       // index in that object's mesh (indices 3 * triangle ...)
    double u, v;        // weights of the triangle's second and third vertex
    bool ccw;           // the ray sees the triangle's vertices counter-clockwise
};

// Rays from a scene's camera through window points, from its near plane to
// its far plane (the volume facet's clipper keeps).
class CameraRays {
public:
    explicit CameraRays(const Scene& scene);
    // The ray through window point (x, y): pixel centres are at + 0.5
    // (direction not normalised; t = 1 is the far plane).
    void ray(double x, double y, glm::dvec3& origin, glm::dvec3& dir) const;

private:
    glm::dmat4 inverse_;
    double width_, height_, near_, far_;
};

class RayCaster {
public:
    explicit RayCaster(const Scene& scene);

    // The nearest hit. With `cull`, triangles that the scene's culling (the
    // render setting, or their part's material's override) removes from the
    // camera's view are skipped, as facet's rasterizer skips them; shadow
    // and AO rays see every triangle, as facet's shadow and AO passes do.
    std::optional<Hit> first_hit(const glm::dvec3& origin, const glm::dvec3& dir,
                                 double t_max = 1e30, bool cull = false) const;
    bool occluded(const glm::dvec3& origin, const glm::dvec3& dir, double t_max) const;

    // The ray from the camera through the centre of pixel (x, y) of a
    // width x height image (direction not normalised).
    static void camera_ray(const Scene& scene, double x, double y, glm::dvec3& origin,
                           glm::dvec3& dir);

    // The surface the camera sees at window point (x, y) (pixel centres are
    // at + 0.5), if any, with the scene's culling.
    std::optional<Hit> camera_hit(const Scene& scene, double x, double y) const;

    // Does point p (normal n) see `light`? (Point lights: towards position.)
    bool lit(const Light& light, const glm::dvec3& p, const glm::dvec3& n) const;

    // Fraction of `rays` cosine-weighted directions around n (a stratified
    // set) that travel `radius` from p without a hit.
    double ambient_visibility(const glm::dvec3& p, const glm::dvec3& n, double radius,
                              int rays) const;

    // Does the cosine-weighted direction for the point (u, v) of the unit
    // square, around n, travel `radius` from p without a hit?
    bool open(const glm::dvec3& p, const glm::dvec3& n, double radius, double u, double v) const;

private:
    enum Cull : uint8_t { keep_all, drop_cw, drop_ccw };  // what the camera does not see
    struct Triangle {
        glm::dvec3 a, b, c;
        int object;
        int part;
        int index;  // in the object's mesh
        Cull cull;  // its part's material's
    };
    struct Node {
        glm::dvec3 lo, hi;
        int first, count;  // leaf: triangles [first, first + count); inner: count = 0
        int left, right;
    };
    int build(int first, int count);
    // The nearest hit's triangle (or -1) and its t, u, v; `any` stops at the first.
    int trace(const glm::dvec3& o, const glm::dvec3& d, double& t_max, double& u, double& v,
              bool cull, bool any) const;

    std::vector<Triangle> triangles_;
    std::vector<Node> nodes_;
};

}  // namespace facet::reference
