// The one list of a CarState's fields, in hash order, with their names.
// state_hash() and car_hash() feed exactly these values, in this order; the
// replay tools name a differing field by it. A field added to CarState must
// be added here: the static_assert below trips on a size change.
#pragma once

#include "jetrace/core/hovercar.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <type_traits>

namespace jetrace {

/// Calls `v(name, value)` for every field of `c`, in hash order. Values are
/// bool, double, std::int32_t or std::uint32_t (a Vec3 or Quat as its
/// components: position.x, ..., orientation.w, .x, .y, .z).
template <class Car, class Visitor>
void visit_car_fields(Car& c, Visitor&& v) {
    v("active", c.active);
    v("finished", c.finished);
    v("position.x", c.position.x());
    v("position.y", c.position.y());
    v("position.z", c.position.z());
    v("velocity.x", c.velocity.x());
    v("velocity.y", c.velocity.y());
    v("velocity.z", c.velocity.z());
    v("orientation.w", c.orientation.w());
    v("orientation.x", c.orientation.x());
    v("orientation.y", c.orientation.y());
    v("orientation.z", c.orientation.z());
    v("next_checkpoint", c.next_checkpoint);
    v("lap", c.lap);
    v("respawn_checkpoint", c.respawn_checkpoint);
    v("finish_tick", c.finish_tick);
    v("finish_fraction", c.finish_fraction);
    v("respawns", c.respawns);
    v("best_gate_distance_m", c.best_gate_distance_m);
    v("no_progress_ticks", c.no_progress_ticks);
}

/// Fields visit_car_fields() names (a Vec3 counts three, a Quat four).
inline constexpr int kCarFieldCount = 20;

/// Every field of `c` as raw bits, in visit_car_fields() order: two cars
/// are the same, bit for bit, when these are equal.
inline std::array<std::uint64_t, kCarFieldCount> car_field_bits(const CarState& c) {
    std::array<std::uint64_t, kCarFieldCount> out{};
    std::size_t i = 0;
    visit_car_fields(c, [&](const char*, auto value) {
        using T = std::remove_cvref_t<decltype(value)>;
        if constexpr (std::is_same_v<T, double>) {
            out[i++] = std::bit_cast<std::uint64_t>(value);
        } else if constexpr (std::is_same_v<T, bool>) {
            out[i++] = value ? 1u : 0u;
        } else {
            out[i++] = static_cast<std::uint32_t>(value);
        }
    });
    return out;
}

// Tripwire: two bools, 10 doubles (position, velocity, orientation), 7
// 32-bit integers and 1 double, with padding. A new field changes the size.
static_assert(sizeof(CarState) == 128, "CarState changed: update visit_car_fields() and state_bytes.cpp");

}  // namespace jetrace
