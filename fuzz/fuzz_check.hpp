// Shared by every fuzz target: the libFuzzer entry point's signature and an
// invariant check that aborts in every build type (assert() vanishes under
// NDEBUG, and a broken invariant must reach libFuzzer as a crash).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

/// Aborts with the failed condition when an invariant does not hold.
#define JETRACE_FUZZ_CHECK(cond)                                                                         \
    do {                                                                                                 \
        if (!(cond)) {                                                                                   \
            std::fprintf(stderr, "%s:%d: fuzz invariant failed: %s\n", __FILE__, __LINE__, #cond);      \
            std::abort();                                                                                \
        }                                                                                                \
    } while (false)

namespace jetrace::fuzz {

inline std::span<const std::uint8_t> bytes(const std::uint8_t* data, std::size_t size) { return {data, size}; }

}  // namespace jetrace::fuzz
