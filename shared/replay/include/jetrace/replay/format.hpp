// The replay file format, version 2 (docs/REPLAY_FORMAT.md is the
// specification): an 8-byte magic, then records, each framed as
//   u8 kind | u32 payload length | payload | u32 CRC-32C of the previous three
// in this grammar:
//   Header (Tick [Checkpoint [Keyframe]])* Trailer [Signature]
// A checkpoint follows the tick record after which the world's tick is a
// multiple of checkpoint_every ticks past the initial tick, a keyframe the
// checkpoint of every keyframe_every ticks. All integers little-endian,
// doubles as their raw IEEE-754 bits.
#pragma once

#include "jetrace/core/world.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace jetrace::replay {

/// "JTRREPL" and the version digit.
inline constexpr std::array<std::uint8_t, 8> kMagic = {'J', 'T', 'R', 'R', 'E', 'P', 'L', '2'};
inline constexpr std::size_t kRecordHeadBytes = 5;
inline constexpr std::size_t kRecordTailBytes = 4;
/// Largest payload a reader accepts (unit: bytes). A keyframe of the most
/// slots read_state() takes is about 117 KiB.
inline constexpr std::uint32_t kMaxPayloadBytes = 1u << 20;
/// Largest replay file a reader opens (unit: bytes): about 30 days of an
/// 8-car race at 120 Hz.
inline constexpr std::uint64_t kMaxFileBytes = std::uint64_t{4} << 30;
/// Most car slots a replay holds (a tick record names removed slots in a byte).
inline constexpr std::size_t kMaxReplaySlots = 255;
/// Longest player name kept in a header (unit: bytes).
inline constexpr std::size_t kMaxNameBytes = 64;

enum class RecordKind : std::uint8_t {
    header = 'H',
    tick = 'T',
    checkpoint = 'C',
    keyframe = 'K',
    trailer = 'E',
    signature = 'S',
};

struct Header {
    std::string track_name;
    std::uint64_t track_identity = 0;
    std::uint64_t physics_hash = 0;
    /// (unit: Hz).
    std::uint16_t tick_rate_hz = 120;
    /// A checkpoint every this many ticks (unit: ticks, at least 1).
    std::uint16_t checkpoint_every = 120;
    /// A keyframe every this many ticks: 0 (none) or a multiple of
    /// checkpoint_every (unit: ticks).
    std::uint16_t keyframe_every = 600;
    /// The server's race number (0 for offline races).
    std::uint32_t race_number = 0;
    /// Start of the race (unit: s since 1970 UTC; 0 = not recorded).
    std::int64_t start_unix_s = 0;
    /// Player name per slot ("" = none); at most one per slot.
    std::vector<std::string> names;
    WorldState initial;
};

/// The inputs of one tick: cars removed before it, then one input per slot.
struct TickRecord {
    std::uint32_t tick = 0;
    std::vector<std::uint8_t> removed;
    std::vector<Input> inputs;
};

/// The world after a tick: its state_hash() and every slot's car_hash().
struct Checkpoint {
    std::uint32_t tick = 0;
    std::uint64_t state_hash = 0;
    std::vector<std::uint64_t> car_hashes;
};

enum class EndReason : std::uint8_t {
    finished = 1,       ///< every car still racing finished
    finish_window = 2,  ///< the window after the first finish closed
    time_limit = 3,     ///< the race's time limit (or the offline run's length)
    abandoned = 4,      ///< no car was left
    aborted = 5,        ///< the server stopped the race at once
    drained = 6,        ///< the server's drain timeout cut the race short
};
const char* end_reason_name(EndReason r);

/// One place of the final standings (jetrace::standings()).
struct ResultEntry {
    std::uint8_t slot = 0;
    bool finished = false;
    std::int32_t lap = 0;
    std::int32_t next_checkpoint = 0;
    /// (unit: s), when finished.
    double finish_time_s = 0;
    bool operator==(const ResultEntry&) const = default;
};

struct Trailer {
    std::uint32_t final_tick = 0;
    std::uint64_t final_state_hash = 0;
    EndReason reason = EndReason::finished;
    /// End of the race (unit: s since 1970 UTC; 0 = not recorded).
    std::int64_t end_unix_s = 0;
    /// Cars removed after the last tick (a race stopped between ticks);
    /// the final state hash is taken after removing them.
    std::vector<std::uint8_t> removed;
    std::vector<ResultEntry> results;
};

/// Ed25519ph (RFC 8032, SHA-512 prehash) over kSignatureDomain followed by
/// every byte of the file before the signature record.
struct Signature {
    std::array<std::uint8_t, 32> public_key{};
    std::array<std::uint8_t, 64> signature{};
};
inline constexpr std::uint8_t kSignatureEd25519ph = 1;
inline constexpr std::string_view kSignatureDomain = "jetrace replay signature v2\n";

void encode(const Header& h, std::vector<std::uint8_t>& out);
void encode_tick(std::uint32_t tick, std::span<const std::uint8_t> removed, std::span<const Input> inputs,
                 std::vector<std::uint8_t>& out);
void encode(const Checkpoint& c, std::vector<std::uint8_t>& out);
void encode(const Trailer& t, std::vector<std::uint8_t>& out);
void encode(const Signature& s, std::vector<std::uint8_t>& out);

/// Decoders of untrusted payloads: false with a reason on anything
/// malformed (short, long, out of range).
bool decode(std::span<const std::uint8_t> in, Header& h, std::string& error);
bool decode(std::span<const std::uint8_t> in, std::size_t slots, TickRecord& t, std::string& error);
bool decode(std::span<const std::uint8_t> in, Checkpoint& c, std::string& error);
bool decode_keyframe(std::span<const std::uint8_t> in, WorldState& s, std::string& error);
bool decode(std::span<const std::uint8_t> in, std::size_t slots, Trailer& t, std::string& error);
bool decode(std::span<const std::uint8_t> in, Signature& s, std::string& error);

/// A whole framed record: head, payload, CRC.
void frame(RecordKind kind, std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& out);

Checkpoint checkpoint_of(const WorldState& s);
/// A header for a race on `scene` starting from `initial` (default
/// checkpoint and keyframe spacing, no names, no race number).
Header header_for(const Scene& scene, const WorldState& initial);
/// The trailer of a race that ended in `final_state` (no removals, no time).
Trailer trailer_for(const Scene& scene, const WorldState& final_state, EndReason reason);
std::vector<ResultEntry> results_of(const Scene& scene, const WorldState& s);

}  // namespace jetrace::replay
