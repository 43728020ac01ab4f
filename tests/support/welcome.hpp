// The Welcome a server sends a player joining a race on scene `sc`: the
// scripted client tests' first message.
#pragma once

#include "jetrace/core/world.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>

namespace jetrace::test {

inline proto::Welcome welcome_for(const Scene& sc, std::uint8_t slot) {
    proto::Welcome w;
    w.slot = slot;
    w.max_players = 8;
    w.tick_rate_hz = static_cast<std::uint16_t>(sc.physics.tick_rate_hz);
    w.track_name = "a track";
    w.track_identity = sc.track.identity();
    w.physics_hash = proto::physics_hash(sc.physics);
    w.reconnect_token.assign(proto::kTokenBytes, 7);
    return w;
}

}  // namespace jetrace::test
