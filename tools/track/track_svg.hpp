// The top-down SVG of `jetrace-track render`: the mesh as cells (floors
// faint, walls and steep faces darker), the route, numbered gates with
// arrows for their direction, and the spawns.
#pragma once

#include "jetrace/track.hpp"
#include "jetrace/track_manifest.hpp"

#include <string>

namespace jetrace::tools {

/// The SVG text, `width_px` wide (x to the right, z down: seen from above).
std::string render_svg(const Track& track, const TrackReport& report, int width_px);

}  // namespace jetrace::tools
