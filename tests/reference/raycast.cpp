#include "raycast.hpp"

#include <algorithm>
#include <cmath>

namespace facet::reference {

namespace {

constexpr double kEpsilon = 1e-9;

bool hits_box(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& o,
              const glm::dvec3& inv_d, double t_max) {
    double t0 = 0.0, t1 = t_max;
    for (int k = 0; k < 3; ++k) {
        double a = (lo[k] - o[k]) * inv_d[k], b = (hi[k] - o[k]) * inv_d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return false;
    }
    return true;
}

// A frame with n as its third axis.
glm::dmat3 frame(const glm::dvec3& n) {
    const glm::dvec3 t = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0))
                                                            : glm::cross(n, glm::dvec3(0, 1, 0)));
    return glm::dmat3(t, glm::cross(n, t), n);
}

}  // namespace

// The winding facet culls for a part drawn with material m, as seen through the camera.
uint8_t culled_winding(const Scene& scene, const Material* m) {
    const CullMode mode = m ? m->cull.value_or(scene.settings.cull) : scene.settings.cull;
    if (mode == CullMode::none) return 0;
    const bool drop_front = mode == CullMode::front;
    const bool drop_ccw = drop_front == scene.settings.front_ccw;
    return drop_ccw ? 2 : 1;
}

CameraRays::CameraRays(const Scene& scene) {
    const RenderSettings& s = scene.settings;
    inverse_ = glm::inverse(
        glm::dmat4(scene.camera.projection(float(s.width) / float(s.height), s.reversed_z)) *
        glm::dmat4(scene.camera.view()));
    width_ = s.width;
    height_ = s.height;
    near_ = s.reversed_z ? 1.0 : 0.0;
    far_ = 1.0 - near_;
}

void CameraRays::ray(double x, double y, glm::dvec3& origin, glm::dvec3& dir) const {
    const glm::dvec2 ndc(x / width_ * 2.0 - 1.0, 1.0 - y / height_ * 2.0);
    const glm::dvec4 a = inverse_ * glm::dvec4(ndc, near_, 1.0);
    const glm::dvec4 b = inverse_ * glm::dvec4(ndc, far_, 1.0);
    origin = glm::dvec3(a) / a.w;
    dir = glm::dvec3(b) / b.w - origin;
}

RayCaster::RayCaster(const Scene& scene) {
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& o = scene.objects[i];
        if (!o.visible || !o.mesh) continue;
        const Mesh& mesh = *o.mesh;
        for (size_t p = 0; p < mesh.part_count(); ++p) {
            const glm::dmat4 m(o.part_matrix(p));
            const MeshPart part = mesh.part(p);
            const Cull cull = Cull(culled_winding(scene, o.material_of(p)));
            for (size_t t = part.first_index; t < part.first_index + part.index_count; t += 3) {
                glm::dvec3 v[3];
                for (int k = 0; k < 3; ++k)
                    v[k] = glm::dvec3(
                        m * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[t + k]]), 1));
                triangles_.push_back({v[0], v[1], v[2], int(i), int(p), int(t / 3), cull});
            }
        }
    }
    nodes_.reserve(2 * triangles_.size() + 1);
    if (!triangles_.empty()) build(0, int(triangles_.size()));
}

int RayCaster::build(int first, int count) {
    Node node{glm::dvec3(1e300), glm::dvec3(-1e300), first, count, -1, -1};
    for (int i = first; i < first + count; ++i)
        for (const glm::dvec3& p : {triangles_[i].a, triangles_[i].b, triangles_[i].c}) {
            node.lo = glm::min(node.lo, p);
            node.hi = glm::max(node.hi, p);
        }
    const int index = int(nodes_.size());
    nodes_.push_back(node);
    if (count <= 4) return index;
    const glm::dvec3 size = node.hi - node.lo;
    const int axis = size.x > size.y ? (size.x > size.z ? 0 : 2) : (size.y > size.z ? 1 : 2);
    auto centre = [axis](const Triangle& t) { return t.a[axis] + t.b[axis] + t.c[axis]; };
    const auto begin = triangles_.begin() + first;
    std::nth_element(begin, begin + count / 2, begin + count,
                     [&](const Triangle& x, const Triangle& y) { return centre(x) < centre(y); });
    const int left = build(first, count / 2);
    const int right = build(first + count / 2, count - count / 2);
    nodes_[index].count = 0;
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
}

// Moller-Trumbore, in the form where the determinant's sign is the
// winding the ray sees: det > 0 when it sees a, b, c counter-clockwise.
int RayCaster::trace(const glm::dvec3& o, const glm::dvec3& d, double& t_max, double& u_out,
                     double& v_out, bool cull, bool any) const {
    if (nodes_.empty()) return -1;
    const glm::dvec3 inv_d = 1.0 / d;
    int best = -1;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes_[size_t(stack[--top])];
        if (!hits_box(n.lo, n.hi, o, inv_d, t_max)) continue;
        if (n.count == 0) {
            stack[top++] = n.left;
            stack[top++] = n.right;
            continue;
        }
        for (int i = n.first; i < n.first + n.count; ++i) {
            const Triangle& tri = triangles_[size_t(i)];
            const glm::dvec3 e1 = tri.b - tri.a, e2 = tri.c - tri.a;
            const glm::dvec3 p = glm::cross(d, e2);
            const double det = glm::dot(e1, p);
            if (std::abs(det) < 1e-300) continue;
            if (cull && tri.cull == (det > 0 ? drop_ccw : drop_cw)) continue;
            const double inv = 1.0 / det;
            const glm::dvec3 s = o - tri.a;
            const double u = glm::dot(s, p) * inv;
            if (u < 0.0 || u > 1.0) continue;
            const glm::dvec3 q = glm::cross(s, e1);
            const double v = glm::dot(d, q) * inv;
            if (v < 0.0 || u + v > 1.0) continue;
            const double t = glm::dot(e2, q) * inv;
            if (!(t > kEpsilon && t < t_max)) continue;
            t_max = t;
            u_out = u;
            v_out = v;
            best = i;
            if (any) return best;
        }
    }
    return best;
}

std::optional<Hit> RayCaster::first_hit(const glm::dvec3& o, const glm::dvec3& d, double t_max,
                                        bool cull) const {
    double u = 0, v = 0;
    const int best = trace(o, d, t_max, u, v, cull, false);
    if (best < 0) return std::nullopt;
    const Triangle& tri = triangles_[size_t(best)];
    glm::dvec3 n = glm::normalize(glm::cross(tri.b - tri.a, tri.c - tri.a));
    const bool ccw = glm::dot(n, d) < 0;
    if (!ccw) n = -n;
    return Hit{t_max, o + d * t_max, n, tri.object, tri.part, tri.index, u, v, ccw};
}

bool RayCaster::occluded(const glm::dvec3& o, const glm::dvec3& d, double t_max) const {
    double u, v;
    return trace(o, d, t_max, u, v, false, true) >= 0;
}

void RayCaster::camera_ray(const Scene& scene, double x, double y, glm::dvec3& origin,
                           glm::dvec3& dir) {
    CameraRays(scene).ray(x, y, origin, dir);
}

std::optional<Hit> RayCaster::camera_hit(const Scene& scene, double x, double y) const {
    glm::dvec3 o, d;
    camera_ray(scene, x, y, o, d);
    return first_hit(o, d, 1.0, true);  // t = 1 is the far plane
}

bool RayCaster::lit(const Light& light, const glm::dvec3& p, const glm::dvec3& n) const {
    const glm::dvec3 start = p + n * 1e-6;
    if (light.type == LightType::directional)
        return !occluded(start, -glm::normalize(glm::dvec3(light.direction)), 1e30);
    const glm::dvec3 to = glm::dvec3(light.position) - start;
    return !occluded(start, to, 1.0 - 1e-9);
}

bool RayCaster::open(const glm::dvec3& p, const glm::dvec3& n, double radius, double u,
                     double v) const {
    // Malley's method: a uniform point on the unit disc, lifted to the
    // hemisphere, is cosine-distributed.
    const double r = std::sqrt(u), phi = 2.0 * M_PI * v;
    const glm::dvec3 d = frame(n) * glm::dvec3(r * std::cos(phi), r * std::sin(phi),
                                              std::sqrt(1.0 - u));
    return !occluded(p + n * 1e-6, d, radius);
}

double RayCaster::ambient_visibility(const glm::dvec3& p, const glm::dvec3& n, double radius,
                                     int rays) const {
    const int side = std::max(1, int(std::lround(std::sqrt(double(rays)))));
    int count = 0;
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i)  // stratified
            count += open(p, n, radius, (i + 0.5) / side, (j + 0.5) / side);
    return double(count) / double(side * side);
}

}  // namespace facet::reference
