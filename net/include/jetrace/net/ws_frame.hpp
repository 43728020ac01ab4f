// One protocol message in a WebSocket binary frame (docs/PROTOCOL.md,
// "WebSocket"): a channel byte (net::Channel: 0 unreliable, 1 reliable)
// then the message, which is never empty. Both ends read frames through
// read_ws_frame: the server's WebSocket transport (server/web) and the
// WebAssembly client's (client/web); fuzz/fuzz_ws_frame.cpp feeds it, and
// what it accepts, to the protocol's decoder.
#pragma once

#include "jetrace/net/transport.hpp"

#include <cstdint>
#include <span>
#include <string>

namespace jetrace::net {

/// The frame's channel and message; false (nothing set) if it is shorter
/// than two bytes or names no channel.
inline bool read_ws_frame(std::span<const std::uint8_t> frame, Channel& channel, std::span<const std::uint8_t>& message) {
    if (frame.size() < 2 || frame[0] >= kChannelCount) return false;
    channel = static_cast<Channel>(frame[0]);
    message = frame.subspan(1);
    return true;
}

/// The frame that carries `message` on `channel`.
inline std::string ws_frame(Channel channel, std::span<const std::uint8_t> message) {
    std::string out(message.size() + 1, '\0');
    out[0] = static_cast<char>(channel);
    for (std::size_t i = 0; i < message.size(); ++i) out[i + 1] = static_cast<char>(message[i]);
    return out;
}

}  // namespace jetrace::net
