// A static race track: a triangle mesh, ordered checkpoints, spawn slots.
#pragma once

#include "jetrace/core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace jetrace {

/// A pose where a car can be placed: on the track, sphere just touching it.
struct Pose {
    Vec3 position{0, 0, 0};
    /// Unit direction the car faces.
    Vec3 forward{0, 0, 1};
    /// Unit up; orthogonal to forward.
    Vec3 up{0, 1, 0};
};

/// A rectangular gate. A car passes it when its centre crosses the gate's
/// plane in the direction of `normal` inside the rectangle.
struct Checkpoint {
    Vec3 center{0, 0, 0};
    /// Unit direction of travel through the gate.
    Vec3 normal{0, 0, 1};
    /// Unit vectors spanning the gate rectangle (orthogonal to normal).
    Vec3 across{1, 0, 0};
    Vec3 up{0, 1, 0};
    /// Half extents of the gate along `across` and `up` (unit: m).
    double half_width_m = 10;
    double half_height_m = 10;
    /// Where a car that falls below the kill height after passing this
    /// checkpoint comes back.
    Pose respawn;
};

/// Result of a segment crossing a gate.
struct GateCrossing {
    bool crossed = false;
    /// Where along the segment [0, 1] the crossing happened.
    double fraction = 0;
};

/// Distance from `p` to the gate's rectangle (unit: m), and its square.
double distance_to_gate(const Checkpoint& gate, const Vec3& p);

// Whether the segment from `from` to `to` crosses the gate, and where
// (inline, like squared_distance_to_gate: the race rules ask for every car
// every step).
inline GateCrossing cross_gate(const Checkpoint& g, const Vec3& from, const Vec3& to) {
    const double s0 = (from - g.center).dot(g.normal);
    const double s1 = (to - g.center).dot(g.normal);
    if (!(s0 < 0.0 && s1 >= 0.0)) return {};
    const double f = s0 / (s0 - s1);
    const Vec3 q = from + (to - from) * f - g.center;
    if (std::abs(q.dot(g.across)) > g.half_width_m || std::abs(q.dot(g.up)) > g.half_height_m) return {};
    return {true, f};
}

[[gnu::always_inline]] inline double squared_distance_to_gate(const Checkpoint& g, const Vec3& p) {
    const Vec3 q = p - g.center;
    const double a = std::clamp(q.dot(g.across), -g.half_width_m, g.half_width_m);
    const double u = std::clamp(q.dot(g.up), -g.half_height_m, g.half_height_m);
    return (q - g.across * a - g.up * u).squaredNorm();
}

struct Track {
    std::string name;
    std::vector<Triangle> triangles;
    /// Ordered gates; checkpoints[0] is the start/finish line.
    std::vector<Checkpoint> checkpoints;
    /// Starting grid, pole position first.
    std::vector<Pose> spawns;
    /// A car whose centre falls below this height respawns (unit: m).
    double kill_height_m = -100;
    /// Bounds of all triangles.
    Aabb bounds;

    /// Identity of the geometry and rules: hash of every coordinate, gate and
    /// spawn. Replays and the handshake carry it.
    std::uint64_t identity() const;
};

/// Builds a track from an indexed mesh (precomputes triangle data and bounds).
Track make_track(std::string name, const std::vector<Vec3>& vertices, const std::vector<std::uint32_t>& indices,
                 std::vector<Checkpoint> checkpoints, std::vector<Pose> spawns, double kill_height_m);

/// Appends Triangle::make(a, b, c) to `t` and grows its bounds (the first
/// triangle sets them): what make_track does per triangle, in the same order
/// of operations, so the bounds come out the same bit for bit.
void add_triangle(Track& t, const Vec3& a, const Vec3& b, const Vec3& c);

/// Largest number of triangles a track may have.
inline constexpr std::size_t kMaxTrackTriangles = 4'000'000;
/// Largest |coordinate| accepted in a track (unit: m).
inline constexpr double kMaxTrackCoordinate_m = 1.0e6;

/// Checks a track read from outside: empty string if valid, else the problem.
std::string validate(const Track& track);

/// The part of validate() after the triangles: gates, spawns, kill height
/// (for a reader that has checked every corner already).
std::string validate_rules(const Track& track);

}  // namespace jetrace
