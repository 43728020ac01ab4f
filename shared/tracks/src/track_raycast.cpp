#include "track_raycast.hpp"

#include "jetrace/core/track.hpp"

namespace jetrace::detail {

bool raycast(const std::vector<Triangle>& tris, const Vec3& o, const Vec3& d, double& best_t, Vec3& best_n) {
    std::size_t index = 0;
    if (!raycast_index(tris, o, d, best_t, index)) return false;
    best_n = tris[index].normal();
    return true;
}

bool ray_triangle(const Triangle& tri, const Vec3& o, const Vec3& d, double& t) {
    constexpr double kEdge = 1e-9;
    const Vec3 e1 = tri.b - tri.a, e2 = tri.c - tri.a;
    const Vec3 p = d.cross(e2);
    const double det = e1.dot(p);
    if (!(det * det > 1e-24 * e1.squaredNorm() * e2.squaredNorm())) return false;  // parallel
    const double inv = 1.0 / det;
    const Vec3 sv = o - tri.a;
    const double u = sv.dot(p) * inv;
    if (u < -kEdge || u > 1.0 + kEdge) return false;
    const Vec3 q = sv.cross(e1);
    const double v = d.dot(q) * inv;
    if (v < -kEdge || u + v > 1.0 + kEdge) return false;
    t = e2.dot(q) * inv;
    return true;
}

bool raycast_index(const std::vector<Triangle>& tris, const Vec3& o, const Vec3& d, double& best_t,
                   std::size_t& best_index) {
    bool found = false;
    for (std::size_t i = 0; i < tris.size(); ++i) {
        const Triangle& tri = tris[i];
        double t = 0;
        if (tri.degenerate || !ray_triangle(tri, o, d, t)) continue;
        if (t < -1e-9 || (found && t >= best_t)) continue;
        found = true;
        best_t = t;
        best_index = i;
    }
    return found;
}

Rest rest_on_surface(const std::vector<Triangle>& tris, const Vec3& origin, const Vec3& dir, const Vec3& toward,
                     Pose& out) {
    double t = 0;
    Vec3 n = Vec3::Zero();
    if (!raycast(tris, origin, dir, t, n)) return Rest::no_surface;
    if (n.dot(dir) > 0.0) n = -n;
    const Vec3 f = toward - n * toward.dot(n);
    const double len = f.norm();
    if (!(len > 1e-9 * toward.norm()) || !(len > 0.0)) return Rest::bad_forward;
    out.position = origin + dir * t + n * kRest_m;
    out.forward = f / len;
    out.up = n;
    return Rest::ok;
}

}  // namespace jetrace::detail
