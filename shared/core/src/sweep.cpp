#include "jetrace/core/sweep.hpp"

#include <cmath>

namespace jetrace {

namespace {

// Earliest t in [0, 1] with |m + t d| = r for a sphere that starts outside
// (|m| > r): a point feature (vertex) of the triangle.
bool sweep_point(const Vec3& m, const Vec3& d, double r, double& t_out) {
    const double c = m.squaredNorm() - r * r;
    if (c <= 0.0) return false;  // already touching: the push-out's job
    const double b = m.dot(d);
    if (b >= 0.0) return false;  // moving away
    const double a = d.squaredNorm();
    const double disc = b * b - a * c;
    if (disc < 0.0) return false;
    const double t = (-b - std::sqrt(disc)) / a;
    if (t < 0.0 || t > 1.0) return false;
    t_out = t;
    return true;
}

// Earliest t in [0, 1] at which the centre p0 + t d comes within r of the
// segment [a, a + e] away from its ends (the cylinder around the edge).
bool sweep_edge(const Vec3& p0, const Vec3& d, double r, const Vec3& a, const Vec3& e, double& t_out,
                Vec3& normal_out) {
    const Vec3 m = p0 - a;
    const double ee = e.dot(e);
    if (!(ee > 0.0)) return false;
    const double ed = e.dot(d), em = e.dot(m);
    const double qa = ee * d.dot(d) - ed * ed;
    const double qb = ee * d.dot(m) - ed * em;
    const double qc = ee * (m.dot(m) - r * r) - em * em;
    if (qc <= 0.0 || qb >= 0.0 || !(qa > 0.0)) return false;  // inside the cylinder, moving away, or parallel
    const double disc = qb * qb - qa * qc;
    if (disc < 0.0) return false;
    const double t = (-qb - std::sqrt(disc)) / qa;
    if (t < 0.0 || t > 1.0) return false;
    const double s = (em + t * ed) / ee;
    if (s < 0.0 || s > 1.0) return false;  // beyond an end: the vertex test covers it
    const Vec3 n = (m + d * t) - e * s;
    const double len2 = n.squaredNorm();
    if (!(len2 > 0.0)) return false;
    t_out = t;
    normal_out = n * (1.0 / std::sqrt(len2));
    return true;
}

// True if p (on the triangle's plane) is inside or on the triangle (`n`:
// its unit normal).
bool inside(const Triangle& tri, const Vec3& n, const Vec3& p) {
    return (tri.b - tri.a).cross(p - tri.a).dot(n) >= 0.0 && (tri.c - tri.b).cross(p - tri.b).dot(n) >= 0.0 &&
           (tri.a - tri.c).cross(p - tri.c).dot(n) >= 0.0;
}

}  // namespace

bool sweep_sphere_triangle(const Vec3& p0, const Vec3& d, double r, const Triangle& tri, SweepHit& hit) {
    return sweep_sphere_triangle(p0, d, r, tri, tri.normal(), hit);
}

namespace sweep_detail {

bool sweep_from_plane(const Vec3& p0, const Vec3& d, double r, const Triangle& tri, const Vec3& face_normal,
                      const Vec3& n, double s0, double dn, SweepHit& hit) {
    if (dn < 0.0) {
        // The face: the plane is reached at distance r at time t; the
        // contact point must lie inside the triangle.
        const double t = s0 > r ? (s0 - r) / -dn : 0.0;
        if (t <= 1.0) {
            const Vec3 c = p0 + d * t - n * (s0 > r ? r : s0);
            if (inside(tri, face_normal, c)) {
                if (!(t < hit.t)) return false;
                hit = {t, n};
                return true;
            }
        }
    }
    return sweep_features(p0, d, r, tri, hit);
}

// Edges, then vertices: the earliest of them.
bool sweep_features(const Vec3& p0, const Vec3& d, double r, const Triangle& tri, SweepHit& hit) {
    bool any = false;
    double best = hit.t;
    Vec3 best_n = hit.normal;
    const Vec3* v[3] = {&tri.a, &tri.b, &tri.c};
    for (int i = 0; i < 3; ++i) {
        double t = 0.0;
        Vec3 n;
        if (sweep_edge(p0, d, r, *v[i], *v[(i + 1) % 3] - *v[i], t, n) && t < best) {
            best = t;
            best_n = n;
            any = true;
        }
    }
    for (int i = 0; i < 3; ++i) {
        double t = 0.0;
        const Vec3 m = p0 - *v[i];
        if (sweep_point(m, d, r, t) && t < best) {
            const Vec3 n = m + d * t;
            best = t;
            best_n = n * (1.0 / std::sqrt(n.squaredNorm()));
            any = true;
        }
    }
    if (any) hit = {best, best_n};
    return any;
}

}  // namespace sweep_detail

}  // namespace jetrace
