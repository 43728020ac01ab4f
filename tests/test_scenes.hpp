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

#include "jetrace/hovercar.hpp"
#include "jetrace/track.hpp"
#include "jetrace/world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace jetrace::test {

// ---------------------------------------------------------------- seeds

inline std::uint64_t base_seed() {
    if (const char* e = std::getenv("JETRACE_TEST_SEED"); e != nullptr && *e != '\0') {
        return std::strtoull(e, nullptr, 0);
    }
    return 0x6a65747261636502ull;
}

#define JETRACE_SEEDED_RNG(rng)                                                                    \
    const std::uint64_t rng##_seed = ::jetrace::test::base_seed();                                                  \
    SCOPED_TRACE("JETRACE_TEST_SEED=" + std::to_string(rng##_seed));                               \
    ::testing::Test::RecordProperty("seed", std::to_string(rng##_seed));                           \
    std::mt19937_64 rng(rng##_seed)

// ---------------------------------------------------------------- scenes

constexpr double kR = 2.5;
constexpr double kEps = 1.0 / 1024.0;
constexpr double kRest = kR + kEps;  // resting height above a floor at y = 0

inline std::string str(const Vec3& v) {
    std::ostringstream o;
    o.precision(17);
    o << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return o.str();
}

struct Mesh {
    std::vector<Vec3> vertices;
    std::vector<std::uint32_t> indices;

    // Two triangles (a, b, c) and (a, c, d); the normal follows the right-hand rule.
    void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
        const auto base = static_cast<std::uint32_t>(vertices.size());
        vertices.insert(vertices.end(), {a, b, c, d});
        indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    // The floor y = 0 over [-h, h]^2, normal +Y.
    void floor(double h) { quad(Vec3(-h, 0, -h), Vec3(-h, 0, h), Vec3(h, 0, h), Vec3(h, 0, -h)); }
    // A wall in the plane x = x0 from y = 0 to `height`, z in [-h, h], normal -X.
    void wall_x(double x0, double height, double h) {
        quad(Vec3(x0, 0, -h), Vec3(x0, 0, h), Vec3(x0, height, h), Vec3(x0, height, -h));
    }
    // A wall in the plane z = z0 from y = 0 to `height`, x in [-h, h], normal -Z.
    void wall_z(double z0, double height, double h) {
        quad(Vec3(-h, 0, z0), Vec3(-h, height, z0), Vec3(h, height, z0), Vec3(h, 0, z0));
    }
};

// Settings for the custom scenes: the default physics, except that a car
// standing still is not respawned for lack of progress during long runs.
inline PhysicsSettings test_physics() {
    PhysicsSettings ps;
    ps.no_progress_s = 3599.0;
    return ps;
}

// A track from `mesh` with two gates far away (so race rules run but never
// fire) and one spawn at the origin, resting on a floor at y = 0.
inline Scene make_scene(const Mesh& mesh, const PhysicsSettings& ps, double kill_height = -1e5) {
    const Pose spawn{Vec3(0, kRest, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    Checkpoint g0;
    g0.center = Vec3(0, 10, 20000);
    g0.normal = Vec3(0, 0, 1);
    g0.across = Vec3(-1, 0, 0);
    g0.up = Vec3(0, 1, 0);
    g0.respawn = spawn;
    Checkpoint g1 = g0;
    g1.center = Vec3(0, 10, -20000);
    g1.normal = Vec3(0, 0, -1);
    g1.across = Vec3(1, 0, 0);
    Track track = make_track("test", mesh.vertices, mesh.indices, {g0, g1}, {spawn}, kill_height);
    EXPECT_EQ(validate(track), "");
    EXPECT_EQ(validate(ps), "");
    return Scene::make(std::move(track), ps);
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

inline double distance_to(const Triangle& t, const Vec3& p) { return (p - closest_point_on_triangle(p, t).point).norm(); }

inline double min_distance(const Track& track, const Vec3& p) {
    double d = 1e300;
    for (const Triangle& t : track.triangles) d = std::min(d, distance_to(t, p));
    return d;
}

inline std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

inline bool same_bits(const Vec3& a, const Vec3& b) {
    return bits(a.x()) == bits(b.x()) && bits(a.y()) == bits(b.y()) && bits(a.z()) == bits(b.z());
}

inline bool same_bits(const Quat& a, const Quat& b) {
    return bits(a.w()) == bits(b.w()) && bits(a.x()) == bits(b.x()) && bits(a.y()) == bits(b.y()) &&
           bits(a.z()) == bits(b.z());
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
