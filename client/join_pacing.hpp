// jetrace-bot's pacing of joins. A server refuses the connection requests
// of an IP address that already holds --pre-hello-limit connections waiting
// for their Hello (docs/PROTOCOL.md, "Connection slots and the pre-Hello
// cap"), and every bot of one process comes from one address; so the bots
// of one server address open their connections at most `limit` at a time,
// the next once an earlier one has its Welcome (or has given up).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace jetrace::bot {

enum class JoinPhase : std::uint8_t {
    /// No connection opened yet.
    waiting,
    /// Connecting, or connected without its Welcome yet (joining again and
    /// reconnecting included).
    joining,
    /// Welcomed (in the lobby or racing), or done.
    through,
};

/// The waiting bots that may open their connection now, in index order: as
/// many per server address (`address[i]` of bot i, below `addresses`) as
/// keep that address's joining bots at most `limit` (unit: bots).
std::vector<std::size_t> bots_to_start(const std::vector<JoinPhase>& phase, const std::vector<std::size_t>& address,
                                       std::size_t addresses, int limit);

}  // namespace jetrace::bot
