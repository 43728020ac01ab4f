// Where the driving AI crosses a gate: the places across it it tries, the
// ones a static obstacle stands on (found once per Course) and the one it
// takes, clear of finished cars. Internal to jetrace::ai.
#pragma once

#include "jetrace/ai/driver_ai.hpp"

#include <cstdint>

namespace jetrace::ai_detail {

/// How far across gate `g` from its centre place `place` is (unit: m).
double crossing_place(const Checkpoint& g, int place);

/// Where the car `car` crosses gate `gate`, across it from its centre (unit: m).
double crossing_offset(const Course& course, const WorldState& state, std::int32_t gate, const CarState& car);

}  // namespace jetrace::ai_detail
