// One browser's session in the WebRTC transport: the offer's credentials
// until its STUN check binds an address, then its DataChannelSession.
#pragma once

#include "udp_socket.hpp"

#include "jetrace/net/transport.hpp"
#include "jetrace/webrtc/sdp.hpp"
#include "jetrace/webrtc/session.hpp"

#include <array>
#include <memory>
#include <optional>
#include <string>

namespace jetrace::rtc::detail {

struct RtcSession {
    net::PeerId peer = 0;
    std::string address;  ///< the POST's IP (the pending caps)
    webrtc::IceCredentials ice;
    webrtc::SdpOffer offer;
    /// Made by the first valid STUN check (which binds `remote`).
    std::unique_ptr<webrtc::DataChannelSession> channels;
    std::optional<Endpoint> remote;
    std::uint64_t created_ms = 0;
    std::uint64_t last_received_ms = 0;
    /// Both channels open: the server knows the peer.
    bool connected = false;
    /// disconnect(): closed (close_notify) at closing_ms + a grace period.
    bool closing = false;
    std::uint64_t closing_ms = 0;
    /// The stream of each net::Channel's data channel ("unreliable", "reliable").
    std::array<std::optional<std::uint16_t>, net::kChannelCount> streams;
};

}  // namespace jetrace::rtc::detail
