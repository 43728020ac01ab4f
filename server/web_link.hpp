// jetrace-server --web-link SPEC: jetrace-netsim's network conditions on
// browser players' links, applied inside the server (net::condition_link),
// and the input delay they cause, reported after each race. The WebSocket
// is one TCP stream (a loss holds back every later message until it is
// resent); the data channel carries datagrams (a lost input or snapshot is
// gone; its reliable channel resends). docs/PERFORMANCE.md, "Browser
// transports under loss".
#pragma once

#include "jetrace/net/link_conditions.hpp"
#include "jetrace/net/transport.hpp"

#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace jetrace::server {

/// The resend delay --web-link uses when SPEC names none: a lost segment
/// is resent when a later one has been acknowledged and a quarter of a
/// round trip has passed (TCP's RACK, SCTP's fast retransmit), so about
/// 1.25 round trips (2 × latency + jitter) after it was sent; at least
/// 20 ms (unit: ms).
double default_retransmit_ms(const net::Conditions& c);

/// Parses --web-link's SPEC ("latency=50,loss=0.05", the names of
/// net::condition_fields()); nullopt and `error` if it is wrong.
std::optional<net::Conditions> parse_web_link(std::string_view spec, std::string& error);

/// The conditioned browser transports and what they measured; it must
/// outlive the transports it wraps.
class WebLink {
public:
    explicit WebLink(const net::Conditions& conditions);

    /// Wraps the WebSocket transport (one stream) / the data channels' (datagrams).
    std::unique_ptr<net::Transport> wrap_websocket(std::unique_ptr<net::Transport> t);
    std::unique_ptr<net::Transport> wrap_webrtc(std::unique_ptr<net::Transport> t);

    /// One JSON line: each transport's input delay (ms: n, p50, p99, max)
    /// and its outgoing counters (dropped, retransmitted, delayed).
    std::string report() const;

private:
    net::LinkConditions link(net::Delivery delivery, std::uint64_t seed) const;

    net::Conditions conditions_;
    net::SequenceDelayMeter websocket_meter_;
    net::SequenceDelayMeter webrtc_meter_;
    const net::Transport* websocket_ = nullptr;
    const net::Transport* webrtc_ = nullptr;
};

}  // namespace jetrace::server
