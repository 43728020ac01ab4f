#include "jetrace/ai/pilot.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

std::uint32_t think_ticks(double tick_rate_hz) {
    const double every = std::round(tick_rate_hz / kThinkRate_hz);
    return every >= 1.0 ? static_cast<std::uint32_t>(std::min(every, 1e6)) : 1u;
}

Input Pilot::decide(const Course& course, const WorldState& state, int slot, const StepScratch* stepped) {
    const auto i = static_cast<std::size_t>(slot);
    const CarState& car = state.cars[i];
    const bool follows = holding_ && state.tick == last_tick_ + 1 && car.respawns == respawns_;
    const int rate_hz = course.scene().physics.tick_rate_hz;
    if (rate_hz != rate_hz_) {
        rate_hz_ = rate_hz;
        every_ = think_ticks(rate_hz);
    }
    if (!follows || thinks_on(state.tick, slot, every_)) {
        const CarScratch* kept = stepped != nullptr && i < stepped->cars.size() ? &stepped->cars[i] : nullptr;
        held_ = drive(course, state, slot, skill_, kept);
        holding_ = true;
    }
    last_tick_ = state.tick;
    respawns_ = car.respawns;
    return held_;
}

}  // namespace jetrace
