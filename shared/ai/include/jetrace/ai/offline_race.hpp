// An offline race of AI cars: the loop behind jetrace-sim and the golden
// determinism test.
#pragma once

#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/core/world.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace jetrace {

/// Per-car driving skills drawn from `seed` (fixed bit-level mapping from
/// std::mt19937_64, whose output the C++ standard pins down).
std::vector<DriverSkill> skills_for(int cars, std::uint64_t seed);

/// A world with `cars` cars on the grid, racing `laps` laps from tick 0.
WorldState start_race(const Scene& scene, int cars, int laps);

/// Sees every step of run_ai() (a replay recorder, for one).
class StepObserver {
public:
    virtual ~StepObserver() = default;
    /// Before stepping `state` with `inputs`.
    virtual void before_step(const WorldState& state, std::span<const Input> inputs) = 0;
    /// After the step.
    virtual void after_step(const WorldState& state) = 0;
};

/// Steps `ticks` ticks with every car driven by the AI. Stops early once
/// every car has finished if `stop_when_finished`. Returns the ticks stepped.
std::uint32_t run_ai(const Course& course, WorldState& state, const std::vector<DriverSkill>& skills, std::uint32_t ticks,
                     bool stop_when_finished, StepScratch& scratch, StepObserver* observer = nullptr);

}  // namespace jetrace
