// The reachability part of the drivability checks (gate_unreachable).
// Internal to jetrace::tracks.
#pragma once

#include "jetrace/tracks/drivability.hpp"

namespace jetrace::detail {

/// Walks every leg (gate k-1's road to gate k's road, gate 0's from the
/// last gate) and appends a gate_unreachable warning for each gate its leg
/// does not reach over a continuous surface.
void check_legs(const Track& track, const UniformGrid& grid, const DrivabilityLimits& limits,
                std::vector<DrivabilityWarning>& out);

}  // namespace jetrace::detail
