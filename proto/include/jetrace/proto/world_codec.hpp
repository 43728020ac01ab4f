// The compact encoding of a world state inside a Snapshot: every car's state,
// bit for bit, delta-encoded against an older snapshot the client has
// acknowledged. Positions, velocities and orientations are already quantised
// by the core (2^-10 m, 2^-10 m/s, 2^-14), so the integers sent are exact.
#pragma once

#include "jetrace/core/hovercar.hpp"
#include "jetrace/core/world.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace jetrace::proto {

/// A world state plus, per slot, the input the server last applied to that
/// car (clients use it to predict the other cars).
struct WorldSnapshot {
    WorldState state;
    std::vector<Input> last_inputs;  // one per slot
    /// The server's PhysicsSettings::tick_rate_hz (1..10000). Positions are
    /// predicted from velocities over the ticks since the baseline, which
    /// needs the tick length. Sent in payloads without a baseline; a payload
    /// with a baseline uses (and decodes to) the baseline's value, so the
    /// server fills it in and clients never need to.
    std::uint16_t tick_rate_hz = 120;
    /// Per slot (or empty): the inputs the server already holds for ticks
    /// tick, tick+1, ... (at most kMaxUpcomingInputs, consecutive). A client
    /// replays the other cars with them instead of guessing, so with no loss
    /// its own prediction matches the server even in contact with them.
    std::vector<std::vector<Input>> upcoming;
};

/// Bits of a car's upcoming-input count in the world payload.
inline constexpr int kUpcomingCountBits = 4;
/// Most upcoming inputs a snapshot carries per car: 15, room for the inputs
/// of a client with an input delay (ClientConfig::input_delay_ticks) of up to
/// about 12 ticks on top of its margin.
inline constexpr std::size_t kMaxUpcomingInputs = (std::size_t{1} << kUpcomingCountBits) - 1;

/// Encodes `now` against `baseline` (nullptr: no baseline). Both must have
/// the same number of slots (<= kMaxSlots) and quantised states.
std::vector<std::uint8_t> encode_world(const WorldSnapshot& now, const WorldSnapshot* baseline);

/// Decodes untrusted bytes against the same baseline. False with a reason on
/// any malformed input; `out` is then unspecified.
bool decode_world(std::span<const std::uint8_t> bytes, const WorldSnapshot* baseline, WorldSnapshot& out,
                  std::string& error);

}  // namespace jetrace::proto
