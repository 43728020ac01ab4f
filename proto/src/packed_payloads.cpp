// The bit-packed payloads of InputBatch and Snapshot: docs/PROTOCOL.md,
// "Messages", sections "InputBatch" and "Snapshot", is the specification;
// keep the two in step.
#include "packed_payloads.hpp"

#include "bitstream.hpp"
#include "world_model.hpp"

#include <cassert>

namespace jetrace::proto::packed {

namespace {

using bits::BitReader;
using bits::BitWriter;

// Exp-Golomb orders and widths. Ticks restart at 0 every race, so absolute
// ticks are mostly below 2^14 (2.3 minutes at 120 Hz).
constexpr int kTickOrder = 14;
constexpr int kInputBits = 10;
constexpr int kInputCountBits = 6;
static_assert(kMaxInputsPerBatch == std::size_t{1} << kInputCountBits);
constexpr int kAckOrder = 0;
constexpr int kAppliedOrder = 0;
constexpr int kMarginOrder = 3;
constexpr int kRaceNumberOrder = 2;
constexpr int kPhaseBits = 2;
static_assert(static_cast<int>(RacePhase::finished) == (1 << kPhaseBits) - 1);
constexpr std::uint64_t kU32Max = 0xFFFFFFFFu;
/// input_margin_ticks with this value (the server's "no input yet") is
/// coded as 0, any other as zigzag + 1.
constexpr std::int16_t kNoMargin = -32768;

/// Reads a bit-packed payload, naming the field in errors.
class PackedReader {
public:
    PackedReader(std::span<const std::uint8_t> bytes, std::string& error) : r_(bytes), error_(error) {}
    bool fail(const char* field, const char* what) {
        error_ = std::string(field) + ": " + what;
        return false;
    }
    bool bits(const char* field, int n, std::uint64_t& v) { return r_.get(n, v) || fail(field, r_.error()); }
    bool bit(const char* field, bool& b) { return r_.get_bit(b) || fail(field, r_.error()); }
    bool ue(const char* field, int k, std::uint64_t& v) { return r_.get_ue(k, v) || fail(field, r_.error()); }
    bool se(const char* field, int k, std::int64_t& v) { return r_.get_se(k, v) || fail(field, r_.error()); }
    /// A tick coded as ue(kTickOrder): at most 2^32 - 1.
    bool tick(const char* field, std::uint32_t& t) {
        std::uint64_t v = 0;
        if (!ue(field, kTickOrder, v)) return false;
        if (v > kU32Max) return fail(field, "out of range");
        t = static_cast<std::uint32_t>(v);
        return true;
    }
    /// The residual of an optional tick: 1 bit "present", then se(k) of
    /// reference - tick (the reference may only be known later).
    bool optional_residual(const char* field, int k, bool& present, std::int64_t& d) {
        d = 0;
        return bit(field, present) && (!present || se(field, k, d));
    }
    /// The optional tick reference - d (kNoTick if absent); present, it must
    /// be 0 .. 2^32 - 2.
    bool resolve(const char* field, bool present, std::int64_t reference, std::int64_t d, std::uint32_t& t) {
        t = kNoTick;
        if (!present) return true;
        const std::int64_t v = reference - d;  // |reference| < 2^33, |d| < 2^55
        if (v < 0 || v >= static_cast<std::int64_t>(kNoTick)) return fail(field, "out of range");
        t = static_cast<std::uint32_t>(v);
        return true;
    }
    BitReader& raw() { return r_; }

private:
    BitReader r_;
    std::string& error_;
};

/// An optional tick as PackedReader::optional_residual and resolve read it.
void put_optional_tick(BitWriter& bw, std::uint32_t t, int k, std::int64_t reference) {
    bw.put_bit(t != kNoTick);
    if (t != kNoTick) bw.put_se(reference - std::int64_t{t}, k);
}

}  // namespace

std::vector<std::uint8_t> pack(const InputBatch& m) {
    assert(!m.inputs.empty() && m.inputs.size() <= kMaxInputsPerBatch);
    assert(m.inputs.size() - 1 <= kU32Max - m.first_tick);
    BitWriter bw;
    bw.put_ue(m.first_tick, kTickOrder);
    bw.put(m.inputs.size() - 1, kInputCountBits);
    put_optional_tick(bw, m.ack_snapshot_tick, kAckOrder, m.first_tick);
    for (std::size_t i = 0; i < m.inputs.size(); ++i) {
        const bool same = i > 0 && m.inputs[i] == m.inputs[i - 1];
        if (i > 0) bw.put_bit(same);
        if (!same) bw.put(m.inputs[i].pack(), kInputBits);
    }
    return bw.finish();
}

std::vector<std::uint8_t> pack(const Snapshot& m) {
    assert(!m.world.empty() && m.world.size() <= kMaxMessageBytes);
    std::uint32_t world_tick = 0;
    std::string error;
    const bool readable = world::read_world_tick(m.world, m.baseline_tick, world_tick, error);
    assert(readable && world_tick == m.server_tick && "encode: Snapshot.server_tick is not the world payload's tick");
    (void)readable;
    BitWriter bw;
    bw.put(static_cast<std::uint64_t>(m.phase), kPhaseBits);
    bw.put_bit(m.baseline_tick != kNoTick);
    if (m.baseline_tick != kNoTick) bw.put_ue(m.baseline_tick, kTickOrder);
    put_optional_tick(bw, m.last_applied_input_tick, kAppliedOrder, std::int64_t{m.server_tick} - 1);
    bw.put_ue(m.input_margin_ticks == kNoMargin ? 0 : bits::zigzag(m.input_margin_ticks) + 1, kMarginOrder);
    bw.put_ue(m.race_number, kRaceNumberOrder);
    std::vector<std::uint8_t> out = bw.finish();
    out.insert(out.end(), m.world.begin(), m.world.end());
    return out;
}

bool unpack(std::span<const std::uint8_t> bytes, InputBatch& m, std::string& error) {
    PackedReader r(bytes, error);
    m = InputBatch{};
    if (!r.tick("InputBatch.first_tick", m.first_tick)) return false;
    std::uint64_t v = 0;
    if (!r.bits("InputBatch.inputs", kInputCountBits, v)) return false;
    const std::size_t count = v + 1;  // 1 .. kMaxInputsPerBatch
    if (count - 1 > kU32Max - m.first_tick) return r.fail("InputBatch.first_tick", "last tick overflows");
    const char* const ack = "InputBatch.ack_snapshot_tick";
    bool has_ack = false;
    std::int64_t d = 0;
    if (!r.optional_residual(ack, kAckOrder, has_ack, d)) return false;
    if (!r.resolve(ack, has_ack, m.first_tick, d, m.ack_snapshot_tick)) return false;
    m.inputs.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        bool same = false;
        if (i > 0 && !r.bit("InputBatch.inputs", same)) return false;
        if (same) {
            m.inputs.push_back(m.inputs.back());
            continue;
        }
        if (!r.bits("InputBatch.inputs", kInputBits, v)) return false;
        if (!world::is_packed_input(v)) return r.fail("InputBatch.inputs", "not an Input::pack() value");
        m.inputs.push_back(Input::unpack(static_cast<std::uint16_t>(v)));
    }
    if (!r.raw().only_padding_left()) return r.fail("InputBatch.payload", "trailing bytes or non-zero padding");
    return true;
}

bool unpack(std::span<const std::uint8_t> bytes, Snapshot& m, std::string& error) {
    PackedReader r(bytes, error);
    m = Snapshot{};
    std::uint64_t v = 0;
    if (!r.bits("Snapshot.phase", kPhaseBits, v)) return false;
    m.phase = static_cast<RacePhase>(v);  // every 2-bit value is a phase
    bool has_baseline = false;
    if (!r.bit("Snapshot.baseline_tick", has_baseline)) return false;
    if (has_baseline) {
        if (!r.tick("Snapshot.baseline_tick", m.baseline_tick)) return false;
        if (m.baseline_tick == kNoTick) return r.fail("Snapshot.baseline_tick", "out of range");
    }
    // last_applied_input_tick is coded against server_tick - 1, and
    // server_tick is the world payload's first field, after the header.
    const char* const applied = "Snapshot.last_applied_input_tick";
    bool has_applied = false;
    std::int64_t d = 0;
    if (!r.optional_residual(applied, kAppliedOrder, has_applied, d)) return false;
    if (!r.ue("Snapshot.input_margin_ticks", kMarginOrder, v)) return false;
    if (v > 0xFFFF) return r.fail("Snapshot.input_margin_ticks", "out of range");
    m.input_margin_ticks = static_cast<std::int16_t>(v == 0 ? kNoMargin : bits::unzigzag(v - 1));
    if (!r.ue("Snapshot.race_number", kRaceNumberOrder, v)) return false;
    if (v > kU32Max) return r.fail("Snapshot.race_number", "out of range");
    m.race_number = static_cast<std::uint32_t>(v);
    if (!r.raw().skip_padding()) return r.fail("Snapshot.payload", "non-zero padding after the header");
    const std::span<const std::uint8_t> world = r.raw().rest_bytes();
    if (world.empty()) return r.fail("Snapshot.world", "empty");
    if (world.size() > kMaxMessageBytes) return r.fail("Snapshot.world", "too long");
    std::string why;
    if (!world::read_world_tick(world, m.baseline_tick, m.server_tick, why))
        return r.fail("Snapshot.world", why.c_str());
    if (!r.resolve(applied, has_applied, std::int64_t{m.server_tick} - 1, d, m.last_applied_input_tick)) return false;
    m.world.assign(world.begin(), world.end());
    return true;
}

}  // namespace jetrace::proto::packed
