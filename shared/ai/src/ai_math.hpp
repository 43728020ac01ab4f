// Small geometric helpers the driving AI's parts share. Internal to
// jetrace::ai.
#pragma once

#include "jetrace/core/math.hpp"

#include <cstdint>

namespace jetrace::ai_detail {

/// `i` modulo `n` (n > 0) in [0, n), negative `i` included; no division
/// for an `i` already in range (the legs and gates just ahead).
inline std::int32_t wrap(std::int32_t i, std::int32_t n) { return i >= 0 && i < n ? i : ((i % n) + n) % n; }

/// The part of `v` in the plane across unit vector `n`.
[[gnu::always_inline]] inline Vec3 in_plane(const Vec3& v, const Vec3& n) { return v - n * v.dot(n); }

/// Heading error of unit direction `d` against the car's forward: about the
/// angle (its sine) while ahead, beyond a right angle (2 - sine) when behind.
inline double heading_error(const Vec3& d, const Vec3& fwd, const Vec3& right) {
    const double lateral = d.dot(right);
    return d.dot(fwd) > 0.0 ? lateral : (lateral >= 0.0 ? 2.0 - lateral : -2.0 - lateral);
}

}  // namespace jetrace::ai_detail
