#include "unstick.hpp"

#include "ai_math.hpp"

#include "jetrace/core/candidates.hpp"

#include <cmath>
#include <cstdint>

namespace jetrace::ai_detail {

namespace {

// The nearest point of a face steeper than the road (unit normal within
// 45 degrees of level against `up`: a block's side, a barrier) within
// `reach` of the car centred at `p`. False if there is none.
bool nearest_obstacle(const Scene& sc, const Vec3& p, const Vec3& up, double reach, Vec3& at) {
    double best2 = reach * reach;
    bool found = false;
    sc.grid.for_each_candidate(Aabb::around(p, reach), [&](std::uint32_t i) {
        const Triangle& t = sc.track.triangles[i];
        ClosestPoint cp;
        if (!closest_point_within(p, t, reach, cp)) return true;
        const double d2 = (p - cp.point).squaredNorm();
        if (d2 < best2 && std::abs(t.normal().dot(up)) < 0.7) {
            best2 = d2;
            at = cp.point;
            found = true;
        }
        return true;
    });
    return found;
}

// With heading error `error` to where the car should go: turn on the spot
// (braked) until the nose is within about 17 degrees of it, then drive there.
Input turn_then_drive(double error) {
    if (std::abs(error) > 0.3) return Input::clamped(0, error >= 0.0 ? Input::kMaxSteer : -Input::kMaxSteer, 1);
    return Input::clamped(Input::kMaxThrottle, static_cast<int>(std::lround(error * 2.0 * Input::kMaxSteer)), 0);
}

}  // namespace

// Pinned against an obstacle (a face steeper than the road within a car's
// radius and a half): turn along it, to the side of the aim `d`, and drive
// out round it. Else turn on the spot towards the aim, then drive; every
// few seconds try the other way round.
bool unstick(const Scene& sc, const CarState& car, const Vec3& d, double error, double speed, Input& out) {
    const auto hz = static_cast<std::uint32_t>(sc.physics.tick_rate_hz);
    if (car.no_progress_ticks < hz * 3 / 2 || speed > 6.0) return false;
    const Vec3 up = car.up(), fwd = car.forward();
    const Vec3 right = fwd.cross(up);
    Vec3 at(0, 0, 0);
    // An obstacle between the car and its aim (within 60 degrees of it).
    if (nearest_obstacle(sc, car.position, up, 1.5 * sc.physics.car_radius_m, at) &&
        (at - car.position).dot(d) > 0.5 * (at - car.position).norm()) {
        const Vec3 away = in_plane(car.position - at, up);
        Vec3 along = up.cross(away);
        if (along.dot(d) < 0.0) along = -along;
        const Vec3 way = normalized_or(along + away * 0.25, d);
        out = turn_then_drive(heading_error(way, fwd, right));
        return true;
    }
    const std::uint32_t phase = (car.no_progress_ticks - hz * 3 / 2) % (hz * 4);
    const double turn = phase < hz * 5 / 2 ? error : -error;
    if (phase >= hz * 5 / 2 && phase < hz * 3) {
        out = Input::clamped(0, turn >= 0.0 ? Input::kMaxSteer : -Input::kMaxSteer, 1);
    } else {
        out = turn_then_drive(turn);
    }
    return true;
}

}  // namespace jetrace::ai_detail
