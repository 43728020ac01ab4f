// Names the fields in which two world states differ (the world's own
// fields, then each car's in visit_car_fields() order), with both values.
#pragma once

#include "jetrace/core/world.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace jetrace::replay {

struct FieldDifference {
    /// The car's slot, or -1 for a field of the world itself.
    int slot = -1;
    std::string field;
    /// The values as text: integers in decimal, doubles as %.17g and their raw bits.
    std::string a, b;
};

/// The first `max` differences between `a` and `b`, in slot and field order.
std::vector<FieldDifference> diff_states(const WorldState& a, const WorldState& b, std::size_t max = 16);

/// Whether the two states are bit for bit the same.
bool same_state(const WorldState& a, const WorldState& b);

/// "slot 3 position.x: 1.5 (0x3ff8000000000000) vs 1.5000000000000002 (...)".
std::string describe(const FieldDifference& d);

}  // namespace jetrace::replay
