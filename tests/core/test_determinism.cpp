// Determinism: the pinned golden hash of a fixed race (Box2D's
// EXPECTED_HASH), identical under g++ and clang++ at -O0 and -O2 (tools/test.sh
// builds this test in those configurations), and repeatability in-process.
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <gtest/gtest.h>

namespace {

// 8 AI cars, 60 simulated seconds (7,200 ticks) on `stadium`, skills seed 1,
// 3 laps, default PhysicsSettings. Equals `jetrace-sim --track stadium
// --cars 8 --seconds 60 --seed 1`. Change it only with a change of the
// physics or of the driving AI (which drives the race), and say so in the
// commit.
constexpr std::uint64_t kGoldenStadiumHash = 0xf1129698fddce275ull;

std::uint64_t race_hash(const std::string& track_name, int cars, std::uint32_t ticks, std::uint64_t seed) {
    jetrace::Track track;
    EXPECT_TRUE(jetrace::make_builtin_track(track_name, track));
    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), jetrace::PhysicsSettings{});
    jetrace::WorldState st = jetrace::start_race(scene, cars, 3);
    jetrace::StepScratch scratch;
    jetrace::run_ai(jetrace::Course(scene), st, jetrace::skills_for(cars, seed), ticks, false, scratch);
    return jetrace::state_hash(st);
}

}  // namespace

TEST(Determinism, GoldenStadiumRace) {
    const std::uint64_t h = race_hash("stadium", 8, 60 * 120, 1);
    EXPECT_EQ(jetrace::hash_hex(h), jetrace::hash_hex(kGoldenStadiumHash))
        << "the 8-car 60 s race on stadium no longer reproduces the pinned state hash";
}

TEST(Determinism, SameRaceTwiceSameHash) {
    EXPECT_EQ(race_hash("ring", 6, 2400, 7), race_hash("ring", 6, 2400, 7));
}

TEST(Determinism, SeedChangesTheRace) {
    EXPECT_NE(race_hash("ring", 6, 2400, 7), race_hash("ring", 6, 2400, 8));
}

TEST(Determinism, HashCoversEveryField) {
    jetrace::WorldState a = jetrace::make_world(2, 3);
    const std::uint64_t base = jetrace::state_hash(a);
    auto changed = [&](auto mutate) {
        jetrace::WorldState b = a;
        mutate(b);
        return jetrace::state_hash(b) != base;
    };
    EXPECT_TRUE(changed([](auto& s) { s.tick = 1; }));
    EXPECT_TRUE(changed([](auto& s) { s.start_tick = 1; }));
    EXPECT_TRUE(changed([](auto& s) { s.laps = 4; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].active = true; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].finished = true; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].position.z() = 1e-300; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].velocity.x() = -0.0; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].orientation.x() = 1e-9; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].next_checkpoint = 2; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].lap = 2; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].respawn_checkpoint = 2; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].finish_tick = 2; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].finish_fraction = 0.5; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].respawns = 1; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].best_gate_distance_m = 3; }));
    EXPECT_TRUE(changed([](auto& s) { s.cars[1].no_progress_ticks = 3; }));
}

TEST(Determinism, DeterministicTrigMatchesReference) {
    // det_sin/det_cos are what the step uses instead of libm; check accuracy
    // (libm is only the reference here, never on the step path).
    for (int i = -1000; i <= 1000; ++i) {
        const double x = i * 0.01;
        EXPECT_NEAR(jetrace::det_sin(x), std::sin(x), 1e-9) << x;
        EXPECT_NEAR(jetrace::det_cos(x), std::cos(x), 1e-9) << x;
    }
}
