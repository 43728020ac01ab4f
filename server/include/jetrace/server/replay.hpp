// Race replays: the track's identity, the settings, the world at the start
// of the race and every car's input per tick (and the cars removed before
// each tick). jetrace-sim --replay re-simulates one and prints the same
// state_hash= line as the live server did.
//
// File layout (little-endian): "JTRREPL1", u16 version (1), u16 name length +
// track name bytes, u64 track identity, u64 physics hash, u16 tick rate, the
// initial WorldState (jetrace/state_bytes.hpp), then tick records until the
// end of the file: u8 'T', u32 tick, u8 n + n slot bytes (cars removed
// before this tick), u16 slot count, one packed u16 Input per slot. The file
// is flushed as it grows; a final record cut short (a killed server) is
// ignored when reading.
#pragma once

#include "jetrace/world.hpp"

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

namespace jetrace {

struct ReplayHeader {
    std::string track_name;
    std::uint64_t track_identity = 0;
    std::uint64_t physics_hash = 0;
    std::uint16_t tick_rate_hz = 120;
    WorldState initial;
};

struct ReplayTick {
    std::uint32_t tick = 0;
    std::vector<std::uint8_t> removed;
    std::vector<Input> inputs;
};

struct Replay {
    ReplayHeader header;
    std::vector<ReplayTick> ticks;
    /// The file ended inside a record (ignored).
    bool truncated = false;
};

class ReplayWriter {
public:
    ReplayWriter() = default;
    ~ReplayWriter();
    ReplayWriter(const ReplayWriter&) = delete;
    ReplayWriter& operator=(const ReplayWriter&) = delete;

    /// Creates (truncates) `path` and writes the header. False and `error` on failure.
    bool open(const std::string& path, const ReplayHeader& header, std::string& error);
    /// Appends one tick; flushes to the OS every `flush_every` records.
    void record(std::uint32_t tick, std::span<const std::uint8_t> removed, std::span<const Input> inputs);
    void flush();
    void close();
    bool is_open() const { return file_ != nullptr; }

private:
    std::FILE* file_ = nullptr;
    std::vector<std::uint8_t> buffer_;
    int since_flush_ = 0;
};

/// Parses a replay file (untrusted). False with a reason on anything malformed.
bool read_replay(const std::string& path, Replay& out, std::string& error);
/// Parses replay bytes (untrusted); the fuzz target calls this.
bool parse_replay(std::span<const std::uint8_t> bytes, Replay& out, std::string& error);

/// Checks a replay against a scene (identity, slot counts, gate indices).
bool check_replay(const Scene& scene, const Replay& replay, std::uint64_t physics_hash, std::string& error);

/// Re-simulates a checked replay; returns the final state.
WorldState run_replay(const Scene& scene, const Replay& replay);

}  // namespace jetrace
