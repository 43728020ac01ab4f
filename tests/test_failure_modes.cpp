// Where methods fail (issue 4). Each test runs the failing variant and shows
// it failing, then the default and shows it holding. The scenes and probes
// live in tools/lab (shared with `jetrace-bench study`).
//
// Epsilon 0 (the seed's fall through the ground) is not repeated here: see
// Resolver.SeedBugEpsilonZeroFallsThroughFloor and
// Resolver.SeedBugEpsilonZeroFloorFirstDrivesThroughWall in test_resolver.cpp.
//
// Nothing here is random: every scenario is a fixed grid of approaches.
#include "lab/probes.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using namespace jetrace;
using namespace jetrace::lab;

void record(const char* key, double v) { ::testing::Test::RecordProperty(key, std::to_string(v)); }

// ================================================================ tunnelling

// The naive discrete push-out at 120 Hz: a car whose centre crosses a
// zero-thickness wall within one step is pushed out on the far side. The
// closest a car can be before a step without touching is r + epsilon (where
// a push-out leaves it), so the limit is (r + epsilon)/dt, raised by the
// drag of that step: 300.25 m/s at 120 Hz. The issue expected "about 290
// m/s"; that is not what this core does (no probed phase or offset passes
// below r/dt = 300 m/s). The test finds the limit and pins it between r/dt
// and r/dt + 0.5%.
TEST(FailureModes, DiscretePushOutTunnelsAtROverDt) {
    PhysicsSettings ps = lab_physics();
    set_swept(ps, false);
    const Scene sc = make_lab_scene(thin_wall_mesh(), ps);
    const TunnelLimit lim = tunnelling_limit(sc, 50.0, 4000.0, Approach{});
    record("discrete_holds_to_mps", lim.holds_to_mps);
    record("discrete_first_pass_mps", lim.first_pass_mps);
    std::printf("discrete 120 Hz: holds to %.2f m/s, passes at %.2f m/s\n", lim.holds_to_mps, lim.first_pass_mps);
    ASSERT_GT(lim.first_pass_mps, 0.0) << "the discrete push-out should pass through the wall below 4,000 m/s";
    const double r_over_dt = ps.car_radius_m / ps.dt_s();
    EXPECT_GE(lim.holds_to_mps, 0.99 * r_over_dt);
    EXPECT_LE(lim.first_pass_mps, 1.005 * r_over_dt) << "the limit is r/dt";
    EXPECT_FALSE(passes_through(sc, lim.holds_to_mps, Approach{}));
    EXPECT_TRUE(passes_through(sc, lim.first_pass_mps, Approach{}));
}

// The default mode (swept) holds to 2,000 m/s at every
// probed phase and offset.
TEST(FailureModes, DefaultModeHoldsTo2000mps) {
    const PhysicsSettings ps = lab_physics();
    const Scene sc = make_lab_scene(thin_wall_mesh(), ps);
    for (double v = 50.0; v <= 2000.0; v *= 1.05) EXPECT_FALSE(passes_through(sc, v, Approach{})) << v << " m/s";
    EXPECT_FALSE(passes_through(sc, 2000.0, Approach{32, 8}));
}

// ==================================================================== spring

// An undamped spring (1 Hz, 120 Hz steps, 100,000 steps = 833 s) through the
// core's integrate(). Explicit Euler multiplies the energy by 1 + (w dt)^2
// every step: it explodes. Semi-implicit Euler is symplectic: the energy
// oscillates within a few tenths of a percent and never grows. The car has
// no hover spring; the default (velocity Verlet with one acceleration per
// step) is exact for the constant accelerations it does have, but on a spring
// it is not symplectic and grows too (by 1 + (w dt)^2 / 2 per step): pinned
// here so that adding a spring to the model cannot go unnoticed.
TEST(FailureModes, ExplicitEulerSpringGainsEnergySemiImplicitBounded) {
    const double w = 2 * kPi;
    const SpringRun ex = spring(Integrator::explicit_euler, 120, w, 100000);
    const SpringRun si = spring(Integrator::semi_implicit_euler, 120, w, 100000);
    const SpringRun vv = spring(Integrator::velocity_verlet, 120, w, 100000);
    record("explicit_max_energy_ratio", ex.max_energy_ratio);
    record("semi_implicit_max_energy_ratio", si.max_energy_ratio);
    record("verlet_max_energy_ratio", vv.max_energy_ratio);
    std::printf("energy ratio after 1e5 steps: explicit %.3g, semi-implicit max %.6f, verlet %.3g\n",
                ex.final_energy_ratio, si.max_energy_ratio, vv.final_energy_ratio);
    EXPECT_GT(ex.final_energy_ratio, 1e6) << "explicit Euler should blow up";
    EXPECT_LT(si.max_energy_ratio, 1.03) << "semi-implicit Euler should stay bounded";
    EXPECT_GT(si.final_energy_ratio, 0.97);
    EXPECT_GT(vv.final_energy_ratio, 1e3) << "one-evaluation Verlet is not symplectic on a spring";
}

// ===================================================================== seams

// Sliding at 100 m/s (no throttle) over a floor split into 0.5 m squares,
// along the seams and across them at 30 degrees: against the same slide on a
// floor of two triangles, the height differs by under 1 mm and the speed not
// at all. The sliding car rests at r + epsilon, the normal force cancels
// gravity, and it is never pushed, so a seam has nothing to push it with.
//
// The failing case is a landing: dropping 0.3 m at 10 m/s onto the same
// floor at 30 degrees, the car penetrates; the resolver pushes out of the
// touching triangles in index order, and when the first one's closest point
// is on an edge the push is tilted (a ghost edge) and takes speed: 0.23 m/s
// of 98 m/s here, 0.2 %. On the two-triangle floor the same landing loses
// nothing, and sliding on never loses anything.
TEST(FailureModes, SlidingOverSeamsKeepsHeightAndSpeed) {
    const PhysicsSettings ps = lab_physics();
    const SeamRun landing = slide_over_seams(ps, 0.5, 100.0, 30.0, 1.0, 0.3, -10.0);
    std::printf("landing at 30 degrees: excursion %.3g m, speed change %.3g m/s\n", landing.max_excursion_m,
                landing.max_speed_change_mps);
    record("landing_speed_change_mps", landing.max_speed_change_mps);
    EXPECT_GT(landing.max_speed_change_mps, 0.05) << "a hard landing on seams should show the ghost-edge loss";
    for (double heading : {0.0, 30.0}) {
        const SeamRun run = slide_over_seams(ps, 0.5, 100.0, heading, 1.0);
        std::printf("heading %.0f: excursion %.3g m, speed change %.3g m/s\n", heading, run.max_excursion_m,
                    run.max_speed_change_mps);
        EXPECT_LT(run.max_excursion_m, 1e-3) << heading;
        EXPECT_EQ(run.max_speed_change_mps, 0.0) << heading;
        EXPECT_GT(run.reference_speed_mps, 95.0) << "only air drag slows the car";
    }
}

// ==================================================================== corner

// Cars driven at full throttle into a pit corner where 3 x 48 thin triangles
// meet, from 9 headings and speeds up to 120 m/s (below the tunnelling limit).
// Pushing out of one triangle per pass (PushOut::first_contact, what the
// resolver did before revision 2) the car is shoved around the fan a little
// at a time and needs up to about 50 passes: with 20, the cap stops it
// inside geometry in some steps, and every step that ends inside is one the
// cap stopped. The default pushes out of every touching triangle in each
// pass: the corner then takes a handful of passes, the cap is never reached
// and no step ends inside.
constexpr double kCornerSpeed_mps = 120.0;

TEST(FailureModes, CornerFirstContactPassesRunOutEachContactHolds) {
    PhysicsSettings first = lab_physics();
    first.push_out = PushOut::first_contact;
    const CornerRun fail = drive_into_corners(first, kCornerSpeed_mps, 9, 1.0);
    std::printf("first contact, 20 passes: %d of %d steps capped, %d inside, worst %.3g m\n", fail.capped_steps,
                fail.steps, fail.inside_steps, fail.worst_penetration_m);
    record("first_contact_capped_steps", fail.capped_steps);
    EXPECT_GT(fail.inside_steps, 0) << "20 one-push passes should not clear this corner every step";
    EXPECT_EQ(fail.inside_uncapped_steps, 0) << "a step ending inside geometry must be reported as capped";

    PhysicsSettings first_many = first;
    first_many.resolver_passes = 100;
    const CornerRun slow = drive_into_corners(first_many, kCornerSpeed_mps, 9, 1.0);
    std::printf("first contact, 100 passes: %d capped, %d inside, max passes %d\n", slow.capped_steps,
                slow.inside_steps, slow.max_passes);
    EXPECT_EQ(slow.inside_steps, 0);
    EXPECT_GT(slow.max_passes, 20) << "the corner needs more than 20 one-push passes";

    const PhysicsSettings def = lab_physics();
    ASSERT_EQ(def.push_out, PushOut::each_contact);
    const CornerRun ok = drive_into_corners(def, kCornerSpeed_mps, 9, 1.0);
    std::printf("each contact (default), 20 passes: %d capped, %d inside, max passes %d, max pushes %d\n",
                ok.capped_steps, ok.inside_steps, ok.max_passes, ok.max_pushes);
    record("default_max_passes", ok.max_passes);
    EXPECT_EQ(ok.capped_steps, 0);
    EXPECT_EQ(ok.inside_steps, 0);
    EXPECT_EQ(ok.worst_penetration_m, 0.0);
    EXPECT_LE(ok.max_passes, def.resolver_passes / 2) << "the default should clear the corner well inside the cap";
}

}  // namespace
