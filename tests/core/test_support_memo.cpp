// The controls' and the alignment's kept unit orientation, support frame
// and turn (SupportMemo): a car stepped with one memo kept through every
// step and a car stepped without (a fresh memo each call) agree bit for bit
// at every step, through straight runs (the memo found again), steering
// (the unit orientation changes each step; a held steer turns by the angle
// kept), a change of supporting surface (same orientation, another normal),
// a tilt the alignment turns towards, and no support at all.
#include "jetrace/core/hovercar.hpp"
#include "support/test_seed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using jetrace::CarState;
using jetrace::Contacts;
using jetrace::Input;
using jetrace::Vec3;

bool same_car_bits(const CarState& a, const CarState& b) {
    return jetrace::same_bits(a.position, b.position) && jetrace::same_bits(a.velocity, b.velocity) &&
           jetrace::same_bits(a.orientation, b.orientation);
}

// The contacts of step `i` of a scripted ride: a flat floor for long runs,
// a 10-degree ramp, both at once, none (a jump).
Contacts contacts_at(int i) {
    const Vec3 floor(0, 1, 0);
    const Vec3 ramp = Vec3(0, std::cos(0.1745), std::sin(0.1745)).normalized();
    Contacts c;
    switch ((i / 40) % 5) {
        case 0: c.add(floor); break;
        case 1: c.add(ramp); break;
        case 2:
            c.add(floor);
            c.add(ramp);
            break;
        case 3: break;
        default: c.add(floor); break;
    }
    return c;
}

}  // namespace

TEST(SupportMemo, KeptMemoStepsAsAFreshOne) {
    JETRACE_SEEDED_RNG(rng);
    const jetrace::PhysicsSettings ps;
    CarState kept, fresh;
    kept.position = Vec3(0, ps.car_radius_m, 0);
    kept.velocity = Vec3(0, 0, 30);
    jetrace::quantize_car(kept);
    fresh = kept;
    jetrace::SupportMemo memo;
    std::uniform_int_distribution<int> steer(-Input::kMaxSteer, Input::kMaxSteer);
    std::bernoulli_distribution turns(0.3), brakes(0.1);
    int steered = 0, held_turns = 0;
    int held = 0, last_steer = 0;
    for (int i = 0; i < 2000; ++i) {
        const Contacts c = contacts_at(i);
        // Steer in bursts, so that straight runs find the memo again; the
        // steer is held for four steps at a time (as the AI holds it), so
        // that a turn's angle is found again too.
        if (i % 4 == 0) held = steer(rng);
        const bool turn = (i / 25) % 2 == 1 && turns(rng);
        const Input in = Input::clamped(Input::kMaxThrottle, turn ? held : 0, brakes(rng) ? 1 : 0);
        steered += in.steer != 0 ? 1 : 0;
        held_turns += in.steer != 0 && in.steer == last_steer ? 1 : 0;
        last_steer = in.steer != 0 ? in.steer : last_steer;
        for (CarState* car : {&kept, &fresh}) {
            const Vec3 v0 = car->velocity;
            if (car == &kept) {
                jetrace::apply_controls_and_forces(ps, c, in, *car, memo);
            } else {
                jetrace::apply_controls_and_forces(ps, c, in, *car);
            }
            jetrace::integrate(ps, v0, *car);
            jetrace::quantize_motion(*car);
            if (car == &kept) {
                jetrace::align_to_contacts(ps, c, *car, memo);
            } else {
                jetrace::align_to_contacts(ps, c, *car);
            }
            jetrace::quantize_orientation(*car);
        }
        ASSERT_TRUE(same_car_bits(kept, fresh)) << "step " << i;
    }
    EXPECT_GT(steered, 100);
    EXPECT_GT(held_turns, 50);
    // Not vacuous: the car moved and turned.
    EXPECT_GT(kept.velocity.norm(), 1.0);
    EXPECT_LT(std::abs(kept.orientation.w()), 0.9999);
}
