#include "jetrace/core/state_bytes.hpp"

#include <bit>
#include <cmath>

namespace jetrace {

void put_u8(std::vector<std::uint8_t>& out, std::uint8_t v) { out.push_back(v); }
void put_u16(std::vector<std::uint8_t>& out, std::uint16_t v) {
    for (int i = 0; i < 2; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<std::uint8_t>& out, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_f64(std::vector<std::uint8_t>& out, double v) { put_u64(out, std::bit_cast<std::uint64_t>(v)); }

namespace {
template <class T>
bool get_le(std::span<const std::uint8_t> in, std::size_t& off, T& v) {
    if (off > in.size() || in.size() - off < sizeof(T)) return false;
    std::uint64_t x = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) x |= std::uint64_t{in[off + i]} << (8 * i);
    v = static_cast<T>(x);
    off += sizeof(T);
    return true;
}
}  // namespace

bool get_u8(std::span<const std::uint8_t> in, std::size_t& off, std::uint8_t& v) { return get_le(in, off, v); }
bool get_u16(std::span<const std::uint8_t> in, std::size_t& off, std::uint16_t& v) { return get_le(in, off, v); }
bool get_u32(std::span<const std::uint8_t> in, std::size_t& off, std::uint32_t& v) { return get_le(in, off, v); }
bool get_u64(std::span<const std::uint8_t> in, std::size_t& off, std::uint64_t& v) { return get_le(in, off, v); }
bool get_f64(std::span<const std::uint8_t> in, std::size_t& off, double& v) {
    std::uint64_t bits = 0;
    if (!get_u64(in, off, bits)) return false;
    v = std::bit_cast<double>(bits);
    return true;
}

void write_state(const WorldState& s, std::vector<std::uint8_t>& out) {
    put_u32(out, s.tick);
    put_u32(out, s.start_tick);
    put_u32(out, static_cast<std::uint32_t>(s.laps));
    put_u32(out, static_cast<std::uint32_t>(s.cars.size()));
    for (const CarState& c : s.cars) {
        put_u8(out, static_cast<std::uint8_t>((c.active ? 1 : 0) | (c.finished ? 2 : 0)));
        for (int i = 0; i < 3; ++i) put_f64(out, c.position[i]);
        for (int i = 0; i < 3; ++i) put_f64(out, c.velocity[i]);
        put_f64(out, c.orientation.w());
        put_f64(out, c.orientation.x());
        put_f64(out, c.orientation.y());
        put_f64(out, c.orientation.z());
        put_u32(out, static_cast<std::uint32_t>(c.next_checkpoint));
        put_u32(out, static_cast<std::uint32_t>(c.lap));
        put_u32(out, static_cast<std::uint32_t>(c.respawn_checkpoint));
        put_u32(out, c.finish_tick);
        put_f64(out, c.finish_fraction);
        put_u32(out, c.respawns);
        put_u32(out, static_cast<std::uint32_t>(c.best_gate_distance_m));
        put_u32(out, c.no_progress_ticks);
    }
}

bool read_state(std::span<const std::uint8_t> in, std::size_t& off, WorldState& s, std::string& error) {
    std::uint32_t laps = 0, n = 0;
    if (!get_u32(in, off, s.tick) || !get_u32(in, off, s.start_tick) || !get_u32(in, off, laps) ||
        !get_u32(in, off, n)) {
        error = "state: truncated header";
        return false;
    }
    if (laps < 1 || laps > 1000) {
        error = "state: laps out of range";
        return false;
    }
    if (n > kMaxStateSlots) {
        error = "state: too many slots";
        return false;
    }
    s.laps = static_cast<std::int32_t>(laps);
    s.cars.assign(n, CarState{});
    for (std::uint32_t k = 0; k < n; ++k) {
        CarState& c = s.cars[k];
        std::uint8_t flags = 0;
        double q[4];
        std::uint32_t next = 0, lap = 0, respawn = 0, best = 0;
        bool ok = get_u8(in, off, flags);
        for (int i = 0; i < 3 && ok; ++i) ok = get_f64(in, off, c.position[i]);
        for (int i = 0; i < 3 && ok; ++i) ok = get_f64(in, off, c.velocity[i]);
        for (int i = 0; i < 4 && ok; ++i) ok = get_f64(in, off, q[i]);
        ok = ok && get_u32(in, off, next) && get_u32(in, off, lap) && get_u32(in, off, respawn) &&
             get_u32(in, off, c.finish_tick) && get_f64(in, off, c.finish_fraction) && get_u32(in, off, c.respawns) &&
             get_u32(in, off, best) && get_u32(in, off, c.no_progress_ticks);
        if (!ok) {
            error = "state: truncated car " + std::to_string(k);
            return false;
        }
        bool finite = std::isfinite(c.finish_fraction);
        for (int i = 0; i < 3; ++i) finite = finite && std::isfinite(c.position[i]) && std::isfinite(c.velocity[i]);
        for (double v : q) finite = finite && std::isfinite(v);
        if (!finite || flags > 3 || next > 65535 || lap > 65535 || respawn > 65535) {
            error = "state: car " + std::to_string(k) + " has a value out of range";
            return false;
        }
        c.active = (flags & 1) != 0;
        c.finished = (flags & 2) != 0;
        c.orientation = Quat(q[0], q[1], q[2], q[3]);
        c.next_checkpoint = static_cast<std::int32_t>(next);
        c.lap = static_cast<std::int32_t>(lap);
        c.respawn_checkpoint = static_cast<std::int32_t>(respawn);
        c.best_gate_distance_m = static_cast<std::int32_t>(best);
    }
    return true;
}

}  // namespace jetrace
