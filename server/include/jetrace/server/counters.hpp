// What RaceServer counts, for metrics: plain integers, incremented where the
// server decides (a refusal, a late input, a race's end), read through
// RaceServer::counters(). No clocks, no I/O, no threads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace jetrace::server {

/// Why a Hello was refused (a bounded set: metric labels).
enum class Refusal : std::uint8_t {
    /// The client speaks another protocol version.
    version,
    /// A private race's connect token was missing, invalid, expired or spent.
    token,
    /// The server clock was never set, so no connect token can be checked.
    clock,
    /// Every slot is taken.
    full,
    /// An unknown or spent reconnect token, or one of another player's name.
    reconnect,
    /// The server is draining: it finishes the race under way and takes no one new.
    draining,
    /// Every observer place is taken.
    observers_full,
    count,
};
inline constexpr std::array<std::string_view, static_cast<std::size_t>(Refusal::count)> kRefusalNames{
    "version", "token", "clock", "full", "reconnect", "draining", "observers_full"};

/// Why a connection was dropped by the server (a bounded set: metric labels).
enum class DropReason : std::uint8_t {
    /// No Hello within the hello timeout.
    no_hello,
    /// A message that does not decode.
    malformed,
    /// A message out of place (inputs before Hello, a second Hello, ...).
    protocol,
    count,
};
inline constexpr std::array<std::string_view, static_cast<std::size_t>(DropReason::count)> kDropReasonNames{
    "no_hello", "malformed", "protocol"};

struct RaceCounters {
    /// Races whose countdown began (unit: races).
    std::uint64_t races_started = 0;
    /// Races that ended by the rules: all finished, the finish window or the
    /// time limit (unit: races).
    std::uint64_t races_finished = 0;
    /// Races stopped by shutdown() or left by every player (unit: races).
    std::uint64_t races_aborted = 0;
    /// Inputs that arrived after their tick was stepped without them (unit: inputs).
    std::uint64_t inputs_late = 0;
    /// Inputs dropped for being too far ahead of the server tick (unit: inputs).
    std::uint64_t inputs_dropped = 0;
    /// Ticks a car was stepped with its previous input because the one for
    /// the tick had not arrived (unit: car-ticks).
    std::uint64_t inputs_missing = 0;
    /// Hellos refused, by reason (unit: connections).
    std::array<std::uint64_t, static_cast<std::size_t>(Refusal::count)> refused{};
    /// Connections dropped by the server, by reason (unit: connections).
    std::array<std::uint64_t, static_cast<std::size_t>(DropReason::count)> dropped{};
};

/// One player of RaceServer::player_status().
struct PlayerStatus {
    int slot = -1;
    std::string name;
    /// Connected (false: dropped, its slot held for a reconnect).
    bool connected = true;
    /// Joined during a race: no car until the next one.
    bool spectating = false;
    /// The car's lap (0 before it first crosses the start line) and finish.
    int lap = 0;
    bool finished = false;
    /// The transport of its connection: "enet" or "websocket"
    /// (net::transport_of; a held slot keeps its last one).
    std::string transport = "enet";
};

}  // namespace jetrace::server
