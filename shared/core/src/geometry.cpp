#include "jetrace/core/geometry.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace jetrace {

Triangle Triangle::make(const Vec3& a, const Vec3& b, const Vec3& c) {
    Triangle t;
    t.a = a;
    t.b = b;
    t.c = c;
    const Vec3 n = (b - a).cross(c - a);
    const double len2 = n.squaredNorm();
    // Relative test: area small against the squared longest edge.
    const double scale = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (!(len2 > 1e-20 * scale * scale) || scale == 0.0) {
        t.degenerate = true;
    } else {
        t.thin = len2 < 1e-6 * scale * scale;
    }
    return t;
}

namespace {

// The float after `f` towards +infinity (`up`) or -infinity, for a finite
// `f` or the infinity on the other side: std::nextafter without the library
// call (a grid of millions of triangles makes millions of these).
float float_step(float f, bool up) {
    if (f == 0.0f) return up ? std::numeric_limits<float>::denorm_min() : -std::numeric_limits<float>::denorm_min();
    const auto bits = std::bit_cast<std::uint32_t>(f);
    // Away from zero adds one to the magnitude's bits, towards zero takes one.
    const bool away = (f > 0.0f) == up;
    return std::bit_cast<float>(away ? bits + 1 : bits - 1);
}

}  // namespace

FloatBox FloatBox::around(const Aabb& b) {
    FloatBox f;
    for (int i = 0; i < 3; ++i) {
        f.lo[i] = static_cast<float>(b.min[i]);
        if (double{f.lo[i]} > b.min[i]) f.lo[i] = float_step(f.lo[i], false);
        f.hi[i] = static_cast<float>(b.max[i]);
        if (double{f.hi[i]} < b.max[i]) f.hi[i] = float_step(f.hi[i], true);
    }
    return f;
}

Aabb Triangle::bounds() const {
    Aabb box{a, a};
    box.expand(b);
    box.expand(c);
    return box;
}

Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    if (!(len2 > 0.0)) return a;
    double t = (p - a).dot(ab) / len2;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return a + ab * t;
}

namespace {

// The closest of the three edges (vertices included), with its region.
ClosestPoint closest_on_edges(const Vec3& p, const Triangle& t) {
    const Vec3 q0 = closest_point_on_segment(p, t.a, t.b);
    const Vec3 q1 = closest_point_on_segment(p, t.b, t.c);
    const Vec3 q2 = closest_point_on_segment(p, t.c, t.a);
    const double d0 = (p - q0).squaredNorm(), d1 = (p - q1).squaredNorm(), d2 = (p - q2).squaredNorm();
    ClosestPoint r;
    if (d0 <= d1 && d0 <= d2) {
        r = {q0, TriRegion::edge_ab};
    } else if (d1 <= d2) {
        r = {q1, TriRegion::edge_bc};
    } else {
        r = {q2, TriRegion::edge_ca};
    }
    if (r.point == t.a) r.region = TriRegion::vertex_a;
    if (r.point == t.b) r.region = TriRegion::vertex_b;
    if (r.point == t.c) r.region = TriRegion::vertex_c;
    return r;
}

// Outside an edge of a non-degenerate triangle: the nearest edge or vertex.
// Kept out of line: the face test before it is the hot path (measured with
// callgrind on `jetrace-bench bullet --scenario driving --jetrace-only`).
[[gnu::noinline]] ClosestPoint closest_outside_face(const Vec3& p, const Triangle& t) {
    // Slivers by their edges, where the Voronoi-region arithmetic below
    // loses its digits to cancellation.
    if (t.thin) return closest_on_edges(p, t);
    const Vec3& a = t.a;
    const Vec3& b = t.b;
    const Vec3& c = t.c;
    const Vec3 ab = b - a;
    const Vec3 ac = c - a;
    const Vec3 ap = p - a;
    const double d1 = ab.dot(ap);
    const double d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) return {a, TriRegion::vertex_a};

    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp);
    const double d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) return {b, TriRegion::vertex_b};

    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        return {a + ab * v, TriRegion::edge_ab};
    }

    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp);
    const double d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) return {c, TriRegion::vertex_c};

    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        return {a + ac * w, TriRegion::edge_ca};
    }

    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {b + (c - b) * w, TriRegion::edge_bc};
    }

    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom;
    const double w = vc * denom;
    return {a + ab * v + ac * w, TriRegion::face};
}

}  // namespace

namespace {

// How far beyond reach a lower bound of the distance must be before
// closest_point_within calls a triangle certainly farther (unit: m): far
// above the rounding of the distances its callers compute.
constexpr double kReachSlack_m = 1e-6;

// closest_point_within's tests from the plane on; `inward(i)` gives edge i's
// inward normal (computed when asked, or kept).
template <class Inward>
bool closest_from_plane(const Vec3& p, const Triangle& t, const Vec3& n, Inward&& inward, double reach_m,
                        ClosestPoint& out) {
    const double h = (p - t.a).dot(n);
    if (h > reach_m || h < -reach_m) return false;
    // p's distance inside each edge (Triangle::inward), edge by edge, so that
    // a triangle beyond its first edge costs one test. Each is a
    // well-conditioned dot product, so slivers are classified as exactly as
    // large triangles.
    const double ab = (p - t.a).dot(inward(0));
    if (ab < -reach_m) return false;
    const double bc = (p - t.b).dot(inward(1));
    if (bc < -reach_m) return false;
    const double ca = (p - t.c).dot(inward(2));
    if (ca < -reach_m) return false;
    // The face: the projection onto the plane (the common case, and the only
    // well-conditioned one for a sliver).
    if (ab >= 0.0 && bc >= 0.0 && ca >= 0.0) {
        out = ClosestPoint{p - n * h, TriRegion::face};
        return true;
    }
    // Outside an edge by `e` (in the plane) and off the plane by h, p is at
    // least sqrt(h^2 + e^2) from the triangle, which lies inside every
    // edge. Beyond reach by more than kReachSlack_m, certainly farther: no
    // caller's rounding of the exact distance could bring it within reach.
    // Not for a sliver: its computed normal can be off by enough to move a
    // point metres away by micrometres.
    const double e = -std::min({ab, bc, ca});
    const double limit = reach_m + kReachSlack_m;
    if (!t.thin && h * h + e * e > limit * limit) return false;
    out = closest_outside_face(p, t);
    return true;
}

}  // namespace

bool closest_point_within(const Vec3& p, const Triangle& t, double reach_m, ClosestPoint& out) {
    if (t.degenerate) {
        out = closest_on_edges(p, t);
        return true;
    }
    const Vec3 n = t.normal();
    return closest_from_plane(p, t, n, [&](int i) { return t.inward(i, n); }, reach_m, out);
}

bool closest_point_within(const Vec3& p, const Triangle& t, const TriangleFrame& frame, double reach_m,
                          ClosestPoint& out) {
    return closest_from_plane(p, t, frame.normal, [&](int i) -> const Vec3& { return frame.inward[i]; }, reach_m,
                              out);
}

ClosestPoint closest_point_on_triangle(const Vec3& p, const Triangle& t) {
    ClosestPoint cp;
    closest_point_within(p, t, std::numeric_limits<double>::infinity(), cp);
    return cp;
}

}  // namespace jetrace
