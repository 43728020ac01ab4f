#include "jetrace/driver_ai.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

namespace {

// True if any triangle is within the contact skin of the sphere at `p`: the
// test find_contacts() makes (a triangle beyond the reach of its plane or
// of an edge is rejected before its closest point is computed).
bool touches_track(const Scene& sc, const Vec3& p) {
    const double reach = sc.physics.car_radius_m + sc.physics.contact_skin_m;
    const double reach2 = reach * reach;
    return sc.grid.any_candidate(Aabb::around(p, reach), [&](std::uint32_t i) {
        ClosestPoint cp;
        return closest_point_within(p, sc.track.triangles[i], reach, cp) && (p - cp.point).squaredNorm() < reach2;
    });
}

Vec3 in_plane(const Vec3& v, const Vec3& n) { return v - n * v.dot(n); }

// Highest speed at which the car can still slow down for the corners at the
// next few gates (unit: m/s).
double speed_limit(const Scene& sc, const CarState& car, const Vec3& up, const DriverSkill& skill) {
    const auto& gates = sc.track.checkpoints;
    const auto k = static_cast<std::int32_t>(gates.size());
    const double decel = sc.physics.brake_mps2 * 0.8;
    double limit = 1e9;
    double dist = in_plane(gates[static_cast<std::size_t>(car.next_checkpoint)].center - car.position, up).norm();
    for (int ahead = 0; ahead < 4; ++ahead) {
        const Checkpoint& a = gates[static_cast<std::size_t>((car.next_checkpoint + ahead) % k)];
        const Checkpoint& b = gates[static_cast<std::size_t>((car.next_checkpoint + ahead + 1) % k)];
        const Vec3 ab = b.center - a.center;
        const double seg = in_plane(ab, a.up).norm();
        // Angle between the gates' directions, from the chord of unit normals.
        const double turn = (a.normal - b.normal).norm();
        double corner_speed = 1e9;
        if (turn > 1e-3) corner_speed = std::sqrt(skill.corner_mps2 * (seg / turn));
        // A gate passed climbing (its direction points up, like the top of the
        // wall): arrive slowly, or the car flies far above it.
        if (a.normal.y() > 0.5) corner_speed = std::min(corner_speed, skill.climb_top_mps);
        limit = std::min(limit, std::sqrt(corner_speed * corner_speed + 2.0 * decel * dist));
        dist += seg;
    }
    return limit;
}

}  // namespace

Input drive(const Scene& sc, const WorldState& state, int slot, const DriverSkill& skill) {
    const CarState& car = state.cars[static_cast<std::size_t>(slot)];
    const auto& gates = sc.track.checkpoints;
    if (!car.active || car.finished || gates.empty()) return Input::clamped(0, 0, 1);
    if (!touches_track(sc, car.position)) return Input::clamped(Input::kMaxThrottle, 0, 0);  // airborne

    const Vec3 fwd = car.forward();
    const Vec3 up = car.up();
    const Vec3 right = fwd.cross(up);
    const auto k = static_cast<std::int32_t>(gates.size());
    const Checkpoint& g = gates[static_cast<std::size_t>(car.next_checkpoint)];
    const Checkpoint& g2 = gates[static_cast<std::size_t>((car.next_checkpoint + 1) % k)];

    // Aim at the next gate; close to it, start turning for the one after.
    Vec3 to_gate = in_plane(g.center - car.position, up);
    const double dist = to_gate.norm();
    Vec3 aim = to_gate;
    if (dist < skill.lookahead_m) {
        const double w = 1.0 - dist / skill.lookahead_m;
        aim = to_gate * (1.0 - w) + in_plane(g2.center - car.position, up) * w;
    }
    const Vec3 d = normalized_or(aim, fwd);
    const double lateral = d.dot(right);
    const double ahead = d.dot(fwd);
    const double error = ahead > 0.0 ? lateral : (lateral >= 0.0 ? 1.5 : -1.5);
    const int steer = static_cast<int>(std::lround(skill.steer_gain * error * Input::kMaxSteer));

    const double speed = in_plane(car.velocity, up).norm();
    const double limit = speed_limit(sc, car, up, skill);
    int throttle = Input::kMaxThrottle;
    int brake = 0;
    if (speed > limit) {
        throttle = 0;
        brake = speed > limit * 1.05 ? 1 : 0;
    }
    // Sliding sideways: ease off so the grip comes back.
    if (std::abs(car.velocity.dot(right)) > 8.0) throttle = std::min(throttle, Input::kMaxThrottle / 2);
    return Input::clamped(throttle, steer, brake);
}

}  // namespace jetrace
