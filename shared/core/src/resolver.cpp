#include "jetrace/core/resolver.hpp"

#include "jetrace/core/hovercar.hpp"
#include "jetrace/core/sweep.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace jetrace {

namespace {

// Calls f(triangle, index) for each candidate that may_reach_along_axes(k,
// q) accepts, in order (index: the triangle's); a run's eight boxes tested
// at once.
template <class F>
void for_each_reaching(const Track& track, const Candidates& cand, const BoxQuery& q, F&& f) {
    if (cand.all) {
        for (std::size_t k = 0; k < track.triangles.size(); ++k) f(track.triangles[k], static_cast<std::uint32_t>(k));
        return;
    }
    for (std::size_t first = 0; first < cand.triangles.size(); first += Candidates::kRunLength) {
        for (std::uint32_t mask = cand.boxes.within8_along_axes(first, q); mask != 0; mask &= mask - 1) {
            const std::uint32_t index = cand.triangles[first + static_cast<std::size_t>(std::countr_zero(mask))];
            f(track.triangles[index], index);
        }
    }
}

// Calls f(triangle, k, index) for each candidate from the k-th on that
// may_touch(p, reach_m) accepts, in order (k: its place among the
// candidates, index: the triangle's); under brute force every triangle from
// the k-th on. Stops when f returns false. f must not gather again (the
// list it is called from would change under it): return false, then gather.
template <class F>
void for_each_touching(const Track& track, const Candidates& cand, std::size_t k, const Vec3& p, double reach_m,
                       F&& f) {
    if (cand.all) {
        for (; k < track.triangles.size(); ++k) {
            if (!f(track.triangles[k], k, static_cast<std::uint32_t>(k))) return;
        }
        return;
    }
    const std::size_t count = cand.touching_from(k, p, reach_m);
    // The triangles are read one after another below, each after the last
    // one's tests: on a track of millions (80 bytes each, far outside the
    // caches) their loads would wait in turn. Asking for them all first
    // lets them arrive together (a hint: it changes no result). For one or
    // two (a car over a coarse mesh) the hint's own loads cost more than
    // the overlap saves: none then.
    for (std::size_t i = 0; count > 2 && i < count; ++i) {
        const char* bytes = reinterpret_cast<const char*>(&track.triangles[cand.triangles[cand.found[i]]]);
        __builtin_prefetch(bytes);
        __builtin_prefetch(bytes + sizeof(Triangle) - 1);
    }
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t at = cand.found[i];
        const std::uint32_t index = cand.triangles[at];
        if (!f(track.triangles[index], at, index)) return;
    }
}

// closest_point_within for triangle `index` (`t`), with its kept frame.
bool closest_within(const Candidates& cand, std::uint32_t index, const Triangle& t, const Vec3& p, double reach_m,
                    ClosestPoint& out) {
    if (cand.all || t.degenerate) return closest_point_within(p, t, reach_m, out);
    return closest_point_within(p, t, cand.frames.get(index, t), reach_m, out);
}

// Triangle `index`'s unit normal (Triangle::normal(), kept). Always inline:
// kept, it is a few loads, which a call and a returned copy would double.
[[gnu::always_inline]] inline Vec3 unit_normal(const Candidates& cand, std::uint32_t index, const Triangle& t) {
    if (cand.all || t.degenerate) return t.normal();
    return cand.frames.get(index, t).normal;
}

// The least squared distance d2 whose square root exceeds 1e-9 m: a test
// `d2 >= kContactDist2` gives exactly `std::sqrt(d2) > 1e-9` (the rounded
// square root is monotonic), without waiting for the root.
const double kContactDist2 = [] {
    constexpr double kMin = 1e-9;
    double d2 = kMin * kMin;
    while (std::sqrt(d2) > kMin) d2 = std::nextafter(d2, 0.0);
    while (!(std::sqrt(d2) > kMin)) d2 = std::nextafter(d2, 1.0);
    return d2;
}();

// contact_normal() away from a face region's interior: the normalised
// centre-to-closest-point vector, or for a centre on the triangle (within
// 1e-9 m) the face normal on the side the car came from.
[[gnu::noinline]] Vec3 contact_normal_off_face(const Candidates& cand, std::uint32_t index, const Triangle& t,
                                               const ClosestPoint& cp, const Vec3& p, double d2,
                                               const Vec3* came_from) {
    const Vec3& q = cp.point;
    if (d2 >= kContactDist2) return (p - q) / std::sqrt(d2);
    if (t.degenerate) return kWorldUp;
    const Vec3 n = unit_normal(cand, index, t);
    const Vec3 from = came_from != nullptr ? *came_from : Vec3(p + n);
    return (from - q).dot(n) < 0.0 ? Vec3(-n) : n;
}

// Direction from the surface point `q` to the centre `p`, `d2` apart
// (squared). Inside the face region that is the face normal (on the
// centre's side), exactly: a car at rest on a flat floor then feels an
// exactly vertical normal, not one tilted by the rounding of the closest
// point. If the centre lies on the triangle (within 1e-9 m), the face
// normal on the side the car came from (`came_from`; nullptr: p + the
// normal, the normal's own side). Inline up to the face region's answer,
// the common one (a car over a floor); the rest out of line.
[[gnu::always_inline]] inline Vec3 contact_normal(const Candidates& cand, std::uint32_t index, const Triangle& t,
                                                  const ClosestPoint& cp, const Vec3& p, double d2,
                                                  const Vec3* came_from) {
    if (d2 >= kContactDist2 && cp.region == TriRegion::face && !t.degenerate) {
        const Vec3 n = unit_normal(cand, index, t);
        return (p - cp.point).dot(n) < 0.0 ? Vec3(-n) : n;
    }
    return contact_normal_off_face(cand, index, t, cp, p, d2, came_from);
}

// The swept phase: moves the car from `from` towards `position` until its
// first contact, stops it there (epsilon clear), removes its velocity into
// the surface, and slides the rest of the motion along it; up to
// sweep_contacts times. Returns the contacts met.
int sweep_motion(const TrackQuery& q, const SphereMotion& car, Candidates& cand) {
    const PhysicsSettings& s = q.physics;
    const Track& track = q.track;
    Vec3& position = car.position;
    Vec3& velocity = car.velocity;
    const double r = s.car_radius_m;
    Vec3 p = car.from;
    Vec3 d = position - car.from;
    double length = std::sqrt(d.squaredNorm());
    // One gather covers every slide and the push-out that follows.
    keep_covered(q, car.from, gather_reach(s, GatherFor::sweep, length), cand);
    int hits = 0;
    while (true) {
        SweepHit hit;
        bool found = false;
        // Every point of the swept sphere lies within |d|/2 + r of the
        // motion's midpoint.
        const Vec3 mid = p + d * 0.5;
        const BoxQuery swept = cand.box_query(mid, 0.5 * length + r);
        for_each_reaching(track, cand, swept, [&](const Triangle& t, std::uint32_t index) {
            found = sweep_sphere_triangle(p, d, r, t, unit_normal(cand, index, t), hit) || found;
        });
        if (!found) {
            // Nothing in the way: the car ends where it was going (exactly:
            // from + (to - from) could round differently).
            if (hits > 0) position = p + d;
            return hits;
        }
        const Vec3& n = hit.normal;
        p += d * hit.t + n * s.resolver_epsilon_m;
        const double vn = velocity.dot(n);
        if (vn < 0.0) velocity -= n * vn;  // inelastic, as in the push-out
        if (++hits == s.sweep_contacts) {  // the rest of the motion is dropped
            position = p;
            return hits;
        }
        d *= 1.0 - hit.t;
        const double dn = d.dot(n);
        if (dn < 0.0) d -= n * dn;  // slide along the surface
        length = std::sqrt(d.squaredNorm());
    }
}

}  // namespace

void find_contacts(const TrackQuery& q, const Candidates& cand, const Vec3& center, Contacts& out) {
    out.clear();
    const double reach = q.physics.car_radius_m + q.physics.contact_skin_m;
    const double reach2 = reach * reach;
    for_each_touching(q.track, cand, 0, center, reach, [&](const Triangle& t, std::size_t, std::uint32_t index) {
        ClosestPoint cp;
        if (!closest_within(cand, index, t, center, reach, cp)) return true;
        const double d2 = (center - cp.point).squaredNorm();
        if (d2 < reach2) out.add(contact_normal(cand, index, t, cp, center, d2, nullptr));
        return true;
    });
}

namespace {

// Whether a pass at reach `r` finds candidate `at` (triangle `index`, `t`)
// touching the car at `position`: its box test there, then its closest-point
// test. Out of line: only a pass that touches asks (the box query is made
// only then).
[[gnu::noinline]] bool touches_at(const Candidates& cand, std::size_t at, std::uint32_t index, const Triangle& t,
                                  const Vec3& position, double r) {
    ClosestPoint same_point;
    return cand.may_touch(at, position, r) && closest_within(cand, index, t, position, r, same_point);
}

// One push-out pass: in ascending triangle order, every candidate the sphere
// touches (distance <= r) moves the centre to r + epsilon from its closest
// point and loses its velocity into it; PushOut::first_contact stops after
// the first. Returns the pushes made. With `collect`, a pass that pushes
// nothing has also found the contacts where the car is (exactly what
// find_contacts() finds: the same tests in the same order), into `contacts`.
//
// The result depends only on the geometry, never on where the candidates
// were gathered (a client restoring a snapshot into fresh scratch gathers
// elsewhere than the server did): when a push carries the car out of the
// gathered region, the candidates are gathered again around it and the pass
// resumes after the triangle it was at. The triangles it skips were checked
// at positions the old region covered, as brute force would have.
int push_pass(const TrackQuery& q, const SphereMotion& car, Candidates& cand, bool collect, Contacts& contacts) {
    const PhysicsSettings& s = q.physics;
    const Track& track = q.track;
    Vec3& position = car.position;
    Vec3& velocity = car.velocity;
    const double r = s.car_radius_m;
    const double r2 = r * r;
    const double target = r + s.resolver_epsilon_m;
    const double query_radius = r + s.contact_skin_m;
    const double query2 = query_radius * query_radius;
    if (collect) contacts.clear();
    int pushes = 0;
    // Contacts only matter while the pass has pushed nothing; after a push
    // only touching triangles do, and the cheaper reach r rejects the rest.
    double reach = collect ? query_radius : r;
    std::size_t k = 0;  // where the pass goes on after a push
    for (;;) {
        bool pushed = false;
        for_each_touching(track, cand, k, position, reach, [&](const Triangle& t, std::size_t at, std::uint32_t index) {
            ClosestPoint cp;
            if (!closest_within(cand, index, t, position, reach, cp)) return true;
            const double d2 = (position - cp.point).squaredNorm();
            // Touching is decided exactly as a pass at reach r decides it
            // (its cheap rejections included, which rounding can tip at a
            // distance of r), so that the push never depends on the reach
            // this pass gathers contacts at, that is, on resolve()'s hint.
            bool touching = d2 <= r2;
            if (touching && reach != r) touching = touches_at(cand, at, index, t, position, r);
            if (!touching) {
                if (collect && pushes == 0 && d2 < query2) {
                    contacts.add(contact_normal(cand, index, t, cp, position, d2, nullptr));
                }
                return true;
            }
            reach = r;
            const Vec3 n = contact_normal(cand, index, t, cp, position, d2, &car.from);
            position = cp.point + n * target;
            const double vn = velocity.dot(n);
            if (vn < 0.0) velocity -= n * vn;  // inelastic: no velocity into the surface
            ++pushes;
            k = at + 1;
            pushed = true;
            return false;  // the pass goes on after this triangle, from where the car now is
        });
        if (!pushed) break;
        const std::uint32_t last = cand.all ? static_cast<std::uint32_t>(k - 1) : cand.triangles[k - 1];
        if (keep_covered(q, position, gather_reach(s, GatherFor::contacts), cand) && !cand.all) {
            k = static_cast<std::size_t>(std::upper_bound(cand.triangles.begin(), cand.triangles.end(), last) -
                                         cand.triangles.begin());
        }
        if (s.push_out == PushOut::first_contact) break;
    }
    return pushes;
}

}  // namespace

ResolveStats resolve(const TrackQuery& q, const SphereMotion& car, Candidates& cand, Contacts& contacts,
                     bool expect_push) {
    const PhysicsSettings& s = q.physics;
    Vec3& position = car.position;
    Vec3& velocity = car.velocity;
    ResolveStats stats;
    const double r = s.car_radius_m;
    const double r2 = r * r;
    const GatherReach near = gather_reach(s, GatherFor::contacts);
    if (needs_sweep(s, car.from, position)) {
        // Moving more than half the radius: the push-out alone could be
        // fooled by a thin wall (docs/ACCURACY.md). Slower, it cannot: a
        // sphere that started clear ends at least r/2 from every triangle
        // on the side it came from.
        stats.sweep_hits = sweep_motion(q, car, cand);
        // A sweep that met nothing left the car where it was (the step
        // rounded it before the push-out).
        if (stats.sweep_hits > 0 && s.quantize_state) quantize_motion(position, velocity);
        // The sweep's gather covers the push-out wherever the sweep left
        // the car (sweep_reach: its slides, their epsilons, and a margin
        // far beyond the rounding's 0.85 mm).
    } else {
        keep_covered(q, position, near, cand);
    }
    for (int pass = 0; pass < s.resolver_passes; ++pass) {
        // A pass expected to push skips the contacts (they would be stale);
        // the pass after it finds them.
        const bool collect = !(expect_push && pass == 0);
        const int pushes = push_pass(q, car, cand, collect, contacts);
        if (pushes == 0) {
            stats.found_contacts = collect;
            break;
        }
        ++stats.passes;
        stats.pushes += pushes;
        // Pushed cars are rounded too, and the next pass checks them where
        // they will be: rounding moves a car at most sqrt(3) 2^-11 m (0.85
        // mm), less than the default epsilon (1/1024 m), so it cannot undo a
        // push (a smaller epsilon lets it: docs/ACCURACY.md). Rounding can
        // also carry the car to the edge of its candidates: the next pass
        // must cover it, or its contacts would depend on where they were
        // gathered.
        if (s.quantize_state) {
            quantize_motion(position, velocity);
            keep_covered(q, position, near, cand);
        }
    }
    if (stats.passes == s.resolver_passes) {
        // Did the last pass leave the car clear?
        for_each_touching(q.track, cand, 0, position, r, [&](const Triangle& t, std::size_t, std::uint32_t) {
            ClosestPoint cp;
            if (!closest_point_within(position, t, r, cp)) return true;
            if ((position - cp.point).squaredNorm() < r2) {
                stats.capped = true;
                return false;
            }
            return true;
        });
    }
    return stats;
}

}  // namespace jetrace
