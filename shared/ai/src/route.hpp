// The route as the driving AI walks it: the gates as a closed polyline,
// points along it, the legs' levels and the radius of each turn. Internal
// to jetrace::ai (inline: drive() asks for these on every decision).
#pragma once

#include "ai_math.hpp"

#include "jetrace/ai/road_profile.hpp"
#include "jetrace/core/track.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace jetrace::ai_detail {

// The gates as a closed polyline, seen from one car.
struct Route {
    const std::vector<Checkpoint>& gates;
    std::int32_t count;
    const Checkpoint& at(std::int32_t i) const { return gates[static_cast<std::size_t>(wrap(i, count))]; }
};

// A point on the route: a fraction `t` (0..1) of the way along the leg
// into gate `leg`.
struct RoutePoint {
    Vec3 at;
    std::int32_t leg = 0;
    double t = 0.0;
};

// Where the car's route starts: its projection onto the leg into gate
// `next`, in the plane across `up`.
inline RoutePoint route_start(const Route& r, std::int32_t next, const Vec3& p, const Vec3& up) {
    const Vec3 a = r.at(next - 1).center;
    const Vec3 b = r.at(next).center;
    const Vec3 ab = in_plane(b - a, up);
    const double len2 = ab.squaredNorm();
    const double t = len2 > 1e-9 ? std::clamp(in_plane(p - a, up).dot(ab) / len2, 0.0, 1.0) : 1.0;
    return {a + (b - a) * t, next, t};
}

// The point `ahead` metres along the route from `start` (route_start()'s;
// unit: m).
inline Vec3 route_point(const Route& r, const RoutePoint& start, const Vec3& up, double ahead) {
    const std::int32_t next = start.leg;
    Vec3 from = start.at;
    double left = ahead;
    for (std::int32_t i = 0; i < 16 && i < r.count; ++i) {
        const Vec3 leg = r.at(next + i).center - from;
        const double len = in_plane(leg, up).norm();
        if (len >= left) return from + leg * (left / len);
        left -= len;
        from = r.at(next + i).center;
    }
    return from;
}

// The points every `step` metres along the route from `start`
// (route_start()'s), `count` + 1 of them (the first the start), in one walk.
inline void route_points(const Route& r, const RoutePoint& start, const Vec3& up, double step, int count,
                         RoutePoint* out) {
    const std::int32_t next = start.leg;
    Vec3 from = start.at;
    double t0 = start.t;  // where `from` is along the current leg
    double at = 0.0;  // distance along the route to `from` (unit: m)
    std::int32_t leg = next;
    int k = 0;
    for (std::int32_t i = 0; i < 16 && i < r.count && k <= count; ++i) {
        leg = next + i;
        const Vec3 d = r.at(leg).center - from;
        const double len = in_plane(d, up).norm();
        for (; k <= count && step * k - at <= len; ++k) {
            const double u = len > 0.0 ? (step * k - at) / len : 0.0;
            out[k] = {from + d * u, leg, t0 + (1.0 - t0) * u};
        }
        at += len;
        from = r.at(leg).center;
        t0 = 0.0;
    }
    for (; k <= count; ++k) out[k] = {from, leg, 1.0};
}

// True if route_points(r, start, up, step, count) would place every point
// on legs that are level at one height (RoadProfile::level_height): the same
// walk over the legs, without the points.
inline bool level_ahead(const RoadProfile& road, const Route& r, const RoutePoint& start, const Vec3& up, double step,
                        int count) {
    const double y = road.level_height(start.leg);
    Vec3 from = start.at;
    double at = 0.0;
    const double last = step * count;
    for (std::int32_t i = 0; i < 16 && i < r.count; ++i) {
        const std::int32_t leg = start.leg + i;
        if (!(road.level_height(leg) == y)) return false;
        const double len = in_plane(r.at(leg).center - from, up).norm();
        // route_points() puts the last point on this leg.
        if (last - at <= len) return true;
        at += len;
        from = r.at(leg).center;
    }
    return true;  // the points left over go on the last leg walked
}

// Radius of the turn at gate `i` (unit: m; 0 when the route runs straight
// on): the widest arc tangent to the legs in and out within half the shorter
// leg that still passes the gate within 80 % of its half-width. With the
// turn angle a, R = min(L / tan(a/2), w / (1/cos(a/2) - 1)); sin(a/2) is half
// the chord between the legs' unit directions, so no trig is needed.
inline double corner_radius(const Route& r, std::int32_t i, const Vec3& up) {
    const Vec3 in = in_plane(r.at(i).center - r.at(i - 1).center, up);
    const Vec3 out = in_plane(r.at(i + 1).center - r.at(i).center, up);
    const double half_sin = 0.5 * (normalized_or(in, up) - normalized_or(out, up)).norm();
    if (half_sin < 5e-4) return 0.0;
    const double half_cos = std::sqrt(std::max(1.0 - half_sin * half_sin, 1e-9));
    const double legs = 0.5 * std::min(in.norm(), out.norm());
    const double w = 0.8 * r.at(i).half_width_m;
    // L / tan = L cos / sin; w / (1/cos - 1) = w cos / (1 - cos).
    return std::min(legs * half_cos / half_sin, w * half_cos / std::max(1.0 - half_cos, 1e-12));
}

}  // namespace jetrace::ai_detail
