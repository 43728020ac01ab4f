// The top-down SVG of `jetrace-track render`: the mesh as cells (floors
// faint, walls and steep faces darker), the route, numbered gates with
// arrows for their direction, and the spawns; optionally cars' lines over
// a race, coloured by speed.
#pragma once

#include "jetrace/core/track.hpp"
#include "jetrace/tracks/track_manifest.hpp"

#include <span>
#include <string>
#include <vector>

namespace jetrace::tools {

/// One car's line over a race (jetrace-sim --replay FILE --svg): its
/// centre at successive moments and its speed there.
struct SvgTrace {
    std::string name;
    std::vector<Vec3> points;
    /// One per point (unit: m/s).
    std::vector<double> speeds_mps;
};

/// The SVG text, `width_px` wide (x to the right, z down: seen from above).
std::string render_svg(const Track& track, const TrackReport& report, int width_px);
/// The same with each trace drawn over it, coloured by speed (blue slow,
/// red fast, a legend of the range), named at its last point.
std::string render_svg(const Track& track, const TrackReport& report, int width_px, std::span<const SvgTrace> traces);

}  // namespace jetrace::tools
