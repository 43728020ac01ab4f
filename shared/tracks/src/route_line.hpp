// A manifest's route as a closed polyline in the horizontal plane: points and
// tangents by distance along it, and the nearest distance to a point.
#pragma once

#include "jetrace/tracks/track_manifest.hpp"

#include <string>
#include <vector>

namespace jetrace::detail {

class RouteLine {
public:
    /// False (with the reason) for a route without horizontal length.
    bool build(const std::vector<RoutePoint>& points, std::string& error);
    /// Horizontal length of the closed loop (unit: m).
    double length() const { return cumulative_.back(); }
    /// The point `u` metres along (wrapped into the loop) and the unit
    /// horizontal direction there; y is interpolated where both ends have one.
    void at(double u, RoutePoint& p, Vec3& tangent) const;
    /// Distance along the loop of the point nearest to `q` (horizontally).
    double project(const RoutePoint& q, Vec3& tangent) const;

private:
    std::vector<RoutePoint> points_;   // with zero-length segments removed
    std::vector<double> cumulative_;   // distance at each point; back() = length
};

}  // namespace jetrace::detail
