// One AI driver at its think rate: the driving AI (drive()) run 30 times a
// second, each car on its own tick, its input held between. That is the
// rate a person's hands change their input at, a quarter of the AI's cost
// at 120 Hz, and inputs that change rarely are what a client predicting
// other cars (it repeats their last input) guesses right.
#pragma once

#include "jetrace/ai/driver_ai.hpp"

#include <cstdint>

namespace jetrace {

/// Decisions a second the AI makes (unit: Hz).
inline constexpr double kThinkRate_hz = 30.0;

/// Ticks between one car's decisions at tick rate `tick_rate_hz`: the
/// tick rate over kThinkRate_hz, rounded, at least 1 (4 at 120 Hz).
std::uint32_t think_ticks(double tick_rate_hz);

/// True if car `slot` decides on tick `tick`: one tick in think_ticks(),
/// the cars spread over them by slot.
inline bool thinks_on(std::uint32_t tick, int slot, std::uint32_t every) {
    return (tick + static_cast<std::uint32_t>(slot)) % every == 0;
}

/// One car's AI: its skill, the course of whichever scene it races on, and
/// the input it holds between decisions. A function object for
/// client::InputSource (pass it by reference: a copy holds its own input).
class Pilot {
public:
    explicit Pilot(const DriverSkill& skill = {}) : skill_(skill) {}

    /// The input of car `slot` for the tick after `state.tick` on `scene`.
    Input operator()(const Scene& scene, const WorldState& state, int slot) { return next(course_(scene), state, slot); }

    /// The same on a course the caller keeps (an offline race shares one).
    /// It decides on its thinking ticks, and on any other if it has not
    /// decided on the tick before (its first tick, a world that jumped, as
    /// a client's does when it resynchronises) or the car was respawned.
    /// `stepped`: the scratch of the step that made `state`, if the caller
    /// has it (drive() reads the contacts it kept; the same decisions).
    Input next(const Course& course, const WorldState& state, int slot, const StepScratch* stepped = nullptr) {
        // Holding: the tick after the last, the same car, the same rate,
        // not a thinking tick (inline: three ticks in four end here).
        if (holding_ && state.tick == last_tick_ + 1 &&
            state.cars[static_cast<std::size_t>(slot)].respawns == respawns_ &&
            course.scene().physics.tick_rate_hz == rate_hz_ && !thinks_on(state.tick, slot, every_)) {
            last_tick_ = state.tick;
            return held_;
        }
        return decide(course, state, slot, stepped);
    }

    const DriverSkill& skill() const { return skill_; }

private:
    // next() on any other tick: decides if it is to (and keeps the rate).
    Input decide(const Course& course, const WorldState& state, int slot, const StepScratch* stepped);

    DriverSkill skill_;
    CourseCache course_;
    Input held_{};
    bool holding_ = false;
    // think_ticks() of the tick rate last raced at (kept: it rounds).
    int rate_hz_ = 0;
    std::uint32_t every_ = 1;
    std::uint32_t last_tick_ = 0;
    std::uint32_t respawns_ = 0;
};

}  // namespace jetrace
