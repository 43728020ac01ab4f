// The integer model of a car behind the world payload (internal to
// jetrace::proto): wire units, orders and the predictions both ends compute.
// Every prediction is exact integer arithmetic on values both ends have, so
// decoding is the exact inverse of encoding on any compiler.
#pragma once

#include "jetrace/core/car_fields.hpp"
#include "jetrace/core/hovercar.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>

namespace jetrace::proto::world {

constexpr std::int64_t kI32Min = std::numeric_limits<std::int32_t>::min();
constexpr std::int64_t kI32Max = std::numeric_limits<std::int32_t>::max();
constexpr std::int64_t kU32Max = std::numeric_limits<std::uint32_t>::max();
/// Quaternion components on the wire: units of 2^-14, within [-2^15, 2^15).
constexpr std::int64_t kQuatOne = std::int64_t{1} << kQuatBits;
constexpr std::int64_t kQuatLimit = std::int64_t{1} << 15;
/// Checkpoint indexes must be below this.
constexpr std::uint64_t kCheckpointLimit = std::uint64_t{1} << 16;
constexpr int kMaxTickRate = 10000;
/// Position extrapolation only over this many ticks (keeps products small).
constexpr std::int64_t kMaxExtrapolationTicks = 255;

// Exp-Golomb orders (docs/PROTOCOL.md, "World payload", has the table and
// the measurements behind it). Changes over n ticks grow with n, so some
// orders add L = floor(log2(n)). World +Y is up: on the track, cars mostly
// turn about Y (quaternion x and z and velocity y rarely change).
constexpr int kTickDeltaOrder = 2;
constexpr int kSmallIntOrder = 0;
constexpr int kQuatBigOrder = 0;
constexpr int kPosOrder = 0;
constexpr int kVelVerticalOrder = 1;
constexpr int kNoProgressOrder = 0;

/// floor(log2(n)) for n >= 1 (0 for n = 0), at most 8.
inline int log2_ticks(std::int64_t n) {
    const int l = n >= 1 ? static_cast<int>(std::bit_width(static_cast<std::uint64_t>(n))) - 1 : 0;
    return std::min(l, 8);
}
/// Quaternion component i (0 w, 1 x, 2 y, 3 z) residual order.
inline int quat_order(int i, int l) { return i == 0 || i == 2 ? 4 + l : 0; }
/// Velocity component i (0 x, 1 y, 2 z) residual order.
inline int vel_order(int i, int l) { return i == 1 ? kVelVerticalOrder : 6 + l; }
inline int gate_distance_order(int l) { return std::min(l, 3); }

/// The integer in units of 2^-bits of a quantised double, clamped to
/// [lo, hi]. Asserts that it is exact (a quantised value, not -0.0).
inline std::int64_t to_units(double x, int bits, std::int64_t lo, std::int64_t hi) {
    const double u = x * static_cast<double>(std::int64_t{1} << bits);  // exact: power of two
    assert(u == std::nearbyint(u) && "encode_world: state not quantised");
    assert(!(u == 0.0 && std::signbit(u)) && "encode_world: -0.0 in state");
    assert(u >= static_cast<double>(lo) && u <= static_cast<double>(hi) && "encode_world: value out of range");
    if (!(u >= static_cast<double>(lo))) return lo;  // also NaN
    if (u > static_cast<double>(hi)) return hi;
    return static_cast<std::int64_t>(std::nearbyint(u));
}

inline double from_units(std::int64_t u, int bits) {
    return static_cast<double>(u) / static_cast<double>(std::int64_t{1} << bits);  // exact
}

/// Rounds num/den to nearest, ties away from zero (den > 0).
inline std::int64_t round_div(std::int64_t num, std::int64_t den) {
    return num >= 0 ? (num + den / 2) / den : -((-num + den / 2) / den);
}

/// floor(sqrt(v)) for 0 <= v < 2^52, exactly.
inline std::int64_t isqrt(std::int64_t v) {
    if (v <= 0) return 0;
    auto r = static_cast<std::int64_t>(std::sqrt(static_cast<double>(v)));
    while (r * r > v) --r;
    while ((r + 1) * (r + 1) <= v) ++r;
    return r;
}

inline bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

inline bool same_race_fields(const CarState& a, const CarState& b) {
    return a.next_checkpoint == b.next_checkpoint && a.lap == b.lap && a.respawn_checkpoint == b.respawn_checkpoint &&
           a.finished == b.finished && a.finish_tick == b.finish_tick && same_bits(a.finish_fraction, b.finish_fraction) &&
           a.respawns == b.respawns;
}

/// Every field the same, bit for bit (the one field list: car_fields.hpp).
inline bool same_car(const CarState& a, const CarState& b) { return car_field_bits(a) == car_field_bits(b); }

// The payload carries every CarState field: motion (put_car/get_car),
// race fields (same_race_fields, put_race_fields) and progress. A field
// added to CarState changes this count and must be given a place there.
static_assert(kCarFieldCount == 20, "CarState gained a field: carry it in the world payload (world_codec.cpp)");

/// A car's motion as wire integers: position and velocity in units of
/// 2^-10, orientation (w, x, y, z) in units of 2^-14.
struct Motion {
    std::int64_t p[3];
    std::int64_t v[3];
    std::int64_t q[4];
};

inline Motion motion_of(const CarState& c) {
    Motion m{};
    for (int i = 0; i < 3; ++i) {
        m.p[i] = to_units(c.position[i], kPosBits, kI32Min, kI32Max);
        m.v[i] = to_units(c.velocity[i], kVelBits, kI32Min, kI32Max);
    }
    const double q[4] = {c.orientation.w(), c.orientation.x(), c.orientation.y(), c.orientation.z()};
    for (int i = 0; i < 4; ++i) m.q[i] = to_units(q[i], kQuatBits, -kQuatLimit, kQuatLimit - 1);
    return m;
}

inline void set_motion(const Motion& m, CarState& c) {
    for (int i = 0; i < 3; ++i) {
        c.position[i] = from_units(m.p[i], kPosBits);
        c.velocity[i] = from_units(m.v[i], kVelBits);
    }
    c.orientation = Quat(from_units(m.q[0], kQuatBits), from_units(m.q[1], kQuatBits), from_units(m.q[2], kQuatBits),
                         from_units(m.q[3], kQuatBits));
}

/// The orientation reference: the baseline's, negated if that is closer to
/// `flip`, and the index of its largest component (the one predicted from
/// the unit norm).
struct QuatRef {
    std::int64_t b[4];
    int big;
};

inline QuatRef quat_ref(const std::int64_t (&base)[4], bool flip) {
    QuatRef r{};
    r.big = 0;
    for (int i = 0; i < 4; ++i) {
        r.b[i] = flip ? -base[i] : base[i];
        if (std::abs(r.b[i]) > std::abs(r.b[r.big])) r.big = i;
    }
    return r;
}

/// The largest component predicted from the other three (unit norm), with
/// the reference's sign.
inline std::int64_t predict_big(const QuatRef& r, const std::int64_t (&q)[4]) {
    std::int64_t rest = kQuatOne * kQuatOne;
    for (int i = 0; i < 4; ++i)
        if (i != r.big) rest -= q[i] * q[i];
    const std::int64_t m = isqrt(rest);
    return r.b[r.big] < 0 ? -m : m;
}

/// Position prediction: the baseline position moved by the mean of the
/// baseline and new velocities over n ticks (exact for constant
/// acceleration under velocity Verlet).
inline std::int64_t predict_position(std::int64_t base_p, std::int64_t base_v, std::int64_t v, std::int64_t n, int rate) {
    std::int64_t disp = 0;
    if (n <= kMaxExtrapolationTicks && rate >= 1 && rate <= kMaxTickRate) disp = round_div((base_v + v) * n, 2 * rate);
    return std::clamp(base_p + disp, kI32Min, kI32Max);
}

/// True if x is an exact multiple of 2^-bits (not -0.0) whose integer in
/// those units is within [lo, hi]: what to_units() accepts.
inline bool is_units(double x, int bits, std::int64_t lo, std::int64_t hi) {
    const double u = x * static_cast<double>(std::int64_t{1} << bits);
    return u >= static_cast<double>(lo) && u <= static_cast<double>(hi) && u == std::nearbyint(u) &&
           !(u == 0.0 && std::signbit(u));
}

/// True if v is what Input::pack() produces (10 bits, steer within range):
/// the only input values decoding accepts.
inline bool is_packed_input(std::uint64_t v) {
    return v < (1u << 10) && Input::unpack(static_cast<std::uint16_t>(v)).pack() == v;
}

/// The tick of a world payload, read from its first field without decoding
/// the rest: baseline_tick + n with a baseline (kNoTick: none), else the
/// u(32) tick. Snapshot carries its server_tick only there
/// (packed_payloads.cpp).
/// False with a reason if the field is truncated or the tick passes 2^32 - 1.
bool read_world_tick(std::span<const std::uint8_t> payload, std::uint32_t baseline_tick, std::uint32_t& tick,
                     std::string& error);

}  // namespace jetrace::proto::world
