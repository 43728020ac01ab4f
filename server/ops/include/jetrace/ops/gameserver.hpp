// The parts of an Agones GameServer that jetrace reads, and the race options
// an allocation carries in its annotations. Pure functions: no I/O.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace jetrace::ops {

/// What jetrace reads from a GameServer resource as the SDK sidecar sends it.
struct GameServerView {
    /// status.state: "Scheduled", "Ready", "Allocated", "Shutdown", ... ("" if absent).
    std::string state;
    /// object_meta.annotations (entries whose value is not a string are skipped).
    std::map<std::string, std::string> annotations;
};

/// Parses one line of `GET /watch/gameserver` ({"result": GameServer}) or
/// the body of `GET /gameserver` (a GameServer). Untrusted input: never
/// throws; nullopt for anything that is not a JSON object with a GameServer
/// (an {"error": ...} line, garbage, a truncated line). Missing fields read
/// as empty.
std::optional<GameServerView> parse_gameserver(std::string_view json);

/// The annotation keys jetrace reads (set by a GameServerAllocation's
/// metadata.annotations). Any other key under "jetrace.dev/" is an error.
inline constexpr std::string_view kAnnotationPrefix = "jetrace.dev/";
inline constexpr std::string_view kTrackAnnotation = "jetrace.dev/track";
inline constexpr std::string_view kLapsAnnotation = "jetrace.dev/laps";
inline constexpr std::string_view kMinPlayersAnnotation = "jetrace.dev/min-players";
inline constexpr std::string_view kRaceIdAnnotation = "jetrace.dev/race-id";

/// Race options from an allocation; unset ones keep the command line's.
struct AllocationOptions {
    std::optional<std::string> track;
    std::optional<int> laps;
    std::optional<int> min_players;
    std::optional<std::string> race_id;
};

/// Reads the jetrace.dev/ annotations. False and `error` (naming the key and
/// value) for a value that is not valid: laps an integer in [1, 1000],
/// min-players an integer in [1, 64], track and race-id non-empty and at
/// most 64 bytes, or an unknown jetrace.dev/ key.
bool parse_allocation(const std::map<std::string, std::string>& annotations, AllocationOptions& out,
                      std::string& error);

}  // namespace jetrace::ops
