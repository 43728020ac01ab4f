// The driving AI on small made-up tracks, each with one feature that real
// levels from other games have and the built-in tracks do not: a block
// across a gate's centre, floors whose faces point down, a ramp up to a
// gate on a plateau, and a drop off its far edge, a block across the
// straight line between two gates. 8 cars, skill seeds 1 to 3: all 8
// finish a lap each time, with at most 4 respawns among them. Also single
// cars: rolling backwards, and pinned against a block.
#include "jetrace/ai/offline_race.hpp"
#include "support/made_up_track.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using jetrace::Checkpoint;
using jetrace::Pose;
using jetrace::Track;
using jetrace::Vec3;
using jetrace::test::gate;
using jetrace::test::kRest_m;
using jetrace::test::Mesh;

struct Outcome {
    int finished = 0;
    int respawns = 0;
    double mean_s = 0;
};

Outcome race(const Track& track, std::uint64_t seed, double seconds = 120) {
    const jetrace::Scene scene = jetrace::Scene::make(Track(track), jetrace::PhysicsSettings{});
    constexpr int kCars = 8;
    jetrace::WorldState st = jetrace::start_race(scene, kCars, 1);
    jetrace::StepScratch scratch;
    jetrace::run_ai(jetrace::Course(scene), st, jetrace::skills_for(kCars, seed),
                    static_cast<std::uint32_t>(seconds * scene.physics.tick_rate_hz), true, scratch);
    Outcome o;
    for (const auto& c : st.cars) {
        o.respawns += static_cast<int>(c.respawns);
        if (!c.finished) continue;
        ++o.finished;
        o.mean_s += static_cast<double>(c.finish_tick - st.start_tick) / scene.physics.tick_rate_hz;
    }
    if (o.finished > 0) o.mean_s /= o.finished;
    return o;
}

// 8 spawns in two columns behind (x, z), facing +x.
std::vector<Pose> grid_behind(double x, double z, double road_y = 0) {
    std::vector<Pose> s;
    for (int i = 0; i < 8; ++i) {
        s.push_back(Pose{Vec3(x - 10 - 8 * (i / 2), road_y + kRest_m, z + (i % 2 == 0 ? -4 : 4)), Vec3(1, 0, 0),
                         Vec3(0, 1, 0)});
    }
    return s;
}

// A loop round a 300 m by 200 m rectangle on a floor: gates at the middle
// of its sides and at two corners.
std::vector<Checkpoint> rectangle(double g1_road_y = 0) {
    return {gate(-100, -100, 1, 0), gate(50, -100, 1, 0, g1_road_y), gate(150, 0, 0, 1), gate(0, 100, -1, 0),
            gate(-150, 0, 0, -1)};
}

// Skill seeds 1 to JETRACE_AI_SEEDS (default 3; the figures in
// docs/TRACKS.md use 12; the race's assertions hold for 1 to 3).
std::uint64_t seed_count() {
    const char* env = std::getenv("JETRACE_AI_SEEDS");
    const long n = env ? std::strtol(env, nullptr, 10) : 3;
    return n >= 1 && n <= 1000 ? static_cast<std::uint64_t>(n) : 3;
}

void expect_finish(const char* name, const Track& t) {
    const std::uint64_t seeds = seed_count();
    int finished = 0, respawns = 0;
    double lap_sum = 0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const Outcome o = race(t, seed);
        std::printf("%s seed %llu: %d/8 finished, %d respawns, mean %.1f s\n", name,
                    static_cast<unsigned long long>(seed), o.finished, o.respawns, o.mean_s);
        finished += o.finished;
        respawns += o.respawns;
        lap_sum += o.mean_s * o.finished;
        if (seed > 3) continue;
        EXPECT_EQ(o.finished, 8) << name << ", skill seed " << seed << ": " << o.respawns << " respawns";
        EXPECT_LE(o.respawns, 4) << name << ", skill seed " << seed;
    }
    std::printf("%s seeds 1-%llu: %d/%llu finished, %.2f respawns a car, mean lap %.1f s\n", name,
                static_cast<unsigned long long>(seeds), finished, static_cast<unsigned long long>(8 * seeds),
                static_cast<double>(respawns) / static_cast<double>(8 * seeds), finished ? lap_sum / finished : 0.0);
}

}  // namespace

TEST(AiObstacles, AFlatLoopIsRaced) {
    Mesh m;
    m.floor(-200, -150, 200, 150, 0);
    expect_finish("flat", jetrace::test::track_of(m, rectangle(), grid_behind(-100, -100)));
}

TEST(AiObstacles, ABlockAcrossAGatesCentreIsDrivenRound) {
    Mesh m;
    m.floor(-200, -150, 200, 150, 0);
    m.block(50, -100, 2, 0, 4);  // 4 m square, 4 m tall, on gate 1's centre
    expect_finish("block", jetrace::test::track_of(m, rectangle(), grid_behind(-100, -100)));
}

TEST(AiObstacles, TheFirstFreePlaceAcrossAGateIsTheFirstOneNotBlocked) {
    Mesh m;
    m.floor(-200, -150, 200, 150, 0);
    m.block(50, -100, 2, 0, 4);  // on gate 1's centre
    const jetrace::Scene scene = jetrace::Scene::make(jetrace::test::track_of(m, rectangle(), grid_behind(-100, -100)),
                                                      jetrace::PhysicsSettings{});
    const jetrace::Course course(scene);
    const auto& gates = scene.track.checkpoints;
    for (std::size_t g = 0; g < gates.size(); ++g) {
        for (bool finishing : {false, true}) {
            int first = 0;
            constexpr int kLast = 2 * jetrace::Course::kCrossingSteps;
            while (first <= kLast && course.crossing_blocked(g, first, finishing)) ++first;
            // crossing_place(): the centre, then alternately one side and
            // the other, a step further out each pair.
            const int steps = (first + 1) / 2;
            const double want = (first % 2 == 0 ? 1.0 : -1.0) * gates[g].half_width_m * 0.8 * steps /
                                jetrace::Course::kCrossingSteps;
            EXPECT_EQ(course.first_free_place_m(g, finishing), want) << "gate " << g << " finishing " << finishing;
            // Only the gate with the block has its centre blocked.
            EXPECT_EQ(first != 0, g == 1) << "gate " << g << " finishing " << finishing;
        }
    }
}

TEST(AiObstacles, FloorsWhoseFacesPointDownAreRaced) {
    Mesh m;
    m.floor(-200, -150, 200, 150, 0, true);
    expect_finish("flipped", jetrace::test::track_of(m, rectangle(), grid_behind(-100, -100)));
}

TEST(AiObstacles, ARampUpToAGateOnAPlateauAndTheDropOffIt) {
    Mesh m;
    // The floor, less the plateau's and the ramp's footprint.
    m.floor(-200, -150, 200, -130, 0);
    m.floor(-200, -70, 200, 150, 0);
    m.floor(-200, -130, -20, -70, 0);
    m.floor(80, -130, 200, -70, 0);
    // The ramp from x = -20 (y 0) to x = 20 (y 8), the plateau to x = 80,
    // its far edge a 8 m drop; walls round its sides.
    m.quad(Vec3(-20, 0, -130), Vec3(-20, 0, -70), Vec3(20, 8, -70), Vec3(20, 8, -130));
    m.floor(20, -130, 80, -70, 8);
    m.quad(Vec3(80, 8, -130), Vec3(80, 8, -70), Vec3(80, 0, -70), Vec3(80, 0, -130));
    m.quad(Vec3(-20, 0, -130), Vec3(20, 8, -130), Vec3(80, 8, -130), Vec3(80, 0, -130));
    m.quad(Vec3(-20, 0, -70), Vec3(80, 0, -70), Vec3(80, 8, -70), Vec3(20, 8, -70));
    expect_finish("plateau", jetrace::test::track_of(m, rectangle(8), grid_behind(-100, -100)));
}

TEST(AiObstacles, ABlockAcrossTheStraightLineBetweenTwoGatesIsDrivenRound) {
    // A 16 m square block, 4 m tall, on the middle of the leg from gate 2
    // (150, 0) to gate 3 (0, 100): the straight line runs into it.
    Mesh m;
    m.floor(-200, -150, 200, 150, 0);
    m.block(75, 50, 8, 0, 4);
    expect_finish("mid-leg block", jetrace::test::track_of(m, rectangle(), grid_behind(-100, -100)));
}

TEST(AiObstacles, ACarRollingBackwardsDrivesForwards) {
    // On the ground before gate 1, nose towards it, rolling backwards at
    // speeds round the approach speed: thrust (and the brake) at each, never
    // a coast.
    Mesh m;
    m.floor(-200, -150, 200, 150, 0);
    const jetrace::Scene scene =
        jetrace::Scene::make(jetrace::test::track_of(m, rectangle(), grid_behind(-100, -100)), jetrace::PhysicsSettings{});
    const jetrace::Course course(scene);
    jetrace::WorldState st = jetrace::start_race(scene, 1, 1);
    for (double back : {2.0, 10.0, 14.0, 15.0, 16.0, 20.0, 40.0}) {
        jetrace::CarState& car = st.cars[0];
        jetrace::place_car(car, Pose{Vec3(30, kRest_m, -100), Vec3(1, 0, 0), Vec3(0, 1, 0)});
        car.next_checkpoint = 1;
        car.velocity = Vec3(-back, 0, 0);
        const jetrace::Input in = jetrace::drive(course, st, 0);
        EXPECT_EQ(in.throttle, jetrace::Input::kMaxThrottle) << "rolling back at " << back << " m/s";
        EXPECT_EQ(in.brake, 1) << "rolling back at " << back << " m/s";
    }
}

TEST(AiObstacles, ACarPinnedNoseFirstAgainstABlockGetsRoundItBeforeItsRespawn) {
    // At rest, nose against the side of a 16 m block (x 67 to 83, z 42 to
    // 58) that stands on the straight line to its next gate (gate 3 at
    // (0, 100)): within the no-progress window (10 s) it turns along the
    // block, drives round it and through the gate. Three places along the
    // block's side.
    Mesh m;
    m.floor(-200, -150, 200, 150, 0);
    m.block(75, 50, 8, 0, 4);
    const jetrace::Scene scene =
        jetrace::Scene::make(jetrace::test::track_of(m, rectangle(), grid_behind(-100, -100)), jetrace::PhysicsSettings{});
    const jetrace::Course course(scene);
    for (const double z : {46.0, 50.0, 54.0}) {
        jetrace::WorldState st = jetrace::start_race(scene, 1, 1);
        jetrace::CarState& car = st.cars[0];
        jetrace::place_car(car, Pose{Vec3(83 + kRest_m + 0.05, kRest_m, z), Vec3(-1, 0, 0), Vec3(0, 1, 0)});
        car.next_checkpoint = 3;
        car.respawn_checkpoint = 2;
        car.lap = 1;
        jetrace::StepScratch scratch;
        jetrace::run_ai(course, st, jetrace::skills_for(1, 1), static_cast<std::uint32_t>(9.5 * 120), false, scratch);
        EXPECT_EQ(car.respawns, 0u) << "from z = " << z;
        EXPECT_NE(car.next_checkpoint, 3) << "from z = " << z << ": still before gate 3 at (" << car.position.x()
                                          << ", " << car.position.z() << ")";
    }
}
