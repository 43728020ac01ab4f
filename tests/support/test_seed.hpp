// The seed of a randomised test: JETRACE_TEST_SEED (decimal or 0x-hex) if
// set, else `fallback`; printed so that a failure can be repeated with
//   JETRACE_TEST_SEED=<seed> ./test_x --gtest_filter=<test>
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace jetrace::test {

inline std::uint64_t test_seed(std::uint64_t fallback) {
    std::uint64_t seed = fallback;
    if (const char* env = std::getenv("JETRACE_TEST_SEED"); env != nullptr && *env != '\0') {
        seed = std::strtoull(env, nullptr, 0);
    }
    std::printf("[ seed ] JETRACE_TEST_SEED=%llu\n", static_cast<unsigned long long>(seed));
    return seed;
}

}  // namespace jetrace::test
