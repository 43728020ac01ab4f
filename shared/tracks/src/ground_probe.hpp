// Probes of a track's surfaces through its uniform grid, for the
// drivability checks (drivability.cpp, drivability_legs.cpp). Internal to
// jetrace::tracks.
#pragma once

#include "jetrace/core/track.hpp"
#include "jetrace/core/uniform_grid.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace jetrace::detail {

/// A surface met by a vertical probe: its height at the probe and its unit
/// normal, turned to face upwards (faces are wound either way).
struct ColumnHit {
    double y = 0;
    Vec3 normal{0, 1, 0};
};

/// Every non-degenerate triangle of `track` (found through `grid`) that the
/// vertical line through (x, z) meets between heights y_lo and y_hi (unit:
/// m), in no particular order. Faces parallel to the line are not met.
void column_hits(const Track& track, const UniformGrid& grid, double x, double z, double y_lo, double y_hi,
                 std::vector<ColumnHit>& out);

/// The nearest triangle that the ray o + t d (d a unit vector, 0 <= t <=
/// max_t) meets, through `grid`. False if none.
bool cast_ray(const Track& track, const UniformGrid& grid, const Vec3& o, const Vec3& d, double max_t, double& t,
              std::uint32_t& triangle);

/// True if every coordinate of `v` is finite.
bool finite(const Vec3& v);

/// "(x, y, z)" to 0.1 m, for messages.
std::string at(const Vec3& v);

}  // namespace jetrace::detail
