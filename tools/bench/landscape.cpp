#include "bench/landscape.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace jetrace::bench {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kLapRadius_m = 350.0;
constexpr int kGates = 16;
constexpr double kCarRadius_m = 2.5;

// Gentle hills (steepest slope about 10 degrees), the same at every density.
double height(double x, double z) {
    return 3.0 * std::sin(kTwoPi * x / 256.0) * std::cos(kTwoPi * z / 320.0) +
           2.0 * std::sin(kTwoPi * (x + z) / 180.0);
}

// A point of the lap circle at angle `a`, on the surface, and its heading.
Vec3 lap_point(double a) { return {kLapRadius_m * std::cos(a), 0.0, kLapRadius_m * std::sin(a)}; }
Vec3 lap_heading(double a) { return {-std::sin(a), 0.0, std::cos(a)}; }

Pose pose_at(double a, double lateral_m) {
    const Vec3 heading = lap_heading(a);
    const Vec3 side = heading.cross(Vec3(0, 1, 0));
    Vec3 p = lap_point(a) + side * lateral_m;
    p.y() = height(p.x(), p.z()) + kCarRadius_m + 0.5;
    return {p, heading, Vec3(0, 1, 0)};
}

}  // namespace

Track landscape(int n, int spawn_count) {
    std::vector<Vec3> vertices;
    std::vector<std::uint32_t> indices;
    const auto un = static_cast<std::uint32_t>(n);
    vertices.reserve((un + 1) * (un + 1));
    for (std::uint32_t j = 0; j <= un; ++j) {
        for (std::uint32_t i = 0; i <= un; ++i) {
            const double x = -kLandscapeSide_m / 2 + kLandscapeSide_m * i / n;
            const double z = -kLandscapeSide_m / 2 + kLandscapeSide_m * j / n;
            vertices.emplace_back(x, height(x, z), z);
        }
    }
    indices.reserve(6ull * un * un);
    const auto at = [&](std::uint32_t i, std::uint32_t j) { return j * (un + 1) + i; };
    for (std::uint32_t j = 0; j < un; ++j) {
        for (std::uint32_t i = 0; i < un; ++i) {  // both faces up (+y)
            indices.insert(indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            indices.insert(indices.end(), {at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    }
    std::vector<Checkpoint> gates;
    for (int g = 0; g < kGates; ++g) {
        const double a = kTwoPi * g / kGates;
        Checkpoint c;
        c.normal = lap_heading(a);
        c.up = Vec3(0, 1, 0);
        c.across = c.normal.cross(c.up);
        c.center = lap_point(a);
        c.center.y() = height(c.center.x(), c.center.z()) + 10.0;
        c.half_width_m = 25;
        c.half_height_m = 30;
        c.respawn = pose_at(a, 0.0);
        gates.push_back(c);
    }
    std::vector<Pose> spawns;
    for (int s = 0; s < spawn_count; ++s) {  // two columns, 12 m rows behind gate 0
        const double back_m = 15.0 + 12.0 * (s / 2);
        spawns.push_back(pose_at(-back_m / kLapRadius_m, s % 2 == 0 ? -5.0 : 5.0));
    }
    return make_track("landscape-" + std::to_string(n), vertices, indices, std::move(gates), std::move(spawns), -60.0);
}

}  // namespace jetrace::bench
