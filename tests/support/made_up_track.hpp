// Small made-up tracks for tests: floors, blocks, ramps and upright gates
// built in code (units: m, y up), for the drivability checks and the
// driving AI.
#pragma once

#include "jetrace/core/track.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace jetrace::test {

/// A car at rest on a floor: its centre this far above the road (unit: m).
inline constexpr double kRest_m = 2.5 + 1.0 / 1024.0;

struct Mesh {
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    /// Two triangles a, b, c and a, c, d (wound as given).
    void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
        const auto base = static_cast<std::uint32_t>(v.size());
        v.insert(v.end(), {a, b, c, d});
        idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    /// A floor at height y over [x0, x1] x [z0, z1] in 10 m squares, facing up (or down).
    void floor(double x0, double z0, double x1, double z1, double y, bool down = false) {
        for (double x = x0; x < x1; x += 10) {
            for (double z = z0; z < z1; z += 10) {
                const Vec3 a(x, y, z), b(x, y, z + 10), c(x + 10, y, z + 10), d(x + 10, y, z);
                down ? quad(a, d, c, b) : quad(a, b, c, d);
            }
        }
    }
    /// A block of height h on the floor around (cx, cz): a top of half size
    /// `top`, its four sides sloping out to half size `top + flare` at the floor.
    void block(double cx, double cz, double top, double flare, double h) {
        const double t = top, b = top + flare;
        const Vec3 T[4] = {Vec3(cx - t, h, cz - t), Vec3(cx - t, h, cz + t), Vec3(cx + t, h, cz + t),
                           Vec3(cx + t, h, cz - t)};
        const Vec3 B[4] = {Vec3(cx - b, 0, cz - b), Vec3(cx - b, 0, cz + b), Vec3(cx + b, 0, cz + b),
                           Vec3(cx + b, 0, cz - b)};
        quad(T[0], T[1], T[2], T[3]);
        for (int i = 0; i < 4; ++i) quad(B[i], B[(i + 1) % 4], T[(i + 1) % 4], T[i]);
    }
};

/// An upright gate over the road at height road_y at (x, z), its bottom edge
/// `lift` above the road, heading along (hx, hz); its respawn rests on the road.
inline Checkpoint gate(double x, double z, double hx, double hz, double road_y = 0, double lift = 0, double hh = 6) {
    Checkpoint c;
    c.normal = Vec3(hx, 0, hz).normalized();
    c.up = Vec3(0, 1, 0);
    c.across = c.normal.cross(c.up);
    c.center = Vec3(x, road_y + lift + hh, z);
    c.half_width_m = 10;
    c.half_height_m = hh;
    c.respawn = Pose{Vec3(x, road_y + kRest_m, z), c.normal, c.up};
    return c;
}

/// Four gates round a diamond on the floor y = 0: (60, 0), (0, 60), (-60, 0), (0, -60).
inline std::vector<Checkpoint> diamond() {
    return {gate(60, 0, -1, 1), gate(0, 60, -1, -1), gate(-60, 0, 1, -1), gate(0, -60, 1, 1)};
}

inline Pose flat_spawn() { return Pose{Vec3(50, kRest_m, -10), Vec3(-1, 0, 1).normalized(), Vec3(0, 1, 0)}; }

inline Track track_of(const Mesh& m, std::vector<Checkpoint> gates, std::vector<Pose> spawns = {flat_spawn()}) {
    return make_track("made-up", m.v, m.idx, std::move(gates), std::move(spawns), -100);
}

inline Mesh flat_floor() {
    Mesh m;
    m.floor(-100, -100, 100, 100, 0);
    return m;
}

}  // namespace jetrace::test
