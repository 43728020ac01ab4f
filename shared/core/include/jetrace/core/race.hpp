// Race rules: gates in order, laps, finishing, respawn; and standings.
#pragma once

#include "jetrace/core/hovercar.hpp"
#include "jetrace/core/track.hpp"

#include <cstdint>
#include <vector>

namespace jetrace {

/// Applies the rules to one car that moved from `from` to its position
/// during tick `tick`: gate crossing, lap count, finish, respawn below the
/// kill height or after stalling (racing only).
void apply_race_rules(const Track& track, const PhysicsSettings& ps, std::int32_t laps, std::uint32_t tick,
                      bool racing, const Vec3& from, CarState& car);

/// The squared distance from a car to its next gate as the race rules last
/// computed it for a car that did not move, kept by the caller (a parked
/// car asks for the same one tick after tick). A cache of a pure function
/// of the track's gate and the position: it never changes a result. It
/// belongs to one track.
struct GateDistanceMemo {
    Vec3 at{0, 0, 0};
    std::int32_t gate = -1;  // none yet
    double d2_m2 = 0;
};

/// apply_race_rules() for a car that has not moved during tick `tick` (its
/// position is, bit for bit, where the tick began: a parked car), which
/// crosses no gate; its distance to the gate comes from `memo` where the
/// memo has it. The same result as apply_race_rules() with `from` its
/// position.
void apply_race_rules_still(const Track& track, const PhysicsSettings& ps, std::int32_t laps, std::uint32_t tick,
                            bool racing, CarState& car, GateDistanceMemo& memo);

/// Equal-mass sphere-sphere collisions between all active cars, in slot-pair
/// order (i < j): separate the pair and make the collision inelastic along
/// the line of centres (momentum conserved). Returns the pairs found
/// overlapping (0: no car was changed).
int collide_cars(double radius_m, std::vector<CarState>& cars);

struct Standing {
    int slot = 0;
    bool finished = false;
    std::int32_t lap = 0;
    std::int32_t next_checkpoint = 0;
    /// Time of finish (unit: s), valid when finished.
    double finish_time_s = 0;
};

/// Race order: finished cars by finish time (tick, then fraction, then slot),
/// then the others by progress (lap, gates passed, distance to next gate).
std::vector<Standing> standings(const Track& track, const std::vector<CarState>& cars, std::uint32_t start_tick,
                                int tick_rate_hz);

}  // namespace jetrace
