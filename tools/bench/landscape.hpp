// A rolling landscape for the track benchmarks: one height function over a
// 1,024 m square, meshed as n x n squares of two triangles (n = 128, 256,
// 512, 1024 give 32,768 to 2,097,152 triangles of the same surface), with a
// lap of 16 gates on a 350 m circle and 8 (up to 64) spawn slots behind gate 0.
#pragma once

#include "jetrace/core/track.hpp"

namespace jetrace::bench {

/// Side of the landscape's square (unit: m).
inline constexpr double kLandscapeSide_m = 1024.0;

/// The landscape meshed with `n` squares per side (2 n^2 triangles), n >= 2,
/// with `spawns` slots (1 to 64) in two columns, rows 12 m apart along the lap.
Track landscape(int n, int spawns = 8);

}  // namespace jetrace::bench
