// Scenes and checks shared by the core's tests: small custom tracks (floor,
// walls), one-car worlds, bit-exact comparisons, and the seeded RNG.
//
// Random parts draw from std::mt19937_64. The seed is fixed by default; set
// the environment variable JETRACE_TEST_SEED (decimal or 0x-hex) to use
// another. Every test that uses it prints it on failure (SCOPED_TRACE) and
// records it as the test property "seed" (--gtest_output=xml), so a failure
// replays with
//   JETRACE_TEST_SEED=<seed> ./<test binary> --gtest_filter=<test>
#pragma once

#include "jetrace/core/hovercar.hpp"
#include "jetrace/core/track.hpp"
#include "jetrace/core/world.hpp"
#include "lab/scenes.hpp"
#include "test_seed.hpp"
#include "vec_str.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace jetrace::test {

// ---------------------------------------------------------------- scenes

constexpr double kR = 2.5;
constexpr double kEps = 1.0 / 1024.0;
constexpr double kRest = kR + kEps;  // resting height above a floor at y = 0

// Meshes, physics and scenes come from the study's lab (tools/lab), so that
// a scenario is written once for the tests and jetrace-bench.
using lab::Mesh;
using lab::min_distance;
inline PhysicsSettings test_physics() { return lab::lab_physics(); }
inline Scene make_scene(const Mesh& mesh, const PhysicsSettings& ps) {
    EXPECT_EQ(validate(ps), "");
    return lab::make_lab_scene(mesh, ps);
}

// A one-car world with the car at rest on `pose`, then given `velocity`
// (quantised like the state).
inline WorldState one_car(const Pose& pose, const Vec3& velocity = Vec3::Zero()) {
    WorldState st = make_world(1, 1);
    CarState& car = st.cars[0];
    car.active = true;
    place_car(car, pose);
    car.velocity = velocity;
    quantize_motion(car);
    return st;
}

inline void step1(const Scene& sc, WorldState& st, const Input& in, StepScratch& scratch) {
    step(sc, st, std::span<const Input>(&in, 1), scratch);
}

// Steps `ticks` times with zero input; the car's position, velocity and
// orientation are bit-identical from tick `settle` on.
inline void stays_at_rest(const Scene& sc, WorldState st, int ticks, int settle) {
    StepScratch scratch;
    const Input none{};
    for (int i = 0; i < settle; ++i) step1(sc, st, none, scratch);
    const CarState ref = st.cars[0];
    int bad = 0;
    for (int i = settle; i < ticks && bad < 3; ++i) {
        step1(sc, st, none, scratch);
        const CarState& c = st.cars[0];
        if (!same_bits(c.position, ref.position) || !same_bits(c.velocity, ref.velocity) ||
            !same_bits(c.orientation, ref.orientation)) {
            ++bad;
            ADD_FAILURE() << "tick " << i << ": position " << str(c.position) << " velocity " << str(c.velocity)
                          << " differ from the rest state " << str(ref.position) << " " << str(ref.velocity);
        }
    }
    EXPECT_EQ(bad, 0);
    EXPECT_EQ(st.cars[0].respawns, 0u);
    EXPECT_EQ(scratch.capped, 0);
}

}  // namespace jetrace::test
