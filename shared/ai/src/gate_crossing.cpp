#include "gate_crossing.hpp"

#include "ai_math.hpp"

#include "jetrace/core/candidates.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

namespace ai_detail {

namespace {

// Squared distance from `q` to the segment a-b in the plane across `up`.
double segment_distance2(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& up) {
    const Vec3 ab = in_plane(b - a, up), aq = in_plane(q - a, up);
    const double len2 = ab.squaredNorm();
    const double t = len2 > 1e-9 ? std::clamp(aq.dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (aq - ab * t).squaredNorm();
}

// True if a face steeper than the road (unit normal within 45 degrees of
// level, against `up`) that a car driving along `travel` runs into or
// scrapes is within reach of the car centred at `p`: not one that faces
// the way it drives (the riser of a step down).
bool obstacle_near(const Scene& sc, const Vec3& p, const Vec3& up, const Vec3& travel, double reach) {
    return sc.grid.any_candidate(Aabb::around(p, reach), [&](std::uint32_t i) {
        const Triangle& t = sc.track.triangles[i];
        ClosestPoint cp;
        if (!closest_point_within(p, t, reach, cp) || !((p - cp.point).squaredNorm() < reach * reach)) return false;
        const Vec3 n = t.normal();
        return std::abs(n.dot(up)) < 0.7 && n.dot(travel) < 0.5;
    });
}

}  // namespace

// The centre first, then alternately right and left, farther out, up to
// 80 % of the half-width.
double crossing_place(const Checkpoint& g, int place) {
    const int step = (place + 1) / 2;
    return (place % 2 == 0 ? 1.0 : -1.0) * g.half_width_m * 0.8 * step / Course::kCrossingSteps;
}

// Where the car at `from` crosses gate `gate`, across it from its centre
// (unit: m): the place nearest the centre that no static obstacle stands on
// (Course::crossing_blocked) and that no finished car (held with the brake
// where it crossed the line) blocks on the way: near the line from the car
// to the place and on past it along the gate's normal. If none is clear, the
// one farthest from a finished car.
double crossing_offset(const Course& course, const WorldState& state, std::int32_t gate, const CarState& car) {
    const Vec3& from = car.position;
    const bool finishing = gate == 0 && car.lap >= state.laps;
    // No finished car: the first free place (what the search below finds
    // first, with nothing to measure clearance to).
    bool any_finished = false;
    for (const CarState& o : state.cars) any_finished = any_finished || (o.active && o.finished);
    if (!any_finished) return course.first_free_place_m(static_cast<std::size_t>(gate), finishing);
    const Scene& sc = course.scene();
    const Checkpoint& g = sc.track.checkpoints[static_cast<std::size_t>(gate)];
    const double room = 2.0 * sc.physics.car_radius_m + 1.0;
    double best = 0.0;
    double best_clear = -1.0;
    for (int k = 0; k <= 2 * Course::kCrossingSteps; ++k) {
        if (course.crossing_blocked(static_cast<std::size_t>(gate), k, finishing)) continue;
        const double off = crossing_place(g, k);
        const Vec3 at = g.center + g.across * off;
        const Vec3 past = at + g.normal * (finishing ? 0.0 : 3.0 * room);
        double clear2 = 1e18;
        for (const CarState& o : state.cars) {
            if (!o.active || !o.finished) continue;
            const Vec3 rel = o.position - g.center;
            if (std::abs(rel.dot(g.up)) > g.half_height_m) continue;
            clear2 = std::min({clear2, segment_distance2(o.position, from, at, g.up),
                               segment_distance2(o.position, at, past, g.up)});
        }
        if (clear2 >= room * room) return off;
        if (clear2 > best_clear) {
            best_clear = clear2;
            best = off;
        }
    }
    return best;
}

// The first place across `g` whose bit in `blocked` is clear, as
// crossing_place() gives it; 0 if none is.
double first_free(const Checkpoint& g, std::uint32_t blocked) {
    for (int k = 0; k <= 2 * Course::kCrossingSteps; ++k) {
        if (((blocked >> k) & 1u) == 0) return crossing_place(g, k);
    }
    return 0.0;
}

}  // namespace ai_detail

using ai_detail::crossing_place;
using ai_detail::first_free;
using ai_detail::obstacle_near;

Course::Course(const Scene& scene, const RoadProbe& probe)
    : scene_(&scene), road_(RoadProfile::build(scene.track, scene.grid, probe)) {
    // Each place across each gate, tested where a car rides (1 m higher, so
    // a step lower than about 0.7 m does not count) on the line and 4 m
    // before and after it.
    const double reach = scene.physics.car_radius_m + 0.3;
    const std::uint32_t all = (2u << (2 * kCrossingSteps)) - 1u;
    at_line_.reserve(scene.track.checkpoints.size());
    blocked_.reserve(scene.track.checkpoints.size());
    for (const Checkpoint& g : scene.track.checkpoints) {
        std::uint32_t line = 0, past = 0;
        const Vec3& up = g.respawn.up;
        for (int k = 0; k <= 2 * kCrossingSteps; ++k) {
            const Vec3 at = g.respawn.position + g.across * crossing_place(g, k) + up * 1.0;
            const bool before = obstacle_near(scene, at - g.normal * 4.0, up, g.normal, reach);
            if (before || obstacle_near(scene, at, up, g.normal, reach)) line |= 1u << k;
            if (obstacle_near(scene, at + g.normal * 4.0, up, g.normal, reach)) past |= 1u << k;
        }
        // Nowhere clear: no place is ruled out.
        at_line_.push_back(line == all ? 0u : line);
        blocked_.push_back((line | past) == all ? 0u : line | past);
        free_at_line_m_.push_back(first_free(g, at_line_.back()));
        free_m_.push_back(first_free(g, blocked_.back()));
    }
}

}  // namespace jetrace
