// Continuous collision: a sphere swept along a segment against triangles.
//
// The seed's push-out is discrete: it looks only at where the car ends a
// step. A car that moves more than its radius in one step (the seed's car
// peaks near 3 m per frame, its radius is 2.5 m) can end on the far side of
// a thin wall and be pushed out the wrong way, or pass it entirely. The
// sweep finds the first time of contact along the step's motion instead,
// stops the car there, removes its velocity into the surface and lets the
// rest of the motion slide along it (docs/ACCURACY.md).
#pragma once

#include "jetrace/core/geometry.hpp"
#include "jetrace/core/math.hpp"

namespace jetrace {

struct SweepHit {
    /// Fraction of the motion at first contact, in [0, 1].
    double t = 1.0;
    /// Unit normal of the contact, from the triangle towards the sphere.
    Vec3 normal{0, 0, 0};
};

/// First contact of a sphere of radius `r` whose centre moves from `p0` by
/// `d` with triangle `tri`: its face, then its edges and vertices (Ericson,
/// Real-Time Collision Detection 5.5.6). Returns false if the sphere never
/// comes within `r` during the motion, or only moves away. A sphere already
/// within `r` of the face's interior and moving into it hits at t = 0;
/// otherwise features it already touches at the start are left to the
/// push-out. Returns true, and overwrites `hit`, only for a contact earlier
/// than `hit.t`: called over several triangles it keeps the earliest (the
/// first triangle in call order on ties).
bool sweep_sphere_triangle(const Vec3& p0, const Vec3& d, double r, const Triangle& tri, SweepHit& hit);

namespace sweep_detail {
/// sweep_sphere_triangle() past its first test: `n` the normal on the
/// sphere's side, `s0` the centre's distance from the plane along it, `dn`
/// the motion along it (all as sweep_sphere_triangle() computed them).
bool sweep_from_plane(const Vec3& p0, const Vec3& d, double r, const Triangle& tri, const Vec3& face_normal,
                      const Vec3& n, double s0, double dn, SweepHit& hit);
/// sweep_sphere_triangle() for a degenerate triangle: its edges and vertices.
bool sweep_features(const Vec3& p0, const Vec3& d, double r, const Triangle& tri, SweepHit& hit);
}  // namespace sweep_detail

/// The same with `tri`'s unit normal given (Triangle::normal(), or its
/// kept copy: the same bits; unused for a degenerate triangle): the same
/// arithmetic, without computing the normal twice. Inline up to its most
/// common answer, a sphere beyond reach of the plane moving along it or
/// away (a car driving over a floor): the scan of a step's triangles pays
/// no call for those.
inline bool sweep_sphere_triangle(const Vec3& p0, const Vec3& d, double r, const Triangle& tri,
                                  const Vec3& unit_normal, SweepHit& hit) {
    if (tri.degenerate) return sweep_detail::sweep_features(p0, d, r, tri, hit);
    double s0 = (p0 - tri.a).dot(unit_normal);
    double dn = d.dot(unit_normal);
    const bool back = s0 < 0.0 || (s0 == 0.0 && dn > 0.0);  // the sphere is on the back side
    if (back) {
        s0 = -s0;
        dn = -dn;
    }
    if (!(dn < 0.0) && s0 > r) return false;  // moving along or away from the plane, beyond reach
    return sweep_detail::sweep_from_plane(p0, d, r, tri, unit_normal, back ? Vec3(-unit_normal) : unit_normal, s0,
                                          dn, hit);
}

}  // namespace jetrace
