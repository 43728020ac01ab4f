// Triangles, boxes and the exact closest point on a triangle.
#pragma once

#include "jetrace/core/math.hpp"

namespace jetrace {

struct Aabb {
    Vec3 min{0, 0, 0};
    Vec3 max{0, 0, 0};

    static Aabb around(const Vec3& center, double half_extent) {
        const Vec3 h(half_extent, half_extent, half_extent);
        return {center - h, center + h};
    }
    void expand(const Vec3& p) {
        min = min.cwiseMin(p);
        max = max.cwiseMax(p);
    }
    /// Inclusive overlap: boxes that only touch overlap (a flat triangle has a
    /// zero-thickness box and must still be found).
    bool overlaps(const Aabb& o) const {
        return min.x() <= o.max.x() && o.min.x() <= max.x() && min.y() <= o.max.y() &&
               o.min.y() <= max.y() && min.z() <= o.max.z() && o.min.z() <= max.z();
    }
};

/// A box in single precision, rounded outward: it contains the double box
/// it was made from (24 bytes against Aabb's 48). What the grid keeps of
/// each triangle and the gather filters by.
struct FloatBox {
    float lo[3] = {0, 0, 0};
    float hi[3] = {0, 0, 0};

    /// The smallest float box containing `b` (each bound rounded to the
    /// nearest float, then stepped one float outward if that rounding went
    /// inward; NaN stays NaN).
    static FloatBox around(const Aabb& b);
    /// The same box in doubles (exact: every float is a double).
    Aabb aabb() const {
        return {Vec3(double{lo[0]}, double{lo[1]}, double{lo[2]}), Vec3(double{hi[0]}, double{hi[1]}, double{hi[2]})};
    }
    /// Grows to the smallest box holding this one and `o` (exact).
    void expand(const FloatBox& o) {
        for (int i = 0; i < 3; ++i) {
            lo[i] = lo[i] < o.lo[i] ? lo[i] : o.lo[i];
            hi[i] = hi[i] > o.hi[i] ? hi[i] : o.hi[i];
        }
    }
};

/// A track triangle with the data the resolver needs precomputed.
struct Triangle {
    Vec3 a{0, 0, 0}, b{0, 0, 0}, c{0, 0, 0};
    /// True when the triangle has (almost) no area: it is then treated as its
    /// three edges.
    bool degenerate = false;
    /// True for a sliver (height below 1e-3 of its longest edge): its closest
    /// point is found by projection and edge tests, which stay exact where
    /// the Voronoi-region arithmetic loses its digits to cancellation.
    bool thin = false;

    static Triangle make(const Vec3& a, const Vec3& b, const Vec3& c);
    Aabb bounds() const;

    /// Inward unit normal of edge i (0: ab, 1: bc, 2: ca) in the triangle's
    /// plane (normal x edge; only for a triangle that is not degenerate).
    /// (p - a).inward(0, normal()) is p's distance inside edge ab (negative: outside);
    /// p projects onto the face exactly when all three are >= 0, and is
    /// farther than d from the triangle if one is below -d. Computed when
    /// asked rather than stored (with the normal, 96 of what would be 176
    /// bytes a triangle): most candidates are rejected by the plane or the
    /// first edge.
    Vec3 inward(int i, const Vec3& unit_normal) const {
        const Vec3 edge = i == 0 ? Vec3(b - a) : (i == 1 ? Vec3(c - b) : Vec3(a - c));
        return unit_normal.cross(edge) / std::sqrt(edge.squaredNorm());
    }

    /// Unit normal by the right-hand rule over (a, b, c); zero if degenerate.
    /// Computed when asked (a cross product and a square root), as make()
    /// computed it to decide `degenerate`: the same bits every time.
    Vec3 normal() const {
        if (degenerate) return Vec3::Zero();
        const Vec3 n = (b - a).cross(c - a);
        return n / std::sqrt(n.squaredNorm());
    }
};

/// A triangle's unit normal and the inward unit normals of its edges, as
/// Triangle::normal() and Triangle::inward() compute them (the same bits):
/// kept for a triangle that is tested again and again (a car's candidates).
struct TriangleFrame {
    Vec3 normal{0, 0, 0};
    Vec3 inward[3] = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0)};
    /// Only for a triangle that is not degenerate.
    static TriangleFrame of(const Triangle& t) {
        TriangleFrame f;
        f.normal = t.normal();
        for (int i = 0; i < 3; ++i) f.inward[i] = t.inward(i, f.normal);
        return f;
    }
};

/// Which feature of the triangle the closest point lies on.
enum class TriRegion : std::uint8_t { vertex_a, vertex_b, vertex_c, edge_ab, edge_bc, edge_ca, face };

struct ClosestPoint {
    Vec3 point{0, 0, 0};
    TriRegion region = TriRegion::face;
};

/// Exact closest point of `t` to `p`: the projection onto the plane when it
/// falls inside the three edges (Triangle::inward), otherwise by Voronoi
/// regions (Ericson, Real-Time Collision Detection 5.1.5; slivers by their
/// edges), with degenerate triangles handled as segments.
ClosestPoint closest_point_on_triangle(const Vec3& p, const Triangle& t);

/// The same, unless `t` is certainly farther than `reach_m` from `p` (beyond
/// its plane, or outside one of its edges, by more than reach_m, or off the
/// plane by h and outside an edge by e with h^2 + e^2 beyond reach by more
/// than a micrometre): then false and `out` is untouched. The cheap test for
/// a triangle near a car; a car over a fine mesh has several triangles
/// within reach of their plane and of every edge's line, and only the last
/// test rejects those not under it.
bool closest_point_within(const Vec3& p, const Triangle& t, double reach_m, ClosestPoint& out);

/// The same with `t`'s frame (TriangleFrame::of(t), `t` not degenerate)
/// given: the same arithmetic on the same values, so the same result, with
/// no square root or division on the way to it.
bool closest_point_within(const Vec3& p, const Triangle& t, const TriangleFrame& frame, double reach_m,
                          ClosestPoint& out);

/// Closest point to p on segment [a, b].
Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b);

}  // namespace jetrace
