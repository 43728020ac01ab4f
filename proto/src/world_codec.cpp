// The world payload: docs/PROTOCOL.md, section "World payload", is the
// specification; keep the two in step. The predictions are in
// world_model.hpp.
#include "jetrace/proto/world_codec.hpp"

#include "bitstream.hpp"
#include "jetrace/proto/messages.hpp"
#include "world_model.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <string>

namespace jetrace::proto {

namespace {

using bits::BitReader;
using bits::BitWriter;
using namespace world;

// ---------------------------------------------------------------- encode

void put_race_fields(BitWriter& w, const CarState& c, const CarState* ref) {
    w.put_ue(static_cast<std::uint64_t>(c.next_checkpoint), kSmallIntOrder);
    w.put_ue(static_cast<std::uint64_t>(c.lap), kSmallIntOrder);
    w.put_ue(static_cast<std::uint64_t>(c.respawn_checkpoint), kSmallIntOrder);
    w.put_bit(c.finished);
    w.put_ue(c.respawns, kSmallIntOrder);
    const std::uint32_t ref_tick = ref ? ref->finish_tick : 0;
    const double ref_fraction = ref ? ref->finish_fraction : 0.0;
    const bool same_finish = c.finish_tick == ref_tick && same_bits(c.finish_fraction, ref_fraction);
    w.put_bit(same_finish);
    if (!same_finish) {
        w.put(c.finish_tick, 32);
        w.put(std::bit_cast<std::uint64_t>(c.finish_fraction), 64);
    }
}

void put_car(BitWriter& w, const CarState& c, const CarState* ref, std::int64_t n, int rate) {
    assert(c.next_checkpoint >= 0 && static_cast<std::uint64_t>(c.next_checkpoint) < kCheckpointLimit);
    assert(c.respawn_checkpoint >= 0 && static_cast<std::uint64_t>(c.respawn_checkpoint) < kCheckpointLimit);
    assert(c.lap >= 0);
    const Motion m = motion_of(c);
    if (!ref) {
        for (std::int64_t q : m.q) w.put(static_cast<std::uint64_t>(q), 16);
        for (std::int64_t v : m.v) w.put(static_cast<std::uint64_t>(v), 32);
        for (std::int64_t p : m.p) w.put(static_cast<std::uint64_t>(p), 32);
        put_race_fields(w, c, nullptr);
        w.put(static_cast<std::uint32_t>(c.best_gate_distance_m), 32);
        w.put(c.no_progress_ticks, 32);
        return;
    }
    const Motion b = motion_of(*ref);
    std::int64_t dot = 0;
    for (int i = 0; i < 4; ++i) dot += m.q[i] * b.q[i];
    const bool flip = dot < 0;
    w.put_bit(flip);
    const int l = log2_ticks(n);
    const QuatRef qr = quat_ref(b.q, flip);
    for (int i = 0; i < 4; ++i)
        if (i != qr.big) w.put_se(m.q[i] - qr.b[i], quat_order(i, l));
    w.put_se(m.q[qr.big] - predict_big(qr, m.q), kQuatBigOrder);

    for (int i = 0; i < 3; ++i) w.put_se(m.v[i] - b.v[i], vel_order(i, l));
    for (int i = 0; i < 3; ++i) w.put_se(m.p[i] - predict_position(b.p[i], b.v[i], m.v[i], n, rate), kPosOrder);

    const bool same_race = same_race_fields(c, *ref);
    w.put_bit(same_race);
    if (!same_race) put_race_fields(w, c, ref);
    w.put_se(std::int64_t{c.best_gate_distance_m} - ref->best_gate_distance_m, gate_distance_order(l));
    // Unchanged best distance: the counter kept counting (residual usually
    // 0). Else it was reset during the interval: send it as is.
    if (c.best_gate_distance_m == ref->best_gate_distance_m)
        w.put_se(std::int64_t{c.no_progress_ticks} - (std::int64_t{ref->no_progress_ticks} + n), kNoProgressOrder);
    else
        w.put_ue(c.no_progress_ticks, kNoProgressOrder);
}

// ---------------------------------------------------------------- decode

/// Reads with a field name for the error message.
class Reader {
public:
    Reader(std::span<const std::uint8_t> bytes, std::string& error) : r_(bytes), error_(error) {}

    bool fail(const std::string& field, const std::string& what) {
        error_ = "world payload: " + prefix_ + field + ": " + what;
        return false;
    }
    bool bits(const char* field, int n, std::uint64_t& v) { return r_.get(n, v) || fail(field, r_.error()); }
    bool bit(const char* field, bool& b) { return r_.get_bit(b) || fail(field, r_.error()); }
    bool ue(const char* field, int k, std::uint64_t& v) { return r_.get_ue(k, v) || fail(field, r_.error()); }
    bool se(const char* field, int k, std::int64_t& v) { return r_.get_se(k, v) || fail(field, r_.error()); }
    /// A signed two's complement field of n bits.
    bool sbits(const char* field, int n, std::int64_t& v) {
        std::uint64_t u = 0;
        if (!bits(field, n, u)) return false;
        const std::uint64_t sign = std::uint64_t{1} << (n - 1);
        v = static_cast<std::int64_t>(u ^ sign) - static_cast<std::int64_t>(sign);
        return true;
    }
    /// A residual added to a prediction, checked against [lo, hi].
    bool residual(const char* field, int k, std::int64_t pred, std::int64_t lo, std::int64_t hi, std::int64_t& v) {
        std::int64_t d = 0;
        if (!se(field, k, d)) return false;
        v = pred + d;  // |pred| < 2^34, |d| < 2^55: no overflow
        return (v >= lo && v <= hi) || fail(field, "out of range");
    }
    void set_prefix(std::string p) { prefix_ = std::move(p); }
    const BitReader& raw() const { return r_; }

private:
    BitReader r_;
    std::string& error_;
    std::string prefix_;
};

bool get_race_fields(Reader& r, const CarState* ref, CarState& c) {
    std::uint64_t v = 0;
    if (!r.ue("next_checkpoint", kSmallIntOrder, v)) return false;
    if (v >= kCheckpointLimit) return r.fail("next_checkpoint", "out of range");
    c.next_checkpoint = static_cast<std::int32_t>(v);
    if (!r.ue("lap", kSmallIntOrder, v)) return false;
    if (v > static_cast<std::uint64_t>(kI32Max)) return r.fail("lap", "out of range");
    c.lap = static_cast<std::int32_t>(v);
    if (!r.ue("respawn_checkpoint", kSmallIntOrder, v)) return false;
    if (v >= kCheckpointLimit) return r.fail("respawn_checkpoint", "out of range");
    c.respawn_checkpoint = static_cast<std::int32_t>(v);
    if (!r.bit("finished", c.finished)) return false;
    if (!r.ue("respawns", kSmallIntOrder, v)) return false;
    if (v > static_cast<std::uint64_t>(kU32Max)) return r.fail("respawns", "out of range");
    c.respawns = static_cast<std::uint32_t>(v);
    bool same_finish = false;
    if (!r.bit("finish_tick", same_finish)) return false;
    if (same_finish) {
        c.finish_tick = ref ? ref->finish_tick : 0;
        c.finish_fraction = ref ? ref->finish_fraction : 0.0;
        return true;
    }
    if (!r.bits("finish_tick", 32, v)) return false;
    c.finish_tick = static_cast<std::uint32_t>(v);
    if (!r.bits("finish_fraction", 64, v)) return false;
    c.finish_fraction = std::bit_cast<double>(v);
    return true;
}

const char* const kQ[4] = {"orientation.w", "orientation.x", "orientation.y", "orientation.z"};
const char* const kV[3] = {"velocity.x", "velocity.y", "velocity.z"};
const char* const kP[3] = {"position.x", "position.y", "position.z"};

// A car written in full (no active car in the baseline's slot).
bool get_key_car(Reader& r, CarState& c) {
    Motion m{};
    for (int i = 0; i < 4; ++i)
        if (!r.sbits(kQ[i], 16, m.q[i])) return false;
    for (int i = 0; i < 3; ++i)
        if (!r.sbits(kV[i], 32, m.v[i])) return false;
    for (int i = 0; i < 3; ++i)
        if (!r.sbits(kP[i], 32, m.p[i])) return false;
    set_motion(m, c);
    if (!get_race_fields(r, nullptr, c)) return false;
    std::int64_t s = 0;
    if (!r.sbits("best_gate_distance_m", 32, s)) return false;
    c.best_gate_distance_m = static_cast<std::int32_t>(s);
    std::uint64_t u = 0;
    if (!r.bits("no_progress_ticks", 32, u)) return false;
    c.no_progress_ticks = static_cast<std::uint32_t>(u);
    return true;
}

// Orientation, velocity and position as residuals against the baseline's
// car `ref`, n ticks older.
bool get_motion_delta(Reader& r, const CarState& ref, std::int64_t n, int rate, CarState& c) {
    Motion m{};
    const Motion b = motion_of(ref);
    bool flip = false;
    if (!r.bit("orientation", flip)) return false;
    const int l = log2_ticks(n);
    const QuatRef qr = quat_ref(b.q, flip);
    for (int i = 0; i < 4; ++i)
        if (i != qr.big && !r.residual(kQ[i], quat_order(i, l), qr.b[i], -kQuatLimit, kQuatLimit - 1, m.q[i]))
            return false;
    if (!r.residual(kQ[qr.big], kQuatBigOrder, predict_big(qr, m.q), -kQuatLimit, kQuatLimit - 1, m.q[qr.big]))
        return false;
    for (int i = 0; i < 3; ++i)
        if (!r.residual(kV[i], vel_order(i, l), b.v[i], kI32Min, kI32Max, m.v[i])) return false;
    for (int i = 0; i < 3; ++i) {
        const std::int64_t pred = predict_position(b.p[i], b.v[i], m.v[i], n, rate);
        if (!r.residual(kP[i], kPosOrder, pred, kI32Min, kI32Max, m.p[i])) return false;
    }
    set_motion(m, c);
    return true;
}

bool get_car(Reader& r, const CarState* ref, std::int64_t n, int rate, CarState& c) {
    c = CarState{};
    c.active = true;
    if (!ref) return get_key_car(r, c);
    if (!get_motion_delta(r, *ref, n, rate, c)) return false;
    const int l = log2_ticks(n);
    bool same_race = false;
    if (!r.bit("race fields", same_race)) return false;
    if (same_race) {
        c.next_checkpoint = ref->next_checkpoint;
        c.lap = ref->lap;
        c.respawn_checkpoint = ref->respawn_checkpoint;
        c.finished = ref->finished;
        c.finish_tick = ref->finish_tick;
        c.finish_fraction = ref->finish_fraction;
        c.respawns = ref->respawns;
    } else if (!get_race_fields(r, ref, c)) {
        return false;
    }
    std::int64_t v = 0;
    if (!r.residual("best_gate_distance_m", gate_distance_order(l), ref->best_gate_distance_m, kI32Min, kI32Max, v))
        return false;
    c.best_gate_distance_m = static_cast<std::int32_t>(v);
    if (c.best_gate_distance_m == ref->best_gate_distance_m) {
        const std::int64_t pred = std::int64_t{ref->no_progress_ticks} + n;
        if (!r.residual("no_progress_ticks", kNoProgressOrder, pred, 0, kU32Max, v)) return false;
    } else {
        std::uint64_t u = 0;
        if (!r.ue("no_progress_ticks", kNoProgressOrder, u)) return false;
        if (u > static_cast<std::uint64_t>(kU32Max)) return r.fail("no_progress_ticks", "out of range");
        v = static_cast<std::int64_t>(u);
    }
    c.no_progress_ticks = static_cast<std::uint32_t>(v);
    return true;
}

/// The reference for one slot's car: the baseline's car if it was active.
const CarState* car_ref(const WorldSnapshot* baseline, std::size_t i) {
    if (!baseline || !baseline->state.cars[i].active) return nullptr;
    return &baseline->state.cars[i];
}

/// A baseline the decoder can use: one decode_world produced (or the
/// server's own encoder input). Checked so that a caller's mistake is an
/// error, not an assertion or an overflow.
bool baseline_usable(const WorldSnapshot& b, std::string& error) {
    if (b.state.cars.size() > static_cast<std::size_t>(kMaxSlots) || b.last_inputs.size() != b.state.cars.size()) {
        error = "world payload: baseline has a bad slot count";
        return false;
    }
    if (b.tick_rate_hz < 1 || b.tick_rate_hz > kMaxTickRate) {
        error = "world payload: baseline tick_rate_hz out of range";
        return false;
    }
    for (const CarState& c : b.state.cars) {
        if (!c.active) continue;
        // Decoding predicts from these: they must be what decode_world produces.
        bool ok = true;
        for (int i = 0; i < 3; ++i)
            ok = ok && is_units(c.position[i], kPosBits, kI32Min, kI32Max) &&
                 is_units(c.velocity[i], kVelBits, kI32Min, kI32Max);
        for (int i = 0; i < 4; ++i) ok = ok && is_units(c.orientation.coeffs()[i], kQuatBits, -kQuatLimit, kQuatLimit - 1);
        if (!ok) {
            error = "world payload: baseline car not quantised or out of range";
            return false;
        }
    }
    return true;
}

bool decode_into(std::span<const std::uint8_t> bytes, const WorldSnapshot* baseline, WorldSnapshot& out,
                 std::string& error);

}  // namespace

namespace {

// The header: tick, tick rate, start tick and laps, in full or against the
// baseline. Returns the ticks since the baseline (0 without one).
std::int64_t put_header(BitWriter& w, const WorldSnapshot& now, const WorldSnapshot* baseline) {
    const WorldState& s = now.state;
    std::int64_t n = 0;
    if (baseline) {
        const WorldState& b = baseline->state;
        assert(b.cars.size() == s.cars.size() && baseline->last_inputs.size() == s.cars.size());
        assert(s.tick >= b.tick && "encode_world: baseline newer than the state");
        assert(baseline->tick_rate_hz == now.tick_rate_hz);
        n = std::int64_t{s.tick} - b.tick;
        w.put_ue(static_cast<std::uint64_t>(n), kTickDeltaOrder);
        w.put_bit(s.start_tick == b.start_tick);
        if (s.start_tick != b.start_tick) w.put(s.start_tick, 32);
        w.put_bit(s.laps == b.laps);
        if (s.laps != b.laps) w.put(static_cast<std::uint64_t>(s.laps), 16);
    } else {
        w.put(s.tick, 32);
        w.put(now.tick_rate_hz, 16);
        w.put(s.start_tick, 32);
        w.put(static_cast<std::uint64_t>(s.laps), 16);
    }
    return n;
}

// Upcoming inputs of active cars: a 4-bit count, then each input as "same
// as the one before" (starting from the last input) or 10 bits.
void put_upcoming(BitWriter& w, const WorldSnapshot& now) {
    const WorldState& s = now.state;
    for (std::size_t i = 0; i < s.cars.size(); ++i) {
        if (!s.cars[i].active) continue;
        const std::size_t count =
            i < now.upcoming.size() ? std::min(now.upcoming[i].size(), kMaxUpcomingInputs) : std::size_t{0};
        w.put(count, kUpcomingCountBits);
        Input prev = now.last_inputs[i];
        for (std::size_t k = 0; k < count; ++k) {
            const Input& in = now.upcoming[i][k];
            w.put_bit(in == prev);
            if (!(in == prev)) w.put(in.pack(), 10);
            prev = in;
        }
    }
}

}  // namespace

std::vector<std::uint8_t> encode_world(const WorldSnapshot& now, const WorldSnapshot* baseline) {
    const WorldState& s = now.state;
    const std::size_t slots = s.cars.size();
    assert(slots <= static_cast<std::size_t>(kMaxSlots) && now.last_inputs.size() == slots);
    assert(s.laps >= 0 && s.laps <= 0xFFFF);
    assert(now.tick_rate_hz >= 1 && now.tick_rate_hz <= kMaxTickRate);
    BitWriter w;
    const std::int64_t n = put_header(w, now, baseline);
    const int rate = baseline ? baseline->tick_rate_hz : now.tick_rate_hz;
    w.put(slots, 7);
    for (std::size_t i = 0; i < slots; ++i) {
        const CarState& car = s.cars[i];
        const Input& input = now.last_inputs[i];
        if (baseline) {
            const bool identical = same_car(car, baseline->state.cars[i]) && input == baseline->last_inputs[i];
            w.put_bit(identical);
            if (identical) continue;
        }
        w.put_bit(car.active);
        if (car.active)
            put_car(w, car, car_ref(baseline, i), n, rate);
        else
            assert(same_car(car, CarState{}) && "encode_world: inactive slot with a non-default state");
        const Input ref_input = baseline ? baseline->last_inputs[i] : Input{};
        w.put_bit(input == ref_input);
        if (!(input == ref_input)) w.put(input.pack(), 10);
    }
    put_upcoming(w, now);
    return w.finish();
}

bool decode_world(std::span<const std::uint8_t> bytes, const WorldSnapshot* baseline, WorldSnapshot& out,
                  std::string& error) {
    if (bytes.empty()) {
        error = "world payload: empty";
        return false;
    }
    if (bytes.size() > kMaxMessageBytes) {
        error = "world payload: larger than kMaxMessageBytes";
        return false;
    }
    if (baseline && !baseline_usable(*baseline, error)) return false;
    // Decoded into a local: `out` may be the baseline itself, and is left
    // untouched on failure.
    WorldSnapshot result;
    if (!decode_into(bytes, baseline, result, error)) return false;
    out = std::move(result);
    return true;
}

namespace {

bool decode_into(std::span<const std::uint8_t> bytes, const WorldSnapshot* baseline, WorldSnapshot& out,
                 std::string& error) {
    Reader r(bytes, error);
    WorldState& s = out.state;
    std::uint64_t v = 0;
    std::int64_t n = 0;
    if (baseline) {
        const WorldState& b = baseline->state;
        if (!r.ue("tick", kTickDeltaOrder, v)) return false;
        if (v > static_cast<std::uint64_t>(kU32Max - b.tick)) return r.fail("tick", "out of range");
        n = static_cast<std::int64_t>(v);
        s.tick = static_cast<std::uint32_t>(b.tick + v);
        out.tick_rate_hz = baseline->tick_rate_hz;
        bool same = false;
        if (!r.bit("start_tick", same)) return false;
        if (same) {
            s.start_tick = b.start_tick;
        } else {
            if (!r.bits("start_tick", 32, v)) return false;
            s.start_tick = static_cast<std::uint32_t>(v);
        }
        if (!r.bit("laps", same)) return false;
        if (same) {
            s.laps = b.laps;
        } else {
            if (!r.bits("laps", 16, v)) return false;
            s.laps = static_cast<std::int32_t>(v);
        }
    } else {
        if (!r.bits("tick", 32, v)) return false;
        s.tick = static_cast<std::uint32_t>(v);
        if (!r.bits("tick_rate_hz", 16, v)) return false;
        if (v < 1 || v > kMaxTickRate) return r.fail("tick_rate_hz", "out of range");
        out.tick_rate_hz = static_cast<std::uint16_t>(v);
        if (!r.bits("start_tick", 32, v)) return false;
        s.start_tick = static_cast<std::uint32_t>(v);
        if (!r.bits("laps", 16, v)) return false;
        s.laps = static_cast<std::int32_t>(v);
    }
    if (!r.bits("slot count", 7, v)) return false;
    if (v > static_cast<std::uint64_t>(kMaxSlots)) return r.fail("slot count", "above kMaxSlots");
    if (baseline && v != baseline->state.cars.size()) return r.fail("slot count", "differs from the baseline's");
    const auto slots = static_cast<std::size_t>(v);
    s.cars.assign(slots, CarState{});
    out.last_inputs.assign(slots, Input{});
    for (std::size_t i = 0; i < slots; ++i) {
        r.set_prefix("slot " + std::to_string(i) + " ");
        if (baseline) {
            bool identical = false;
            if (!r.bit("identical", identical)) return false;
            if (identical) {
                s.cars[i] = baseline->state.cars[i];
                out.last_inputs[i] = baseline->last_inputs[i];
                continue;
            }
        }
        bool active = false;
        if (!r.bit("active", active)) return false;
        if (active && !get_car(r, car_ref(baseline, i), n, out.tick_rate_hz, s.cars[i])) return false;
        const Input ref_input = baseline ? baseline->last_inputs[i] : Input{};
        bool same_input = false;
        if (!r.bit("last input", same_input)) return false;
        if (same_input) {
            out.last_inputs[i] = ref_input;
        } else {
            if (!r.bits("last input", 10, v)) return false;
            if (!is_packed_input(v)) return r.fail("last input", "not an Input::pack() value");
            out.last_inputs[i] = Input::unpack(static_cast<std::uint16_t>(v));
        }
    }
    out.upcoming.assign(slots, {});
    for (std::size_t i = 0; i < slots; ++i) {
        if (!s.cars[i].active) continue;
        r.set_prefix("slot " + std::to_string(i) + " ");
        if (!r.bits("upcoming count", kUpcomingCountBits, v)) return false;
        const auto count = static_cast<std::size_t>(v);
        Input prev = out.last_inputs[i];
        for (std::size_t k = 0; k < count; ++k) {
            bool same = false;
            if (!r.bit("upcoming input", same)) return false;
            if (!same) {
                if (!r.bits("upcoming input", 10, v)) return false;
                if (!is_packed_input(v)) return r.fail("upcoming input", "not an Input::pack() value");
                prev = Input::unpack(static_cast<std::uint16_t>(v));
            }
            out.upcoming[i].push_back(prev);
        }
    }
    r.set_prefix("");
    if (!r.raw().only_padding_left()) return r.fail("end", "trailing bytes or non-zero padding");
    return true;
}

}  // namespace

bool world::read_world_tick(std::span<const std::uint8_t> payload, std::uint32_t baseline_tick, std::uint32_t& tick,
                            std::string& error) {
    BitReader r(payload);
    std::uint64_t v = 0;
    if (baseline_tick == kNoTick) {
        if (!r.get(32, v)) {
            error = std::string("world payload: tick: ") + r.error();
            return false;
        }
        tick = static_cast<std::uint32_t>(v);
        return true;
    }
    if (!r.get_ue(kTickDeltaOrder, v)) {
        error = std::string("world payload: tick: ") + r.error();
        return false;
    }
    if (v > static_cast<std::uint64_t>(kU32Max - baseline_tick)) {
        error = "world payload: tick: out of range";
        return false;
    }
    tick = static_cast<std::uint32_t>(baseline_tick + v);
    return true;
}

}  // namespace jetrace::proto
