// Seeded random geometry shared by the closest-point and grid tests
// (test_closest_point, test_geometry_grid, test_sparse_grid): the seeded
// generator, random points in a box, on a triangle and on the unit sphere,
// full-precision printing of a Vec3, and the contact query radius.
//
// Random tests draw from std::mt19937_64. The seed is fixed by default; set
// the environment variable JETRACE_TEST_SEED (decimal or 0x-hex) to run with
// another one. JETRACE_SEEDED_RNG prints the seed, shows it on failure
// (SCOPED_TRACE) and records it as the test property "seed" (visible with
// --gtest_output=xml), so a failure can be replayed with
//   JETRACE_TEST_SEED=<seed> ./<test binary> --gtest_filter=<test>
// (test_seed.hpp does all of that).
#pragma once

#include "jetrace/core/geometry.hpp"
#include "test_seed.hpp"
#include "vec_str.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

namespace jetrace::test {

// ---------------------------------------------------------------- random geometry

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline Vec3 random_in_box(std::mt19937_64& rng, const Vec3& lo, const Vec3& hi) {
    return {uniform(rng, lo.x(), hi.x()), uniform(rng, lo.y(), hi.y()), uniform(rng, lo.z(), hi.z())};
}

inline Vec3 random_unit(std::mt19937_64& rng) {
    for (;;) {
        const Vec3 v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        const double n2 = v.squaredNorm();
        if (n2 > 1e-4 && n2 <= 1.0) return v / std::sqrt(n2);
    }
}

// A uniformly distributed point on triangle t.
inline Vec3 random_on_triangle(std::mt19937_64& rng, const Triangle& t) {
    double u = uniform(rng, 0, 1), v = uniform(rng, 0, 1);
    if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
    }
    return t.a + (t.b - t.a) * u + (t.c - t.a) * v;
}

// A car's contact query radius: car radius + contact skin.
inline constexpr double kQueryRadius = 2.5 + 0.05;

}  // namespace jetrace::test
