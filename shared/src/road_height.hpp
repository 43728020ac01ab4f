// The height of the road at a point of the ground plan, from the track's
// triangles through the scene's grid: what the driving AI reads to see a
// crest ahead. Internal to jetrace::core.
#pragma once

#include "jetrace/world.hpp"

namespace jetrace::detail {

/// Height of the highest triangle facing upwards (unit normal's y at least
/// `min_up`) above the point (x, z) of the ground plan, between `y_lo` and
/// `y_hi` (unit: m). False if there is none.
bool road_height(const Scene& sc, double x, double z, double y_lo, double y_hi, double min_up, double& y);

}  // namespace jetrace::detail
