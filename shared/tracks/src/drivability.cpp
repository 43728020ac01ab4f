// The drivability warnings of a loaded track (docs/TRACKS.md, "Drivability
// warnings"): gates on obstacles or above the road, spawns on ground too
// steep to stand on, floors facing down, an implausible size; the legs'
// reachability is in drivability_legs.cpp.
#include "jetrace/tracks/drivability.hpp"

#include "drivability_legs.hpp"
#include "ground_probe.hpp"
#include "track_raycast.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace jetrace {
namespace {

using detail::at;
using detail::finite;

constexpr double kDegToRad = 0.017453292519943295;
constexpr double kRadToDeg = 57.29577951308232;
// A cast from a gate's top edge starts this far inside it (unit: m), so that
// a roof the gate was fitted under (a manifest's clearance) is not met.
constexpr double kTopSkin_m = 0.05;
// A spawn's ground is looked for this far beyond its resting height along
// its -up (unit: m), then straight down.
constexpr double kSpawnReach_m = 1.0;
// The grid's cells follow the default car (unit: m).
constexpr double kCarRadius_m = 2.5;

// Longest ray worth casting from `o` (unit: m): past the track's bounds.
double reach_m(const Track& track, const Vec3& o) {
    const Vec3 mid = (track.bounds.min + track.bounds.max) * 0.5;
    return (o - mid).norm() + (track.bounds.max - track.bounds.min).norm() * 0.5 + 1.0;
}

std::string fixed(double v, int digits = 1) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

// Angle of a face from the horizontal, whichever way it is wound (unit: degrees).
double slope_deg(const Vec3& n) { return std::acos(std::min(1.0, std::abs(n.y()))) * kRadToDeg; }

// gate_on_obstacle / gate_above_road: the first surface down the gate's
// opening (along -up, from just inside its top edge through its centre).
void check_gate(const Track& track, const UniformGrid& grid, const DrivabilityLimits& lim, std::size_t k,
                std::vector<DrivabilityWarning>& out) {
    const Checkpoint& g = track.checkpoints[k];
    const double hh = g.half_height_m;
    if (!finite(g.center) || !finite(g.up) || !std::isfinite(hh) || !(hh > 0)) return;
    const double start = std::max(hh - kTopSkin_m, 0.0);
    const Vec3 top = g.center + g.up * start;
    const std::string name = "gate " + std::to_string(k) + " at " + at(g.center);
    const auto index = static_cast<std::int64_t>(k);
    double t = 0;
    std::uint32_t tri = 0;
    if (!detail::cast_ray(track, grid, top, -g.up, reach_m(track, top), t, tri)) {
        out.push_back({kGateAboveRoad, "gate", index, g.center, name + " has no surface under it at all"});
        return;
    }
    const double below_centre = t - start;  // the surface's depth under the centre, along -up
    const Vec3 n = track.triangles[tri].normal();
    const double tilt = std::acos(std::min(1.0, std::abs(n.dot(g.up)))) * kRadToDeg;
    if (below_centre < 0) {
        out.push_back({kGateOnObstacle, "gate", index, g.center,
                       name + ": a surface at " + at(top - g.up * t) + " is " + fixed(-below_centre) +
                           " m above its centre, inside its opening (the gate stands in or on an obstacle)"});
    } else if (below_centre < hh && tilt > lim.ride_limit_deg) {
        out.push_back({kGateOnObstacle, "gate", index, g.center,
                       name + ": a face at " + fixed(tilt, 0) + " degrees to the gate's floor, " + fixed(below_centre) +
                           " m under its centre, is inside its opening (an obstacle, not a road)"});
    } else if (below_centre - hh > lim.max_gate_lift_m) {
        out.push_back({kGateAboveRoad, "gate", index, g.center,
                       name + ": its bottom edge is " + fixed(below_centre - hh) + " m above the road at " +
                           at(top - g.up * t) + "; cars pass under it (over " + fixed(lim.max_gate_lift_m) + " m)"});
    }
}

// The ground a pose stands on: along its -up first, then straight down.
bool ground_under(const Track& track, const UniformGrid& grid, const Pose& p, Vec3& normal) {
    double t = 0;
    std::uint32_t tri = 0;
    const bool hit = (finite(p.up) && detail::cast_ray(track, grid, p.position, -p.up, detail::kRest_m + kSpawnReach_m,
                                                       t, tri)) ||
                     detail::cast_ray(track, grid, p.position, Vec3(0, -1, 0), reach_m(track, p.position), t, tri);
    if (hit) normal = track.triangles[tri].normal();
    return hit;
}

// spawn_too_steep: every spawn; a gate's respawn pose only when the next
// gate's road is above it (a car put there at rest slides down: harmless
// when the race goes down, as from the top of the stadium's wall).
void check_spawns(const Track& track, const UniformGrid& grid, const DrivabilityLimits& lim,
                  std::vector<DrivabilityWarning>& out) {
    auto steep = [&](const Pose& p, double& deg) {
        Vec3 n;
        if (!finite(p.position) || !ground_under(track, grid, p, n)) return false;
        deg = slope_deg(n);
        return deg > lim.ride_limit_deg;
    };
    const std::string limit = " (the ride limit is " + fixed(lim.ride_limit_deg, 0) + ")";
    const std::size_t n = track.checkpoints.size();
    for (std::size_t k = 0; k < n; ++k) {
        const Pose& here = track.checkpoints[k].respawn;
        const Pose& next = track.checkpoints[(k + 1) % n].respawn;
        double deg = 0;
        if (!(next.position.y() > here.position.y() + lim.max_step_up_m) || !steep(here, deg)) continue;
        out.push_back({kSpawnTooSteep, "respawn", static_cast<std::int64_t>(k), here.position,
                       "gate " + std::to_string(k) + "'s respawn at " + at(here.position) + " stands on ground sloping " +
                           fixed(deg, 0) + " degrees" + limit + " and gate " + std::to_string((k + 1) % n) +
                           " is uphill: a car put there at rest slides back"});
    }
    for (std::size_t i = 0; i < track.spawns.size(); ++i) {
        double deg = 0;
        if (!steep(track.spawns[i], deg)) continue;
        out.push_back({kSpawnTooSteep, "spawn", static_cast<std::int64_t>(i), track.spawns[i].position,
                       "spawn " + std::to_string(i) + " at " + at(track.spawns[i].position) +
                           " stands on ground sloping " + fixed(deg, 0) + " degrees" + limit +
                           ": a car starting there slides off"});
    }
}

// faces_point_down: drivable faces (by the ride limit) whose normal points down.
void check_faces(const Track& track, const DrivabilityLimits& lim, std::vector<DrivabilityWarning>& out) {
    const double min_abs_y = std::cos(lim.ride_limit_deg * kDegToRad);
    std::size_t faces = 0, down = 0;
    for (const Triangle& t : track.triangles) {
        if (t.degenerate) continue;
        ++faces;
        const double y = t.normal().y();
        down += (y < 0 && -y >= min_abs_y) ? 1 : 0;
    }
    const double share = faces ? static_cast<double>(down) / static_cast<double>(faces) : 0.0;
    if (!(share > lim.max_down_share)) return;
    out.push_back({kFacesPointDown, "track", -1, (track.bounds.min + track.bounds.max) * 0.5,
                   std::to_string(down) + " of " + std::to_string(faces) + " faces (" + fixed(100 * share) +
                       " %, over " + fixed(100 * lim.max_down_share, 0) +
                       " %) are drivable floors whose normal points down: flipped winding? (the driving AI's road "
                       "profile sees only faces pointing up)"});
}

// height_range: an implausible extent (false if the bounds are not finite).
bool check_extent(const Track& track, const DrivabilityLimits& lim, std::vector<DrivabilityWarning>& out) {
    const Vec3 size = track.bounds.max - track.bounds.min;
    const Vec3 mid = (track.bounds.min + track.bounds.max) * 0.5;
    bool bad = !finite(track.bounds.min) || !finite(track.bounds.max);
    for (const Triangle& t : track.triangles) bad = bad || !finite(t.a) || !finite(t.b) || !finite(t.c);
    if (bad) {
        out.push_back({kHeightRange, "track", -1, Vec3::Zero(), "the mesh has coordinates that are not finite"});
        return false;
    }
    const double horizontal = std::max(size.x(), size.z()), largest = std::max(horizontal, size.y());
    if (largest > lim.max_extent_m) {
        out.push_back({kHeightRange, "track", -1, mid,
                       "the mesh spans " + fixed(largest / 1000.0) + " km (over " + fixed(lim.max_extent_m / 1000.0, 0) +
                           " km): wrong units (centimetres?) or a stray vertex"});
    } else if (size.y() > lim.max_height_ratio * horizontal) {
        out.push_back({kHeightRange, "track", -1, mid,
                       "the mesh is " + fixed(size.y()) + " m tall and " + fixed(horizontal) + " m wide (over " +
                           fixed(lim.max_height_ratio, 0) + " times): a Z-up mesh read as Y-up, or a stray vertex"});
    }
    return true;
}

}  // namespace

std::vector<DrivabilityWarning> check_drivability(const Track& track, const UniformGrid& grid,
                                                  const DrivabilityLimits& limits) {
    std::vector<DrivabilityWarning> out;
    if (!check_extent(track, limits, out) || track.triangles.empty()) return out;
    std::vector<DrivabilityWarning> head;
    for (std::size_t k = 0; k < track.checkpoints.size(); ++k) check_gate(track, grid, limits, k, head);
    detail::check_legs(track, grid, limits, head);
    // Gates in order (each gate's warnings together), then spawns, then the mesh.
    std::stable_sort(head.begin(), head.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
    check_spawns(track, grid, limits, head);
    check_faces(track, limits, head);
    head.insert(head.end(), out.begin(), out.end());
    return head;
}

std::vector<DrivabilityWarning> check_drivability(const Track& track, const DrivabilityLimits& limits) {
    std::vector<DrivabilityWarning> out;
    if (!check_extent(track, limits, out) || track.triangles.empty()) return out;
    const UniformGrid grid(track.triangles, track.bounds, kCarRadius_m);
    return check_drivability(track, grid, limits);
}

}  // namespace jetrace
