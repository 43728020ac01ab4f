// Lap and gap timing of a recorded race: the tick of every gate a car
// passed, gathered while the replay is re-simulated once, then asked about
// any tick (only passes up to that tick count, so seeking back shows what
// was known then).
#pragma once

#include "jetrace/core/race.hpp"
#include "jetrace/core/world.hpp"

#include <cstdint>
#include <optional>
#include <vector>

namespace jetrace::view {

class RaceTiming {
public:
    /// Starts from the race's first state on a track of `gates` gates.
    void start(const WorldState& initial, int gates);
    /// After each step: records the gates each car passed in it.
    void after_step(const WorldState& state);

    /// Gates car `slot` had passed by `tick`.
    std::size_t passes(int slot, std::uint32_t tick) const;
    /// Fastest whole lap car `slot` had completed by `tick` (unit: s).
    std::optional<double> best_lap_s(int slot, std::uint32_t tick, int tick_rate_hz) const;
    /// Time behind `leader` at the last gate `slot` had passed by `tick`
    /// (unit: s); none for the leader itself or before the first gate.
    std::optional<double> gap_s(int slot, int leader, std::uint32_t tick, int tick_rate_hz) const;

private:
    struct Progress {
        std::int32_t lap = 0;
        std::int32_t next_checkpoint = 0;
        bool finished = false;
        bool operator==(const Progress&) const = default;
    };
    int gates_ = 0;
    std::vector<Progress> last_;
    /// Per slot: the world tick after the step in which each gate was passed.
    std::vector<std::vector<std::uint32_t>> pass_ticks_;
};

}  // namespace jetrace::view
