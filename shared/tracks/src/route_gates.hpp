// Gates and spawns placed on a mesh from a manifest's route or gates, and the
// checks on them (docs/TRACKS.md, "Checks"). Internal to jetrace::tracks.
#pragma once

#include "jetrace/tracks/track_manifest.hpp"

#include <string>
#include <utility>
#include <vector>

namespace jetrace::detail {

/// The assembled track's triangles with the part each came from.
struct Surface {
    const std::vector<Triangle>& tris;
    /// (one past the last triangle, part name), ascending.
    std::vector<std::pair<std::size_t, std::string>> parts;
    Aabb bounds;
    RouteSurface mode = RouteSurface::lowest;

    const std::string& part_of(std::size_t tri) const;
};

/// A car's height: two resting radii (unit: m).
inline constexpr double kCarHeight_m = 2 * (2.5 + 1.0 / 1024.0);

/// Fills track.checkpoints and track.spawns from the manifest's route or
/// gates, and report.route / route_length_m / warnings.
bool place_gates_and_spawns(const TrackManifest& m, const Surface& s, Track& track, TrackReport& report,
                            std::string& error);

/// "(x, y, z)" with one decimal.
std::string where(const Vec3& p);

}  // namespace jetrace::detail
