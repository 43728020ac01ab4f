#include "jetrace/ai/driver_ai.hpp"

#include "ai_math.hpp"
#include "gate_crossing.hpp"
#include "route.hpp"
#include "unstick.hpp"

#include "jetrace/core/candidates.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

using ai_detail::corner_radius;
using ai_detail::in_plane;
using ai_detail::level_ahead;
using ai_detail::Route;
using ai_detail::route_point;
using ai_detail::route_points;
using ai_detail::RoutePoint;
using ai_detail::route_start;

namespace {

// True if any triangle is within the contact skin of the sphere at `p`: the
// test find_contacts() makes (a triangle whose grid box is beyond reach,
// or beyond the reach of its plane or of an edge, is rejected before its
// closest point is computed). The box test first: on a dense mesh the
// cells around a car hold hundreds of triangles, a handful within reach.
bool touches_track(const Scene& sc, const Vec3& p) {
    const double reach = sc.physics.car_radius_m + sc.physics.contact_skin_m;
    const double reach2 = reach * reach;
    const double h = reach + kBoxSlack_m;
    return sc.grid.any_candidate(Aabb::around(p, reach), [&](std::uint32_t i) {
        if (!(box_distance2(sc.grid.box(i).aabb(), p.x(), p.y(), p.z()) <= h * h)) return false;
        ClosestPoint cp;
        return closest_point_within(p, sc.track.triangles[i], reach, cp) && (p - cp.point).squaredNorm() < reach2;
    });
}

// touches_track(sc, car.position), from the contacts the step kept if it
// found them at this very position (the same tests: within the contact
// skin of the sphere).
bool on_track(const Scene& sc, const CarState& car, const CarScratch* stepped) {
    if (stepped != nullptr && stepped->contacts_valid && same(stepped->contacts_at, car.position)) {
        return !stepped->contacts.empty();
    }
    return touches_track(sc, car.position);
}


// Backwards speed along the nose past which the car is rolling back (unit: m/s).
constexpr double kRollingBack_mps = 1.0;

// Over its speed limit by this factor, the car brakes (below it, it only
// lifts off the throttle). Each term of the limit can only lower it, so a
// car already past it brakes whatever the terms not yet taken say.
constexpr double kBrakeOver = 1.03;

// Distance before a gate of the point a car lines up at when it cannot
// drive through the gate from where it is (unit: m).
constexpr double kApproach_m = 15.0;
// Speed to drive to that point at: slow enough to turn there (unit: m/s).
constexpr double kApproachSpeed_mps = 15.0;

// True if the car at `p` cannot drive straight through gate `g`: it is past
// the gate's plane without having crossed it inside (a start beside a gate
// at a corner, an overshoot), or beside the gate, nearly in its plane.
bool needs_approach(const Checkpoint& g, const Vec3& p) {
    const double past = (p - g.center).dot(g.normal);
    const double side = std::abs((p - g.center).dot(g.across));
    if (side < g.half_width_m * 0.8) return past > 0.0;
    return past > -(side - g.half_width_m * 0.5);
}

// Where to steer: the route point ahead, moved sideways by `shift`, unless
// the straight line to it would miss the next gate (then that gate's
// centre, moved the same). `approach`: needs_approach() at the next gate.
Vec3 pursuit_point(const Route& r, const CarState& car, const RoutePoint& start, const Vec3& up, double ahead,
                   const Vec3& shift, bool approach) {
    const Checkpoint& g = r.at(car.next_checkpoint);
    const Vec3 p = car.position;
    const double to_plane = (g.center - p).dot(g.normal);
    if (approach) return g.center - g.normal * kApproach_m;
    const Vec3 x = route_point(r, start, up, ahead) + shift;
    const double along = (x - p).dot(g.normal);
    if (to_plane <= 0.0 || along <= to_plane) return x;  // the aim is before the gate
    const Vec3 cross = p + (x - p) * (to_plane / along);
    if (std::abs((cross - g.center).dot(g.across)) <= g.half_width_m * 0.6) return x;
    return g.center + shift;
}


// Fraction of the full-lock yaw rate the AI plans its turns for.
constexpr double kYawMargin = 0.8;

// Highest speed at which the car, at `speed` along the surface, can still
// slow down for every corner within its braking distance (unit: m/s); or,
// once `speed` is kBrakeOver past the corners' so far, theirs (drive()
// brakes either way).
double speed_limit(const Scene& sc, const Route& r, const CarState& car, const Vec3& up, double speed,
                   const DriverSkill& skill, bool finishing) {
    const double decel = sc.physics.brake_mps2 * 0.8;
    const double horizon = speed * speed / (2.0 * decel) + 60.0;
    double limit = 1e9;
    double dist = in_plane(r.at(car.next_checkpoint).center - car.position, up).norm();
    for (std::int32_t ahead = 0; ahead < r.count && ahead < 64 && dist < horizon; ++ahead) {
        const std::int32_t i = car.next_checkpoint + ahead;
        // The race ends at the finish line: no corner after it counts (a
        // car that crosses it slowly stops on it, in the way of the rest).
        if (finishing && i % r.count == 0) break;
        const double radius = corner_radius(r, i, up);
        double corner_speed = 1e9;
        if (radius > 0.0) {
            // Within the grip, and within what the yaw rate can follow.
            corner_speed = std::min(std::sqrt(skill.corner_mps2 * radius), kYawMargin * sc.physics.steer_rate_radps * radius);
        }
        // A gate passed climbing (it points up, like the top of the wall):
        // arrive slowly, or the car flies far above it.
        if (r.at(i).normal.y() > 0.5) corner_speed = std::min(corner_speed, skill.climb_top_mps);
        limit = std::min(limit, std::sqrt(corner_speed * corner_speed + 2.0 * decel * dist));
        // Past it already: the car brakes whatever the corners farther on say.
        if (speed > limit * kBrakeOver) break;
        dist += in_plane(r.at(i + 1).center - r.at(i).center, up).norm();
    }
    return limit;
}

// Speed to reach an obstacle on the route at, to drive round it (unit: m/s).
constexpr double kAroundSpeed_mps = 20.0;

// Spacing of the road heights read along the route ahead, and the most
// read (unit: m, samples).
constexpr double kProbeStep_m = 6.0;
constexpr int kProbes = 16;

// Highest speed from which the car can slow down, within its braking
// distance, to the speed at which each crest ahead still holds it on the
// road: over a crest of vertical radius R the road's push ends at
// v = sqrt(g R cos(slope)), with R from the course's road profile along the
// route (unit: m/s).
double crest_limit(const Scene& sc, const RoadProfile& road, const Route& r, const RoutePoint& start, const Vec3& up,
                   double decel, double horizon, const DriverSkill& skill) {
    const int n = std::min(kProbes, static_cast<int>(horizon / kProbeStep_m) + 2);
    // Level road all the way (every height the same, no obstacle): no
    // crest and nothing to drive round, what the loops below would find.
    if (level_ahead(road, r, start, up, kProbeStep_m, n)) return 1e9;
    double h[kProbes + 1];
    double s[kProbes + 1];
    bool ok[kProbes + 1];
    RoutePoint points[kProbes + 1];
    route_points(r, start, up, kProbeStep_m, n, points);
    Vec3 prev = points[0].at;
    double limit = 1e9;
    for (int k = 0; k <= n; ++k) {
        const Vec3& q = points[k].at;
        const RoadProfile::Sample road_here = road.sample(points[k].leg, points[k].t);
        ok[k] = road_here.has_height;
        h[k] = road_here.y;
        const double dx = q.x() - prev.x(), dz = q.z() - prev.z();
        s[k] = k == 0 ? 0.0 : s[k - 1] + std::sqrt(dx * dx + dz * dz);
        prev = q;
        // An obstacle on the route: arrive slowly enough to drive round it.
        if (road_here.obstacle) {
            limit = std::min(limit, std::sqrt(kAroundSpeed_mps * kAroundSpeed_mps + 2.0 * decel * s[k]));
        }
    }
    const double g = sc.physics.gravity_mps2;
    for (int k = 1; k < n; ++k) {
        const double d1 = s[k] - s[k - 1], d2 = s[k + 1] - s[k];
        if (!ok[k - 1] || !ok[k] || !ok[k + 1] || d1 < 1.0 || d2 < 1.0) continue;
        const double bend = 2.0 * ((h[k + 1] - h[k]) / d2 - (h[k] - h[k - 1]) / d1) / (d1 + d2);
        if (bend >= 0.0) continue;  // level or a dip
        const double slope = (h[k + 1] - h[k - 1]) / (d1 + d2);
        // v^2 = g cos(slope) / curvature, the curvature y'' / (1 + y'^2)^1.5.
        const double lift2 = skill.crest_ratio * skill.crest_ratio * g * (1.0 + slope * slope) / -bend;
        limit = std::min(limit, std::sqrt(lift2 + 2.0 * decel * s[k - 1]));
    }
    return limit;
}

// Slow enough to reach the aim on the arc through it at the yaw rate the
// steering gives (radius: distance / (2 sin(heading error)), `arc_sin` the
// sine), and to line up where the car cannot drive through the next gate
// (`approach`: needs_approach() there).
double aim_limit(const Scene& sc, const CarState& car, const Vec3& up, const Vec3& aim, double arc_sin,
                 bool approach) {
    double limit = 1e9;
    const double reach = in_plane(aim - car.position, up).norm();
    const double yaw_rate = kYawMargin * sc.physics.steer_rate_radps;
    if (arc_sin > 1e-3) limit = std::max(6.0, yaw_rate * reach / (2.0 * arc_sin));
    if (approach) limit = std::min(limit, kApproachSpeed_mps);
    return limit;
}

// The steering held to what the grip turns: on the ground the yaw rate the
// lock asks for times the speed is the sideways acceleration, and past
// grip_mps2 the car slides, its sideways friction falls to slide_mps2 and
// it turns far slower than asked (at 60 m/s and more full lock is past it).
int within_grip(const Scene& sc, int steer, double speed) {
    if (!(speed > 1.0)) return steer;
    const double cap = 0.9 * sc.physics.grip_mps2 / (speed * sc.physics.steer_rate_radps);
    if (cap >= 1.0) return steer;
    const int c = std::max(1, static_cast<int>(cap * Input::kMaxSteer));
    return std::clamp(steer, -c, c);
}

}  // namespace

const Course& CourseCache::operator()(const Scene& scene) {
    if (!course_ || &course_->scene() != &scene || triangles_ != scene.track.triangles.size() ||
        gates_ != scene.track.checkpoints.size()) {
        course_.emplace(scene);
        triangles_ = scene.track.triangles.size();
        gates_ = scene.track.checkpoints.size();
    }
    return *course_;
}

Input drive(const Course& course, const WorldState& state, int slot, const DriverSkill& skill,
            const CarScratch* stepped) {
    const Scene& sc = course.scene();
    const CarState& car = state.cars[static_cast<std::size_t>(slot)];
    const auto& gates = sc.track.checkpoints;
    if (!car.active || car.finished || gates.empty()) return Input::clamped(0, 0, 1);
    const Route route{gates, static_cast<std::int32_t>(gates.size())};

    // forward() and up(), the orientation normalised once for both.
    const Quat unit = car.unit_orientation();
    const Vec3 fwd = axis_z(unit);
    const Vec3 up = axis_y(unit);
    const Vec3 right = fwd.cross(up);
    const double speed = in_plane(car.velocity, up).norm();
    // Steer at a point at least as far along the route as the next gate: a
    // long leg is driven along, not squeezed onto its centre line.
    const Checkpoint& next = route.at(car.next_checkpoint);
    const double to_gate = in_plane(next.center - car.position, up).norm();
    const double ahead_m = std::max(std::clamp(speed * 0.5, 10.0, skill.lookahead_m), to_gate);
    const std::int32_t next_k = ai_detail::wrap(car.next_checkpoint, route.count);
    const double cross_at = ai_detail::crossing_offset(course, state, next_k, car);
    // Where the car joins the route, for the aim and the crests ahead.
    const RoutePoint start = route_start(route, car.next_checkpoint, car.position, up);
    const bool approach = needs_approach(next, car.position);
    const Vec3 aim = pursuit_point(route, car, start, up, ahead_m, next.across * cross_at, approach);

    const Vec3 d = normalized_or(in_plane(aim - car.position, up), fwd);
    const double lateral = d.dot(right);
    const double error = ai_detail::heading_error(d, fwd, right);
    // On a wall or a steep bank slowing down means sliding back: there the
    // corners and climbs ahead are the only limit.
    const bool steep = up.y() < 0.7;
    Input out;
    if (!steep && ai_detail::unstick(sc, car, d, error, speed, out)) return out;
    // Inputs that change rarely are what a client predicting other cars
    // guesses right (it repeats their last input): no dithering.
    const int steer = static_cast<int>(std::lround(skill.steer_gain * error * Input::kMaxSteer));
    // In the air thrust does nothing: lift off, keep the nose on the aim for
    // the landing (the grip turns the velocity after it; a car that lands
    // rolling backwards is stopped by thrust and brake below).
    if (!on_track(sc, car, stepped)) return Input::clamped(0, steer, 0);

    const int steer_g = within_grip(sc, steer, speed);
    // Rolling backwards (off a ramp's top, back from a wall it could not
    // climb): thrust and brake both stop that, whatever the speed.
    if (car.velocity.dot(fwd) < -kRollingBack_mps) return Input::clamped(Input::kMaxThrottle, steer_g, 1);
    const bool finishing = next_k == 0 && car.lap >= state.laps;
    // The speed limit: the least of the corners', the aim's and the crests'
    // (none is NaN, so the order they are taken in changes nothing). A car
    // already kBrakeOver past it brakes whatever the crests say, and is
    // spared reading them.
    double limit = speed_limit(sc, route, car, up, speed, skill, finishing);
    if (!steep) {
        limit = std::min(limit, aim_limit(sc, car, up, aim, d.dot(fwd) > 0.0 ? std::abs(lateral) : 1.0, approach));
        if (!(speed > limit * kBrakeOver)) {
            const double decel = sc.physics.brake_mps2 * 0.8;
            const double horizon = speed * speed / (2.0 * decel) + 2.0 * kProbeStep_m;
            limit = std::min(limit, crest_limit(sc, course.road(), route, start, up, decel, horizon, skill));
        }
    }
    int throttle = Input::kMaxThrottle;
    int brake = 0;
    if (speed > limit) {
        throttle = 0;
        brake = speed > limit * kBrakeOver ? 1 : 0;
    }
    // Sliding sideways: ease off so the grip comes back.
    if (std::abs(car.velocity.dot(right)) > 8.0) throttle = std::min(throttle, Input::kMaxThrottle / 2);
    return Input::clamped(throttle, steer_g, brake);
}

}  // namespace jetrace
