// The step's shortcut for a car at rest (CarScratch::rest): a car its last
// step left exactly as it found it, found so again with the same input,
// skips its contacts, forces, push-out and alignment. It must change no
// bit: races stepped with it and with it turned off (rest_valid cleared
// before every step) agree at every tick, through a countdown (every car
// braked at rest), a finish (finished cars held by the brake on the line)
// and the cars that arrive later and run into them, and a parked car that
// the rules respawn for making no progress. The runs without it also forget
// the race rules' kept distance to the gate (CarScratch::gate_distance).
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/ai/pilot.hpp"
#include "jetrace/core/race.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <span>
#include <vector>

namespace {

struct Counts {
    int asleep = 0;  // car-steps that took the shortcut
};

jetrace::Scene builtin_scene(const char* track_name) {
    jetrace::Track t;
    EXPECT_TRUE(jetrace::make_builtin_track(track_name, t)) << track_name;
    return jetrace::Scene::make(std::move(t), jetrace::PhysicsSettings{});
}

// One world stepped twice alike: `a` as the step runs, `b` with the
// shortcut and the kept gate distance forgotten before every step.
struct Twins {
    jetrace::WorldState a, b;
    jetrace::StepScratch with, without;

    explicit Twins(const jetrace::WorldState& start) : a(start), b(start) {}
    // Steps both; true if they agree after it.
    bool step(const jetrace::Scene& scene, std::span<const jetrace::Input> in) {
        jetrace::step(scene, a, in, with);
        for (auto& cs : without.cars) {
            cs.rest_valid = false;
            cs.gate_distance = {};
        }
        jetrace::step(scene, b, in, without);
        return jetrace::state_hash(a) == jetrace::state_hash(b);
    }
};

void expect_same_race(const char* track_name, int cars, std::uint64_t seed, std::uint32_t countdown,
                      std::uint32_t ticks, Counts& counts) {
    const jetrace::Scene scene = builtin_scene(track_name);
    const jetrace::Course course(scene);
    jetrace::WorldState start = jetrace::make_world(cars, 1, countdown);
    for (int i = 0; i < cars; ++i) jetrace::spawn_car(scene, start, i, i);
    Twins w(start);
    const auto skills = jetrace::skills_for(cars, seed);
    std::vector<jetrace::Pilot> pilots;
    for (const auto& s : skills) pilots.emplace_back(s);
    std::vector<jetrace::Input> in(static_cast<std::size_t>(cars));
    for (std::uint32_t k = 0; k < ticks; ++k) {
        for (int i = 0; i < cars; ++i) in[static_cast<std::size_t>(i)] = pilots[static_cast<std::size_t>(i)].next(course, w.a, i);
        ASSERT_TRUE(w.step(scene, in)) << track_name << ", seed " << seed << ": the worlds differ after tick " << w.a.tick;
        for (const auto& cs : w.with.cars) counts.asleep += cs.asleep ? 1 : 0;
    }
}

}  // namespace

TEST(Rest, ARaceWithACountdownAndParkedFinishersIsTheSameWithoutTheShortcut) {
    Counts counts;
    // ring: a 1-lap race of about 15 s with a 2 s countdown, then 25 s of
    // finished cars held on and past the line while the rest arrive.
    for (std::uint64_t seed : {1u, 2u}) expect_same_race("ring", 8, seed, 240, 40 * 120, counts);
    std::printf("car-steps at rest through the shortcut: %d\n", counts.asleep);
    // The countdown alone is 8 cars x 240 ticks a race, most of them asleep.
    EXPECT_GT(counts.asleep, 2 * 8 * 200);
}

TEST(Rest, AParkedCarRunIntoIsPushedAsWithoutTheShortcut) {
    // Two cars: one parked (finished and braked) on the road, one driven
    // into it from behind at 30 m/s; the shortcut must give way to the
    // whole step when the other car moves it.
    const jetrace::Scene scene = builtin_scene("ring");
    jetrace::WorldState start = jetrace::make_world(2, 1);
    jetrace::spawn_car(scene, start, 0, 0);
    jetrace::spawn_car(scene, start, 1, 0);
    start.cars[0].finished = true;
    jetrace::CarState& hitter = start.cars[1];
    hitter.position -= hitter.forward() * 30.0;
    hitter.velocity = hitter.forward() * 30.0;
    Twins w(start);
    const std::vector<jetrace::Input> in = {jetrace::Input{}, jetrace::Input{}};
    int asleep_before_hit = 0;
    bool moved = false;
    const jetrace::Vec3 parked_at = start.cars[0].position;
    for (int k = 0; k < 240; ++k) {
        ASSERT_TRUE(w.step(scene, in)) << "the worlds differ after tick " << w.a.tick;
        if (!moved && w.with.cars[0].asleep) ++asleep_before_hit;
        moved = moved || (w.a.cars[0].position - parked_at).norm() > 0.5;
    }
    EXPECT_GT(asleep_before_hit, 10);  // it slept before the hit
    EXPECT_TRUE(moved);                // and the hit moved it
}

TEST(Rest, AParkedCarThatMakesNoProgressIsRespawnedOnTheSameTickAsWithoutTheShortcut) {
    // One car racing from tick 0 with no input: it settles on the grid and
    // stays there, asleep, while the rules count its ticks without
    // progress; after no_progress_s they respawn it, and it settles again.
    const jetrace::Scene scene = builtin_scene("ring");
    jetrace::WorldState start = jetrace::make_world(1, 1);
    jetrace::spawn_car(scene, start, 0, 0);
    Twins w(start);
    const jetrace::Input idle{};
    const auto stall_ticks = static_cast<int>(scene.physics.no_progress_s * scene.physics.tick_rate_hz);
    int asleep = 0;
    for (int k = 0; k < stall_ticks + 240; ++k) {
        ASSERT_TRUE(w.step(scene, {&idle, 1})) << "the worlds differ after tick " << w.a.tick;
        asleep += w.with.cars[0].asleep ? 1 : 0;
    }
    EXPECT_EQ(w.a.cars[0].respawns, 1u);
    EXPECT_GT(asleep, stall_ticks - 240);  // asleep through most of the stall
}

TEST(Rest, TheCarCollisionsCountThePairsTheyChange) {
    std::vector<jetrace::CarState> cars(3);
    for (std::size_t i = 0; i < cars.size(); ++i) {
        cars[i].active = true;
        cars[i].position = jetrace::Vec3(20.0 * static_cast<double>(i), 0, 0);
    }
    const std::vector<jetrace::CarState> apart = cars;
    EXPECT_EQ(jetrace::collide_cars(2.5, cars), 0);
    for (std::size_t i = 0; i < cars.size(); ++i) EXPECT_EQ(cars[i].position, apart[i].position);
    cars[1].position = jetrace::Vec3(3.0, 0, 0);  // 3 m from car 0: the radii overlap by 2 m
    EXPECT_EQ(jetrace::collide_cars(2.5, cars), 1);
    EXPECT_NEAR((cars[1].position - cars[0].position).norm(), 5.0, 1e-12);
}
