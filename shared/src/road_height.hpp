// The height of the road at a point of the ground plan, from the track's
// triangles through its grid: what RoadProfile samples along the route.
// Internal to jetrace::core.
#pragma once

#include "jetrace/track.hpp"
#include "jetrace/uniform_grid.hpp"

namespace jetrace::detail {

/// Height of the highest of `track`'s triangles (found through `grid`, built
/// over them) that faces upwards (unit normal's y at least `min_up`) above
/// the point (x, z) of the ground plan, between `y_lo` and `y_hi` (unit: m).
/// False if there is none.
bool road_height(const Track& track, const UniformGrid& grid, double x, double z, double y_lo, double y_hi,
                 double min_up, double& y);

}  // namespace jetrace::detail
