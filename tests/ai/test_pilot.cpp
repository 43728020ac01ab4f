// The AI at its think rate (Pilot): it decides once every think_ticks()
// ticks, each car on its own tick, holds its input between, and decides at
// once on its first tick, after the world jumps, and after a respawn.
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/ai/pilot.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

namespace {

jetrace::Scene stadium() {
    jetrace::Track t;
    EXPECT_TRUE(jetrace::make_builtin_track("stadium", t));
    return jetrace::Scene::make(std::move(t), jetrace::PhysicsSettings{});
}

}  // namespace

TEST(Pilot, ThinkTicksAreTheTickRateOverThirtyHertz) {
    EXPECT_EQ(jetrace::think_ticks(120), 4u);
    EXPECT_EQ(jetrace::think_ticks(60), 2u);
    EXPECT_EQ(jetrace::think_ticks(240), 8u);
    EXPECT_EQ(jetrace::think_ticks(30), 1u);
    EXPECT_EQ(jetrace::think_ticks(10), 1u);
}

TEST(Pilot, DecidesOnItsOwnTickAndHoldsTheInputBetween) {
    const jetrace::Scene scene = stadium();
    const jetrace::Course course(scene);
    constexpr int kCars = 4;
    jetrace::WorldState st = jetrace::start_race(scene, kCars, 1);
    const auto skills = jetrace::skills_for(kCars, 5);
    std::vector<jetrace::Pilot> pilots;
    for (const auto& s : skills) pilots.emplace_back(s);
    std::vector<jetrace::Input> in(kCars);
    jetrace::StepScratch scratch;
    int changed_off_tick = 0, decisions_checked = 0;
    for (int t = 0; t < 20 * 120; ++t) {
        for (int i = 0; i < kCars; ++i) {
            const jetrace::Input before = in[static_cast<std::size_t>(i)];
            const jetrace::Input got = pilots[static_cast<std::size_t>(i)].next(course, st, i);
            if (t > 0 && !jetrace::thinks_on(st.tick, i, 4) && st.cars[static_cast<std::size_t>(i)].respawns == 0 &&
                !(got == before)) {
                ++changed_off_tick;
            }
            // On its thinking tick it gives what the AI gives.
            if (jetrace::thinks_on(st.tick, i, 4)) {
                EXPECT_EQ(got, jetrace::drive(course, st, i, skills[static_cast<std::size_t>(i)])) << "tick " << st.tick;
                ++decisions_checked;
            }
            in[static_cast<std::size_t>(i)] = got;
        }
        jetrace::step(scene, st, in, scratch);
    }
    EXPECT_EQ(changed_off_tick, 0);
    EXPECT_EQ(decisions_checked, 20 * 120);  // each car one tick in four
}

TEST(Pilot, DecidesAtOnceOnItsFirstTickAfterAJumpAndAfterARespawn) {
    const jetrace::Scene scene = stadium();
    const jetrace::Course course(scene);
    // Two worlds the AI answers differently: the car on its spawn, and the
    // same car turned a quarter round (it steers the other way).
    jetrace::WorldState a = jetrace::start_race(scene, 1, 1);
    a.tick = 401;  // not car 0's own tick (401 % 4 != 0), nor the next
    jetrace::WorldState b = a;
    const jetrace::CarState& c = a.cars[0];
    b.cars[0].orientation = jetrace::orientation_from(c.forward().cross(c.up()), c.up());
    const jetrace::Input in_a = jetrace::drive(course, a, 0), in_b = jetrace::drive(course, b, 0);
    ASSERT_NE(in_a, in_b);
    ASSERT_FALSE(jetrace::thinks_on(402, 0, 4));

    jetrace::Pilot p;
    EXPECT_EQ(p.next(course, a, 0), in_a);  // its first tick
    b.tick = 402;
    EXPECT_EQ(p.next(course, b, 0), in_a);  // the next, not its own: held
    b.tick = 407;
    EXPECT_EQ(p.next(course, b, 0), in_b);  // a jump (407 is not 403): decides
    a.tick = 408;
    EXPECT_EQ(p.next(course, a, 0), in_a);  // its own tick (408 % 4 == 0)
    b.tick = 409;
    EXPECT_EQ(p.next(course, b, 0), in_a);  // held
    b.tick = 410;
    b.cars[0].respawns = 1;
    EXPECT_EQ(p.next(course, b, 0), in_b);  // respawned: decides
    a.tick = 411;
    a.cars[0].respawns = 1;
    EXPECT_EQ(p.next(course, a, 0), in_b);  // held
}

TEST(Pilot, TheContactsTheStepKeptGiveTheSameDecisionsAsTheAisOwnQuery) {
    // drive() told the car's step scratch reads "on the track?" from the
    // contacts the step kept where the car is; every decision must be the
    // one it makes without them, on the ground, in the air and respawned.
    const jetrace::Scene scene = stadium();
    const jetrace::Course course(scene);
    constexpr int kCars = 8;
    jetrace::WorldState st = jetrace::start_race(scene, kCars, 1);
    const auto skills = jetrace::skills_for(kCars, 11);
    std::vector<jetrace::Input> in(kCars);
    jetrace::StepScratch scratch;
    int kept_used = 0, kept_off_track = 0, decisions = 0;
    for (int t = 0; t < 60 * 120; ++t) {
        for (int i = 0; i < kCars; ++i) {
            const auto k = static_cast<std::size_t>(i);
            const jetrace::CarScratch* kept = t > 0 ? &scratch.cars[k] : nullptr;
            const jetrace::Input with = jetrace::drive(course, st, i, skills[k], kept);
            const jetrace::Input without = jetrace::drive(course, st, i, skills[k]);
            ASSERT_EQ(with, without) << "car " << i << " at tick " << st.tick;
            if (kept != nullptr && kept->contacts_valid && jetrace::same(kept->contacts_at, st.cars[k].position)) {
                ++kept_used;
                kept_off_track += kept->contacts.empty() ? 1 : 0;
            }
            ++decisions;
            in[k] = with;
        }
        jetrace::step(scene, st, in, scratch);
    }
    std::printf("decisions %d, kept contacts used %d (%d of them off the track)\n", decisions, kept_used,
                kept_off_track);
    EXPECT_GT(kept_used, decisions * 9 / 10);
    EXPECT_GT(kept_off_track, 0);  // the stadium's jumps: cars in the air
}
