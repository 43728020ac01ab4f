#include "jetrace/server/replay.hpp"

#include "jetrace/state_bytes.hpp"

#include <cstring>
#include <fstream>
#include <iterator>

namespace jetrace {

namespace {
constexpr char kMagic[8] = {'J', 'T', 'R', 'R', 'E', 'P', 'L', '1'};
constexpr std::uint16_t kVersion = 1;
constexpr std::uint8_t kTickTag = 'T';
constexpr int kFlushEvery = 120;
constexpr std::size_t kMaxReplayBytes = std::size_t{1} << 31;
}  // namespace

ReplayWriter::~ReplayWriter() { close(); }

bool ReplayWriter::open(const std::string& path, const ReplayHeader& h, std::string& error) {
    close();
    file_ = std::fopen(path.c_str(), "wb");
    if (!file_) {
        error = "cannot create replay file '" + path + "': " + std::strerror(errno);
        return false;
    }
    buffer_.assign(std::begin(kMagic), std::end(kMagic));
    put_u16(buffer_, kVersion);
    put_u16(buffer_, static_cast<std::uint16_t>(h.track_name.size()));
    buffer_.insert(buffer_.end(), h.track_name.begin(), h.track_name.end());
    put_u64(buffer_, h.track_identity);
    put_u64(buffer_, h.physics_hash);
    put_u16(buffer_, h.tick_rate_hz);
    write_state(h.initial, buffer_);
    flush();
    return true;
}

void ReplayWriter::record(std::uint32_t tick, std::span<const std::uint8_t> removed, std::span<const Input> inputs) {
    if (!file_) return;
    put_u8(buffer_, kTickTag);
    put_u32(buffer_, tick);
    put_u8(buffer_, static_cast<std::uint8_t>(removed.size()));
    buffer_.insert(buffer_.end(), removed.begin(), removed.end());
    put_u16(buffer_, static_cast<std::uint16_t>(inputs.size()));
    for (const Input& in : inputs) put_u16(buffer_, in.pack());
    if (++since_flush_ >= kFlushEvery) flush();
}

void ReplayWriter::flush() {
    if (!file_) return;
    if (!buffer_.empty()) std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
    buffer_.clear();
    std::fflush(file_);
    since_flush_ = 0;
}

void ReplayWriter::close() {
    if (!file_) return;
    flush();
    std::fclose(file_);
    file_ = nullptr;
}

bool parse_replay(std::span<const std::uint8_t> in, Replay& out, std::string& error) {
    out = Replay{};
    std::size_t off = 0;
    if (in.size() < sizeof kMagic || std::memcmp(in.data(), kMagic, sizeof kMagic) != 0) {
        error = "not a jetrace replay (bad magic)";
        return false;
    }
    off = sizeof kMagic;
    std::uint16_t version = 0, name_len = 0;
    if (!get_u16(in, off, version) || version != kVersion) {
        error = "unsupported replay version";
        return false;
    }
    if (!get_u16(in, off, name_len) || in.size() - off < name_len) {
        error = "replay header truncated (track name)";
        return false;
    }
    out.header.track_name.assign(reinterpret_cast<const char*>(in.data() + off), name_len);
    off += name_len;
    if (!get_u64(in, off, out.header.track_identity) || !get_u64(in, off, out.header.physics_hash) ||
        !get_u16(in, off, out.header.tick_rate_hz)) {
        error = "replay header truncated";
        return false;
    }
    if (!read_state(in, off, out.header.initial, error)) {
        error = "replay initial " + error;
        return false;
    }
    const std::size_t slots = out.header.initial.cars.size();
    std::uint32_t expected = out.header.initial.tick;
    while (off < in.size()) {
        const std::size_t start = off;
        ReplayTick t;
        std::uint8_t tag = 0, removed = 0;
        std::uint16_t count = 0;
        bool ok = get_u8(in, off, tag) && get_u32(in, off, t.tick) && get_u8(in, off, removed);
        if (ok && tag != kTickTag) {
            error = "replay record at byte " + std::to_string(start) + " has a bad tag";
            return false;
        }
        for (std::uint8_t i = 0; ok && i < removed; ++i) {
            std::uint8_t s = 0;
            ok = get_u8(in, off, s);
            t.removed.push_back(s);
        }
        ok = ok && get_u16(in, off, count);
        for (std::uint16_t i = 0; ok && i < count; ++i) {
            std::uint16_t bits = 0;
            ok = get_u16(in, off, bits);
            t.inputs.push_back(Input::unpack(bits));
        }
        if (!ok) {
            out.truncated = true;  // a record cut short by a kill: ignore it
            break;
        }
        if (t.tick != expected || count != slots) {
            error = "replay record at byte " + std::to_string(start) + " is out of sequence or has the wrong slot count";
            return false;
        }
        for (std::uint8_t s : t.removed) {
            if (s >= slots) {
                error = "replay record at byte " + std::to_string(start) + " removes slot out of range";
                return false;
            }
        }
        ++expected;
        out.ticks.push_back(std::move(t));
    }
    return true;
}

bool read_replay(const std::string& path, Replay& out, std::string& error) {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        error = "cannot open replay '" + path + "'";
        return false;
    }
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (bytes.size() > kMaxReplayBytes) {
        error = "replay too large";
        return false;
    }
    if (!parse_replay(bytes, out, error)) {
        error = path + ": " + error;
        return false;
    }
    return true;
}

bool check_replay(const Scene& scene, const Replay& r, std::uint64_t physics_hash, std::string& error) {
    if (r.header.track_identity != scene.track.identity()) {
        error = "replay was recorded on a different track than '" + scene.track.name + "' (identity mismatch)";
        return false;
    }
    if (r.header.physics_hash != physics_hash || r.header.tick_rate_hz != scene.physics.tick_rate_hz) {
        error = "replay was recorded with different physics settings";
        return false;
    }
    const auto gates = static_cast<std::int32_t>(scene.track.checkpoints.size());
    for (const CarState& c : r.header.initial.cars) {
        if (c.next_checkpoint >= gates || c.respawn_checkpoint >= gates) {
            error = "replay initial state names a gate the track does not have";
            return false;
        }
    }
    return true;
}

WorldState run_replay(const Scene& scene, const Replay& r) {
    WorldState st = r.header.initial;
    StepScratch scratch;
    for (const ReplayTick& t : r.ticks) {
        for (std::uint8_t s : t.removed) remove_car(st, s);
        step(scene, st, t.inputs, scratch);
    }
    return st;
}

}  // namespace jetrace
