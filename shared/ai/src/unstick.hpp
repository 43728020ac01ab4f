// What the driving AI does when it has made no progress for a while: the
// way out from an obstacle it is pinned against, else turning on the spot
// towards its aim. Internal to jetrace::ai.
#pragma once

#include "jetrace/core/world.hpp"

namespace jetrace::ai_detail {

/// The input for car `car` if it is stuck: no progress towards its gate
/// for 1.5 s at under 6 m/s. `d` is the unit direction to its aim (in the
/// plane across its up), `error` the heading error to it and `speed` its
/// speed in that plane (unit: m/s). False (and `out` untouched) if it is not
/// stuck.
bool unstick(const Scene& sc, const CarState& car, const Vec3& d, double error, double speed, Input& out);

}  // namespace jetrace::ai_detail
