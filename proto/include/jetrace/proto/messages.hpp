// Every message of the jetrace protocol as a plain C++ value, and its
// encoding to and from bytes (flatbuffers, schema in proto/jetrace.fbs).
// Decoding verifies the buffer and range-checks every field: bytes from the
// network are untrusted, a bad message is an error string, never a crash.
// docs/PROTOCOL.md describes the wire format, channels and state machine.
#pragma once

#include "jetrace/core/hovercar.hpp"
#include "jetrace/proto/close_code.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace jetrace::proto {

inline constexpr std::uint16_t kProtocolVersion = 6;
/// Larger datagrams are rejected before parsing (unit: bytes).
inline constexpr std::size_t kMaxMessageBytes = 8192;
/// Longest Snapshot payload (unit: bytes): room left for the flatbuffers
/// framing FlatBufferBuilder adds around it (root offset, identifier,
/// vtable, table, vector length, alignment: under 64 bytes), so that any
/// Snapshot that decodes also re-encodes within kMaxMessageBytes. A
/// hand-made buffer can frame a payload more tightly than the builder does.
inline constexpr std::size_t kMaxSnapshotPayloadBytes = kMaxMessageBytes - 64;
/// Most inputs one InputBatch may carry.
inline constexpr std::size_t kMaxInputsPerBatch = 64;
/// Longest player name (unit: bytes of UTF-8); longer names are refused.
inline constexpr std::size_t kMaxNameBytes = 32;
/// Longest refusal/goodbye reason (unit: bytes).
inline constexpr std::size_t kMaxReasonBytes = 256;
/// How every Goodbye to a connection whose Hello never arrived begins (then
/// the timeout): the server admitted nothing, so the client may join again.
inline constexpr const char* kNoHelloReason = "no hello within";
/// Most players a server hosts (slots are 0..kMaxSlots-1).
inline constexpr int kMaxSlots = 64;
/// Length of the reconnect token in Welcome/Hello (unit: bytes).
inline constexpr std::size_t kTokenBytes = 16;
/// Longest connect token in Hello (unit: bytes; its layout is checked by
/// jetrace::auth::parse_connect_token, not here).
inline constexpr std::size_t kMaxConnectTokenBytes = 256;
/// Largest track file a Welcome may announce (Welcome.track_bytes; unit:
/// bytes). A client's own cap (ClientConfig::max_track_bytes) may be lower.
inline constexpr std::uint32_t kMaxTrackBytes = 64u << 20;
/// Most track bytes one TrackChunk carries (unit: bytes): the server sends
/// exactly this many but in the last chunk.
inline constexpr std::size_t kTrackChunkBytes = 6144;
/// "No baseline": the snapshot is encoded against nothing.
inline constexpr std::uint32_t kNoTick = 0xFFFFFFFFu;
/// A Snapshot's baseline is less than this many ticks older than it: the
/// server keeps its snapshots of that many ticks, and a client keeps the
/// worlds it decoded for as long (docs/PROTOCOL.md, "Baseline").
inline constexpr std::size_t kBaselineWindowTicks = 128;

enum class RacePhase : std::uint8_t { lobby = 0, countdown = 1, racing = 2, finished = 3 };
const char* to_string(RacePhase p);

/// Client -> server, reliable, first message.
struct Hello {
    std::uint16_t protocol_version = kProtocolVersion;
    std::string name;
    /// Empty, or the token of an earlier Welcome to take back a car after a drop.
    std::vector<std::uint8_t> reconnect_token;
    /// Empty, or a signed connect token for a private race (at most
    /// kMaxConnectTokenBytes; docs/PROTOCOL.md, "Connect tokens").
    std::vector<std::uint8_t> connect_token;
    /// Join as an observer: no car and no slot, snapshots and results only
    /// (docs/PROTOCOL.md, "Observers").
    bool observe = false;
};

/// Server -> client, reliable: accepted.
struct Welcome {
    std::uint16_t protocol_version = kProtocolVersion;
    std::uint8_t slot = 0;
    std::uint8_t max_players = 0;
    std::uint16_t tick_rate_hz = 120;
    std::uint16_t snapshot_rate_hz = 60;
    std::string track_name;
    std::uint64_t track_identity = 0;
    /// physics_hash(PhysicsSettings) of the server: the client must match it.
    std::uint64_t physics_hash = 0;
    std::uint32_t server_tick = 0;
    std::vector<std::uint8_t> reconnect_token;  // kTokenBytes
    /// The server's physics settings (physics_hash(physics) == physics_hash
    /// from a server built with the same core; absent from older servers).
    std::optional<PhysicsSettings> physics;
    /// Welcomed as an observer: `slot` means nothing (sent as 0) and there
    /// is no reconnect token.
    bool observer = false;
    /// Size of the server's track as a compiled .jtrack file, which a client
    /// without the track downloads with TrackRequest (0: a built-in track;
    /// at most kMaxTrackBytes; unit: bytes).
    std::uint32_t track_bytes = 0;
};

/// Server -> client, reliable: not accepted (then disconnected).
struct Refuse {
    std::string reason;
    /// Why, as a number (a CloseCode in 2000-2999; 0 from older servers).
    std::uint16_t code = 0;
};

/// Client -> server, unreliable: the client's inputs for ticks first_tick,
/// first_tick+1, ... (every input not yet acknowledged: redundancy).
struct InputBatch {
    std::uint32_t first_tick = 0;
    std::vector<Input> inputs;
    /// Newest snapshot tick the client has received (kNoTick: none yet).
    std::uint32_t ack_snapshot_tick = kNoTick;
};

/// Server -> client, unreliable.
struct Snapshot {
    std::uint32_t server_tick = 0;
    /// The snapshot the payload is encoded against (kNoTick: none).
    std::uint32_t baseline_tick = kNoTick;
    /// Newest input tick of this client that the server has applied (kNoTick: none).
    std::uint32_t last_applied_input_tick = kNoTick;
    /// How many ticks ahead of the server tick this client's newest input
    /// arrived (negative: late). The client speeds up or slows down to keep
    /// it near its target.
    std::int16_t input_margin_ticks = 0;
    RacePhase phase = RacePhase::lobby;
    std::uint32_t race_number = 0;
    /// encode_world() bytes.
    std::vector<std::uint8_t> world;
};

struct PlayerInfo {
    std::uint8_t slot = 0;
    std::string name;
    /// Joined mid-race: watching until the next race.
    bool spectating = false;
};

/// Server -> client, reliable, whenever the race phase or the roster changes.
struct RaceStatus {
    RacePhase phase = RacePhase::lobby;
    std::uint32_t race_number = 0;
    std::uint32_t start_tick = 0;
    std::uint16_t laps = 1;
    std::vector<PlayerInfo> players;
};

struct StandingEntry {
    std::uint8_t slot = 0;
    std::string name;
    bool finished = false;
    std::uint16_t lap = 0;
    /// Race time at the finish (unit: s); 0 if not finished.
    double finish_time_s = 0;
};

/// Server -> client, reliable, at the end of each race.
struct Results {
    std::uint32_t race_number = 0;
    std::vector<StandingEntry> standings;
    std::uint64_t state_hash = 0;
};

/// Either direction, reliable: leaving, with a reason.
struct Goodbye {
    std::string reason;
    /// Why, as a number (a CloseCode; 0 from older peers).
    std::uint16_t code = 0;
};

/// Client -> server, unreliable: the newest snapshot the client decoded,
/// for a client that sends no inputs (an observer); a player's InputBatch
/// carries the same acknowledgement.
struct SnapshotAck {
    /// Newest snapshot tick the client has received (kNoTick: none yet).
    std::uint32_t ack_snapshot_tick = kNoTick;
};

/// Client -> server, reliable: asks for the server's track file from
/// `offset` (answered by one TrackChunk).
struct TrackRequest {
    /// Below Welcome.track_bytes (unit: bytes).
    std::uint32_t offset = 0;
};

/// Server -> client, reliable: the track file's bytes from `offset`.
struct TrackChunk {
    std::uint32_t offset = 0;
    /// 1..kTrackChunkBytes bytes (offset + size at most kMaxTrackBytes).
    std::vector<std::uint8_t> bytes;
};

using Message = std::variant<Hello, Welcome, Refuse, InputBatch, Snapshot, RaceStatus, Results, Goodbye, SnapshotAck,
                             TrackRequest, TrackChunk>;

/// Serialises a message. Asserts on programmer errors (fields out of range).
std::vector<std::uint8_t> encode(const Message& m);

/// Parses and verifies untrusted bytes. False with a reason on anything
/// malformed, truncated, oversized, too deeply nested or out of range.
bool decode(std::span<const std::uint8_t> bytes, Message& out, std::string& error);

/// The ticks an encoded InputBatch carries: `first` = first_tick, `last` =
/// first_tick + count − 1. False if `bytes` is not a valid InputBatch.
bool input_batch_ticks(std::span<const std::uint8_t> bytes, std::uint32_t& first, std::uint32_t& last);

/// True for valid UTF-8 without control characters: the rule every text
/// field of the protocol follows (see docs/PROTOCOL.md, "Validation").
bool valid_text(std::string_view text);

/// Hash of the settings that must match between server and client.
std::uint64_t physics_hash(const PhysicsSettings& s);

}  // namespace jetrace::proto
