#include "jetrace/replay/format.hpp"

#include "jetrace/core/crc32c.hpp"
#include "jetrace/core/race.hpp"
#include "jetrace/core/state_bytes.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace jetrace::replay {

const char* end_reason_name(EndReason r) {
    switch (r) {
        case EndReason::finished: return "finished";
        case EndReason::finish_window: return "finish window";
        case EndReason::time_limit: return "time limit";
        case EndReason::abandoned: return "abandoned";
        case EndReason::aborted: return "aborted";
        case EndReason::drained: return "drained";
    }
    return "unknown";
}

void frame(RecordKind kind, std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& out) {
    const std::size_t start = out.size();
    put_u8(out, static_cast<std::uint8_t>(kind));
    put_u32(out, static_cast<std::uint32_t>(payload.size()));
    out.insert(out.end(), payload.begin(), payload.end());
    const auto body = std::span<const std::uint8_t>(out).subspan(start);
    put_u32(out, crc32c(body));
}

namespace {

void put_i64(std::vector<std::uint8_t>& out, std::int64_t v) { put_u64(out, static_cast<std::uint64_t>(v)); }
bool get_i64(std::span<const std::uint8_t> in, std::size_t& off, std::int64_t& v) {
    std::uint64_t u = 0;
    if (!get_u64(in, off, u)) return false;
    v = static_cast<std::int64_t>(u);
    return true;
}

void put_string(std::vector<std::uint8_t>& out, const std::string& s, std::size_t max) {
    const std::size_t n = s.size() < max ? s.size() : max;
    put_u16(out, static_cast<std::uint16_t>(n));
    out.insert(out.end(), s.begin(), s.begin() + static_cast<std::ptrdiff_t>(n));
}
bool get_string(std::span<const std::uint8_t> in, std::size_t& off, std::string& s, std::size_t max) {
    std::uint16_t n = 0;
    if (!get_u16(in, off, n) || n > max || in.size() - off < n) return false;
    s.assign(reinterpret_cast<const char*>(in.data() + off), n);
    off += n;
    return true;
}

bool finish(std::span<const std::uint8_t> in, std::size_t off, bool ok, const char* what, std::string& error) {
    if (!ok) {
        error = std::string(what) + " record is short or has a value out of range";
        return false;
    }
    if (off != in.size()) {
        error = std::string(what) + " record has " + std::to_string(in.size() - off) + " bytes too many";
        return false;
    }
    return true;
}

}  // namespace

void encode(const Header& h, std::vector<std::uint8_t>& out) {
    put_string(out, h.track_name, 0xFFFF);
    put_u64(out, h.track_identity);
    put_u64(out, h.physics_hash);
    put_u16(out, h.tick_rate_hz);
    put_u16(out, h.checkpoint_every);
    put_u16(out, h.keyframe_every);
    put_u32(out, h.race_number);
    put_i64(out, h.start_unix_s);
    put_u16(out, static_cast<std::uint16_t>(h.names.size()));
    for (const std::string& n : h.names) put_string(out, n, kMaxNameBytes);
    write_state(h.initial, out);
}

bool decode(std::span<const std::uint8_t> in, Header& h, std::string& error) {
    h = Header{};
    std::size_t off = 0;
    std::uint16_t names = 0;
    bool ok = get_string(in, off, h.track_name, 0xFFFF) && get_u64(in, off, h.track_identity) &&
              get_u64(in, off, h.physics_hash) && get_u16(in, off, h.tick_rate_hz) &&
              get_u16(in, off, h.checkpoint_every) && get_u16(in, off, h.keyframe_every) &&
              get_u32(in, off, h.race_number) && get_i64(in, off, h.start_unix_s) && get_u16(in, off, names);
    if (!ok) return finish(in, off, false, "header", error);
    if (h.checkpoint_every == 0 || h.keyframe_every % h.checkpoint_every != 0) {
        error = "header: keyframe_every (" + std::to_string(h.keyframe_every) + ") is not a multiple of checkpoint_every (" +
                std::to_string(h.checkpoint_every) + ")";
        return false;
    }
    for (std::uint16_t i = 0; ok && i < names; ++i) {
        std::string n;
        ok = get_string(in, off, n, kMaxNameBytes);
        h.names.push_back(std::move(n));
    }
    if (!ok) return finish(in, off, false, "header", error);
    if (!read_state(in, off, h.initial, error)) {
        error = "header: initial " + error;
        return false;
    }
    if (h.initial.cars.size() > kMaxReplaySlots) {
        error = "header: more than " + std::to_string(kMaxReplaySlots) + " slots";
        return false;
    }
    if (h.names.size() > h.initial.cars.size()) {
        error = "header names more players than the world has slots";
        return false;
    }
    return finish(in, off, true, "header", error);
}

void encode_tick(std::uint32_t tick, std::span<const std::uint8_t> removed, std::span<const Input> inputs,
                 std::vector<std::uint8_t>& out) {
    put_u32(out, tick);
    put_u8(out, static_cast<std::uint8_t>(removed.size()));
    out.insert(out.end(), removed.begin(), removed.end());
    put_u16(out, static_cast<std::uint16_t>(inputs.size()));
    for (const Input& in : inputs) put_u16(out, in.pack());
}

bool decode(std::span<const std::uint8_t> in, std::size_t slots, TickRecord& t, std::string& error) {
    std::size_t off = 0;
    std::uint8_t removed = 0;
    std::uint16_t count = 0;
    bool ok = get_u32(in, off, t.tick) && get_u8(in, off, removed) && in.size() - off >= removed;
    if (!ok) return finish(in, off, false, "tick", error);
    t.removed.assign(in.begin() + static_cast<std::ptrdiff_t>(off), in.begin() + static_cast<std::ptrdiff_t>(off + removed));
    off += removed;
    ok = get_u16(in, off, count);
    if (ok && count != slots) {
        error = "tick record has " + std::to_string(count) + " inputs for " + std::to_string(slots) + " slots";
        return false;
    }
    t.inputs.resize(count);
    for (std::uint16_t i = 0; ok && i < count; ++i) {
        std::uint16_t bits = 0;
        ok = get_u16(in, off, bits);
        t.inputs[i] = Input::unpack(bits);
    }
    for (std::uint8_t s : t.removed) {
        if (s >= slots) {
            error = "tick record removes slot " + std::to_string(s) + " of " + std::to_string(slots);
            return false;
        }
    }
    return finish(in, off, ok, "tick", error);
}

void encode(const Checkpoint& c, std::vector<std::uint8_t>& out) {
    put_u32(out, c.tick);
    put_u64(out, c.state_hash);
    put_u16(out, static_cast<std::uint16_t>(c.car_hashes.size()));
    for (std::uint64_t h : c.car_hashes) put_u64(out, h);
}

bool decode(std::span<const std::uint8_t> in, Checkpoint& c, std::string& error) {
    std::size_t off = 0;
    std::uint16_t n = 0;
    bool ok = get_u32(in, off, c.tick) && get_u64(in, off, c.state_hash) && get_u16(in, off, n) &&
              in.size() - off >= std::size_t{n} * 8;
    c.car_hashes.assign(ok ? n : 0, 0);
    for (std::uint64_t& h : c.car_hashes) ok = ok && get_u64(in, off, h);
    return finish(in, off, ok, "checkpoint", error);
}

bool decode_keyframe(std::span<const std::uint8_t> in, WorldState& s, std::string& error) {
    std::size_t off = 0;
    if (!read_state(in, off, s, error)) {
        error = "keyframe: " + error;
        return false;
    }
    return finish(in, off, true, "keyframe", error);
}

void encode(const Trailer& t, std::vector<std::uint8_t>& out) {
    put_u32(out, t.final_tick);
    put_u64(out, t.final_state_hash);
    put_u8(out, static_cast<std::uint8_t>(t.reason));
    put_i64(out, t.end_unix_s);
    put_u8(out, static_cast<std::uint8_t>(t.removed.size()));
    out.insert(out.end(), t.removed.begin(), t.removed.end());
    put_u16(out, static_cast<std::uint16_t>(t.results.size()));
    for (const ResultEntry& r : t.results) {
        put_u8(out, r.slot);
        put_u8(out, r.finished ? 1 : 0);
        put_u32(out, static_cast<std::uint32_t>(r.lap));
        put_u32(out, static_cast<std::uint32_t>(r.next_checkpoint));
        put_f64(out, r.finish_time_s);
    }
}

bool decode(std::span<const std::uint8_t> in, std::size_t slots, Trailer& t, std::string& error) {
    std::size_t off = 0;
    std::uint8_t reason = 0, removed = 0;
    std::uint16_t n = 0;
    bool ok = get_u32(in, off, t.final_tick) && get_u64(in, off, t.final_state_hash) && get_u8(in, off, reason) &&
              reason >= 1 && reason <= static_cast<std::uint8_t>(EndReason::drained) &&
              get_i64(in, off, t.end_unix_s) && get_u8(in, off, removed) &&
              in.size() - off >= removed;
    if (!ok) return finish(in, off, false, "trailer", error);
    t.removed.assign(in.begin() + static_cast<std::ptrdiff_t>(off), in.begin() + static_cast<std::ptrdiff_t>(off + removed));
    off += removed;
    for (std::uint8_t s : t.removed) {
        if (s >= slots) {
            error = "trailer removes slot " + std::to_string(s) + " of " + std::to_string(slots);
            return false;
        }
    }
    ok = get_u16(in, off, n) && in.size() - off >= std::size_t{n} * 18;
    t.reason = static_cast<EndReason>(reason);
    t.results.assign(ok ? n : 0, ResultEntry{});
    for (ResultEntry& r : t.results) {
        std::uint8_t fin = 0;
        std::uint32_t lap = 0, next = 0;
        ok = ok && get_u8(in, off, r.slot) && get_u8(in, off, fin) && fin <= 1 && get_u32(in, off, lap) &&
             get_u32(in, off, next) && get_f64(in, off, r.finish_time_s) && std::isfinite(r.finish_time_s);
        r.finished = fin == 1;
        r.lap = static_cast<std::int32_t>(lap);
        r.next_checkpoint = static_cast<std::int32_t>(next);
    }
    return finish(in, off, ok, "trailer", error);
}

void encode(const Signature& s, std::vector<std::uint8_t>& out) {
    put_u8(out, kSignatureEd25519ph);
    out.insert(out.end(), s.public_key.begin(), s.public_key.end());
    out.insert(out.end(), s.signature.begin(), s.signature.end());
}

bool decode(std::span<const std::uint8_t> in, Signature& s, std::string& error) {
    if (in.size() != 1 + s.public_key.size() + s.signature.size() || in[0] != kSignatureEd25519ph) {
        error = "signature record has an unknown algorithm or the wrong size";
        return false;
    }
    std::copy(in.begin() + 1, in.begin() + 33, s.public_key.begin());
    std::copy(in.begin() + 33, in.end(), s.signature.begin());
    return true;
}

Checkpoint checkpoint_of(const WorldState& s) {
    Checkpoint c;
    c.tick = s.tick;
    c.state_hash = state_hash(s);
    c.car_hashes.reserve(s.cars.size());
    for (const CarState& car : s.cars) c.car_hashes.push_back(car_hash(car));
    return c;
}

Header header_for(const Scene& scene, const WorldState& initial) {
    Header h;
    h.track_name = scene.track.name;
    h.track_identity = scene.track.identity();
    h.physics_hash = physics_fingerprint(scene.physics);
    h.tick_rate_hz = static_cast<std::uint16_t>(scene.physics.tick_rate_hz);
    h.initial = initial;
    return h;
}

Trailer trailer_for(const Scene& scene, const WorldState& final_state, EndReason reason) {
    Trailer t;
    t.final_tick = final_state.tick;
    t.final_state_hash = state_hash(final_state);
    t.reason = reason;
    t.results = results_of(scene, final_state);
    return t;
}

std::vector<ResultEntry> results_of(const Scene& scene, const WorldState& s) {
    std::vector<ResultEntry> out;
    for (const Standing& st : standings(scene.track, s.cars, s.start_tick, scene.physics.tick_rate_hz)) {
        out.push_back({static_cast<std::uint8_t>(st.slot), st.finished, st.lap, st.next_checkpoint, st.finish_time_s});
    }
    return out;
}

}  // namespace jetrace::replay
