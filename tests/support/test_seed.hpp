// The seed of a randomised test: JETRACE_TEST_SEED (decimal or 0x-hex) if
// set, else a fixed fallback; printed so that a failure can be repeated with
//   JETRACE_TEST_SEED=<seed> ./test_x --gtest_filter=<test>
//
// JETRACE_SEEDED_RNG_WITH also shows the seed on failure (SCOPED_TRACE) and
// records it as the test property "seed" (visible with --gtest_output=xml).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

namespace jetrace::test {

inline std::uint64_t test_seed(std::uint64_t fallback) {
    std::uint64_t seed = fallback;
    if (const char* env = std::getenv("JETRACE_TEST_SEED"); env != nullptr && *env != '\0') {
        seed = std::strtoull(env, nullptr, 0);
    }
    std::printf("[ seed ] JETRACE_TEST_SEED=%llu\n", static_cast<unsigned long long>(seed));
    return seed;
}

// The seed of the core's randomised tests (JETRACE_SEEDED_RNG).
inline std::uint64_t base_seed() { return test_seed(0x6a65747261636501ull); }

}  // namespace jetrace::test

// Declares `std::mt19937_64 rng` seeded with `seed` (a test_seed() call), shows
// the seed on failure and records it.
#define JETRACE_SEEDED_RNG_WITH(rng, seed)                                                         \
    const std::uint64_t rng##_seed = (seed);                                                       \
    SCOPED_TRACE("JETRACE_TEST_SEED=" + std::to_string(rng##_seed));                               \
    ::testing::Test::RecordProperty("seed", std::to_string(rng##_seed));                           \
    std::mt19937_64 rng(rng##_seed)

// Declares `std::mt19937_64 rng` seeded with base_seed().
#define JETRACE_SEEDED_RNG(rng) JETRACE_SEEDED_RNG_WITH(rng, ::jetrace::test::base_seed())
