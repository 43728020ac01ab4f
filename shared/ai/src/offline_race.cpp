#include "jetrace/ai/offline_race.hpp"

#include "jetrace/ai/pilot.hpp"

#include <random>

namespace jetrace {

std::vector<DriverSkill> skills_for(int cars, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const auto unit = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    std::vector<DriverSkill> out(static_cast<std::size_t>(cars));
    for (DriverSkill& s : out) {
        s.corner_mps2 = 24.0 + 10.0 * unit();
        s.lookahead_m = 30.0 + 15.0 * unit();
        s.steer_gain = 2.0 + 1.5 * unit();
    }
    // The speed at the top of a climb, drawn after the rest (which stay as
    // they were): cars that all leave the top of the stadium's wall at one
    // speed fly one path a few metres apart and land on one another.
    for (DriverSkill& s : out) s.climb_top_mps = 25.0 + 20.0 * unit();
    return out;
}

WorldState start_race(const Scene& scene, int cars, int laps) {
    WorldState st = make_world(cars, laps);
    for (int i = 0; i < cars; ++i) spawn_car(scene, st, i, i);
    return st;
}

std::uint32_t run_ai(const Course& course, WorldState& state, const std::vector<DriverSkill>& skills, std::uint32_t ticks,
                     bool stop_when_finished, StepScratch& scratch, StepObserver* observer) {
    std::vector<Input> inputs(state.cars.size());
    std::vector<Pilot> pilots;
    pilots.reserve(state.cars.size());
    for (std::size_t i = 0; i < state.cars.size(); ++i) pilots.emplace_back(i < skills.size() ? skills[i] : DriverSkill{});
    for (std::uint32_t t = 0; t < ticks; ++t) {
        bool all_done = true;
        for (std::size_t i = 0; i < state.cars.size(); ++i) {
            inputs[i] = pilots[i].next(course, state, static_cast<int>(i), &scratch);
            if (state.cars[i].active && !state.cars[i].finished) all_done = false;
        }
        if (stop_when_finished && all_done) return t;
        if (observer) observer->before_step(state, inputs);
        step(course.scene(), state, inputs, scratch);
        if (observer) observer->after_step(state);
    }
    return ticks;
}

}  // namespace jetrace
