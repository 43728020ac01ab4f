// The client's Predictor against the plain reconciliation it shortens: after
// every snapshot its world must equal, bit for bit, the server's state at the
// snapshot's tick replayed to the predicted tick with the snapshot's best
// known inputs for every tick and every car. Snapshots of an offline AI race
// (the server's side) come every 2 ticks, some late or missing, each with a
// random number of the upcoming inputs; the seed is printed.
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/client/predictor.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace {

using jetrace::Input;
using jetrace::WorldState;
using jetrace::client::Predictor;

// What the server's side of the test keeps: its world and inputs by tick.
struct ServerRun {
    std::vector<WorldState> worlds;  // at the start of tick t
    std::vector<std::vector<Input>> inputs;  // stepped with at tick t
};

ServerRun run_server(const jetrace::Scene& scene, int cars, std::uint32_t ticks) {
    ServerRun run;
    WorldState w = jetrace::start_race(scene, cars, 1);
    const auto skills = jetrace::skills_for(cars, 7);
    const jetrace::Course course(scene);
    jetrace::StepScratch scratch;
    for (std::uint32_t t = 0; t < ticks; ++t) {
        std::vector<Input> in(w.cars.size());
        for (int s = 0; s < cars; ++s) in[static_cast<std::size_t>(s)] = jetrace::drive(course, w, s, skills[s]);
        run.worlds.push_back(w);
        run.inputs.push_back(in);
        jetrace::step(scene, w, in, scratch);
    }
    run.worlds.push_back(w);
    return run;
}

jetrace::proto::WorldSnapshot snapshot_at(const ServerRun& run, std::uint32_t S, std::mt19937_64& rng) {
    jetrace::proto::WorldSnapshot snap;
    snap.state = run.worlds[S];
    const std::size_t n = snap.state.cars.size();
    snap.last_inputs = S > 0 ? run.inputs[S - 1] : std::vector<Input>(n);
    snap.upcoming.resize(n);
    for (std::size_t s = 0; s < n; ++s) {
        const auto k = static_cast<std::uint32_t>(rng() % (jetrace::proto::kMaxUpcomingInputs + 1));
        for (std::uint32_t i = 0; i < k && S + i < run.inputs.size(); ++i) snap.upcoming[s].push_back(run.inputs[S + i][s]);
    }
    return snap;
}

Input known(const jetrace::proto::WorldSnapshot& snap, std::size_t s, std::uint32_t t) {
    const auto& up = snap.upcoming[s];
    if (up.empty()) return snap.last_inputs[s];
    const std::uint32_t k = t - snap.state.tick;
    return k < up.size() ? up[k] : up.back();
}

// The plain reconciliation: every tick from the snapshot's, every car.
WorldState full_replay(const jetrace::Scene& scene, const jetrace::proto::WorldSnapshot& snap, std::size_t own,
                       const std::vector<Input>& mine, std::uint32_t target) {
    WorldState w = snap.state;
    jetrace::StepScratch scratch;
    std::vector<Input> in(w.cars.size());
    for (std::uint32_t t = snap.state.tick; t < target; ++t) {
        for (std::size_t s = 0; s < in.size(); ++s) in[s] = known(snap, s, t);
        in[own] = mine[t];
        jetrace::step(scene, w, in, scratch);
    }
    return w;
}

// `expect_skips`: some reconciliations must have found nothing to replay.
void check_track(const std::string& track, int cars, std::uint32_t ticks, std::uint64_t seed, bool expect_skips) {
    std::printf("track %s, %d cars, seed %llu\n", track.c_str(), cars, static_cast<unsigned long long>(seed));
    jetrace::Track t;
    jetrace::make_builtin_track(track, t);
    const auto scene = jetrace::Scene::make(std::move(t), jetrace::PhysicsSettings{});
    const ServerRun run = run_server(scene, cars, ticks);
    std::mt19937_64 rng(seed);
    const std::size_t own = 1;
    std::vector<Input> mine(ticks);
    for (std::uint32_t i = 0; i < ticks; ++i) mine[i] = run.inputs[i][own];
    Predictor p;
    p.start(run.worlds[0]);
    jetrace::proto::WorldSnapshot latest = snapshot_at(run, 0, rng);
    int checks = 0;
    for (std::uint32_t tick = 0; tick + 1 < ticks; ++tick) {
        p.run_tick(scene, own, mine[p.world().tick], latest);
        const std::uint32_t lead = 3 + static_cast<std::uint32_t>(rng() % 12);  // 3..14 ticks behind
        if (tick % 2 != 0 || rng() % 10 == 0 || p.world().tick < lead) continue;  // every 2 ticks, 10 % lost
        const std::uint32_t S = p.world().tick - lead;
        if (S <= latest.state.tick) continue;
        latest = snapshot_at(run, S, rng);
        const std::uint32_t target = p.world().tick;
        p.reconcile(scene, latest, own, true);
        const WorldState want = full_replay(scene, latest, own, mine, target);
        ASSERT_TRUE(jetrace::client::same_world(p.world(), want)) << "tick " << target << " from snapshot " << S;
        ++checks;
    }
    const auto& w = p.work();
    std::printf("checks %d, replayed ticks %llu, skipped replays %llu, reused car-steps %llu\n", checks,
                static_cast<unsigned long long>(w.replayed_ticks), static_cast<unsigned long long>(w.skipped_replays),
                static_cast<unsigned long long>(w.reused_car_steps));
    EXPECT_GT(checks, 100);
    // Every shortcut was taken, so the comparison covered it.
    if (expect_skips) {
        EXPECT_GT(w.skipped_replays, 0u);
    }
    EXPECT_GT(w.reused_car_steps, 0u);
}

TEST(Predictor, EqualsTheFullReplayOnRing) { check_track("ring", 16, 2400, std::random_device{}(), true); }
TEST(Predictor, EqualsTheFullReplayOnStadium) { check_track("stadium", 24, 2400, std::random_device{}(), false); }

TEST(Predictor, ThinKeepsTheNewestSnapshotAtTheClocksTick) {
    jetrace::Track t;
    jetrace::make_builtin_track("ring", t);
    const auto scene = jetrace::Scene::make(std::move(t), jetrace::PhysicsSettings{});
    const ServerRun run = run_server(scene, 4, 40);
    std::mt19937_64 rng(1);
    Predictor p(true);
    p.start(run.worlds[0]);
    const auto snap0 = snapshot_at(run, 0, rng);
    for (int i = 0; i < 30; ++i) p.run_tick(scene, 0, Input{}, snap0);
    EXPECT_EQ(p.world().tick, 30u);
    const auto snap = snapshot_at(run, 20, rng);
    const auto o = p.reconcile(scene, snap, 0, true);
    EXPECT_FALSE(o.resynced);
    EXPECT_EQ(p.world().tick, 30u);
    for (std::size_t s = 0; s < 4; ++s) EXPECT_EQ(p.world().cars[s].position, run.worlds[20].cars[s].position);
    ASSERT_NE(p.my_input(29), nullptr);
    EXPECT_EQ(p.work().replayed_ticks, 0u);
}

// With an input delay of D ticks, the input given at tick t is stepped at
// t + D (the first D ticks with a neutral one), the prediction is the plain
// replay with those inputs, and the inputs go out as soon as they are given.
TEST(Predictor, AnInputDelayedByDTicksIsSteppedDTicksLaterAndSentAtOnce) {
    jetrace::Track t;
    jetrace::make_builtin_track("ring", t);
    const auto scene = jetrace::Scene::make(std::move(t), jetrace::PhysicsSettings{});
    constexpr std::uint32_t kTicks = 24, kDelay = 5;
    const ServerRun run = run_server(scene, 4, kTicks + kDelay);
    std::mt19937_64 rng(3);
    const auto snap0 = snapshot_at(run, 0, rng);
    const std::size_t own = 2;
    Predictor p(false, kDelay);
    p.start(run.worlds[0]);
    std::vector<Input> stepped(kTicks + kDelay);
    for (std::uint32_t k = 0; k < kTicks; ++k) {
        const Input given = run.inputs[k][own];
        p.run_tick(scene, own, given, snap0);
        stepped[k + kDelay] = given;
    }
    for (std::uint32_t k = 0; k < kTicks + kDelay; ++k) {
        ASSERT_NE(p.my_input(k), nullptr) << "tick " << k;
        EXPECT_TRUE(*p.my_input(k) == stepped[k]) << "tick " << k;
    }
    EXPECT_EQ(p.my_input(kTicks + kDelay), nullptr);
    EXPECT_TRUE(jetrace::client::same_world(p.world(), full_replay(scene, snap0, own, stepped, kTicks)));
    // Sent: every input given so far, the last one for the tick kDelay ahead.
    jetrace::proto::InputBatch b;
    ASSERT_TRUE(p.unapplied_inputs(jetrace::proto::kNoTick, b));
    EXPECT_EQ(b.first_tick + b.inputs.size(), kTicks + kDelay);
    EXPECT_TRUE(b.inputs.back() == stepped[kTicks + kDelay - 1]);
}

}  // namespace

