// The network edge. Everything above it (server, client) talks to this small
// interface, so tests can replace or degrade it. The caller owns time: it
// passes its clock to service(); the ENet implementation additionally reads
// the wall clock inside enet_host_service, which is why it stays here.
#pragma once

#include "jetrace/net/scheduler.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace jetrace::net {

using PeerId = std::uint32_t;

enum class Channel : std::uint8_t {
    /// Unsequenced-unreliable datagrams (inputs, snapshots).
    unreliable = 0,
    /// Reliable, ordered (handshake, race status, results, goodbye).
    reliable = 1,
};
inline constexpr int kChannelCount = 2;

struct Event {
    enum class Type : std::uint8_t { connected, disconnected, received };
    Type type = Type::received;
    PeerId peer = 0;
    Channel channel = Channel::unreliable;
    std::vector<std::uint8_t> data;
    /// disconnected: the number the peer's disconnect carried (ENet's
    /// disconnect data), such as kPreHelloRefusal; 0: none (a plain close,
    /// a timeout, a connection attempt nobody answered) or a value over
    /// 0xFFFF.
    std::uint16_t close_code = 0;
};

/// The close code a server's pre-Hello cap answers a connection request
/// with (ServerConfig::max_pending_per_address): proto::CloseCode::
/// refused_pre_hello_cap, which the client sees as the close_code of its
/// `disconnected` event.
inline constexpr std::uint16_t kPreHelloRefusal = 2008;

struct PeerStats {
    /// Smoothed round-trip time (unit: ms).
    double rtt_ms = 0;
    /// Its variance estimate (unit: ms).
    double rtt_variance_ms = 0;
};

struct Totals {
    /// Bytes handed to the socket / read from it, transport headers included (unit: bytes).
    std::uint64_t bytes_sent = 0;
    std::uint64_t bytes_received = 0;
    std::uint64_t packets_sent = 0;
    std::uint64_t packets_received = 0;
    /// Connection requests (datagrams addressed to no peer, a client's
    /// retries included) dropped because their IP address already held
    /// ServerConfig::max_pending_per_address connections without a Hello.
    std::uint64_t connects_refused = 0;
};

class Transport {
public:
    virtual ~Transport() = default;
    /// Sends what is queued and appends what happened since the last call to
    /// `events` (connects, disconnects, datagrams). Never blocks.
    virtual void service(std::uint64_t now_ms, std::vector<Event>& events) = 0;
    /// Queues a datagram. False if the peer is unknown or the data too large.
    virtual bool send(PeerId peer, Channel channel, std::span<const std::uint8_t> data) = 0;
    /// Graceful disconnect (queued reliable data goes first where possible).
    virtual void disconnect(PeerId peer) = 0;
    /// The server accepted this peer's Hello: it no longer counts against
    /// its address's cap of connections without one
    /// (ServerConfig::max_pending_per_address). Transports without that cap
    /// have nothing to do; decorators pass it on.
    virtual void admit(PeerId /*peer*/) {}
    /// Pushes queued datagrams to the socket now.
    virtual void flush() = 0;
    virtual PeerStats peer_stats(PeerId peer) const = 0;
    virtual Totals totals() const = 0;
    /// The UDP port this end is bound to.
    virtual std::uint16_t local_port() const = 0;
};

struct ServerConfig {
    /// Address to bind ("0.0.0.0" = all, "127.0.0.1" = loopback only).
    std::string bind = "0.0.0.0";
    /// UDP port; 0 lets the system choose (see local_port()).
    std::uint16_t port = 0;
    /// Most simultaneous connections (ENet peer slots).
    std::size_t max_connections = 72;
    /// A peer that stops answering is dropped after this long (unit: ms).
    std::uint32_t timeout_ms = 5000;
    /// Most connections one IP address may hold before the server admits
    /// them (Transport::admit, on a Hello it accepts), handshakes in progress
    /// included; a connection request beyond it gets no slot: it is answered
    /// with an ENet disconnect carrying kPreHelloRefusal (a datagram smaller
    /// than the request), so the client's attempt ends at once with that
    /// close_code. 0: no cap (unit: connections).
    std::size_t max_pending_per_address = 0;
};

/// A listening ENet host; nullptr and `error` if it cannot bind.
std::unique_ptr<Transport> listen_enet(const ServerConfig& config, std::string& error);

/// An ENet client connecting to host:port; the connect completes
/// asynchronously with a `connected` event for peer 0 (or `disconnected`).
std::unique_ptr<Transport> connect_enet(const std::string& host, std::uint16_t port, std::uint32_t timeout_ms,
                                        std::string& error);

/// Wraps `inner`: outgoing datagrams go through a DatagramScheduler (one flow
/// per peer) on the caller's clock given to service(): they wait latency +
/// jitter and for the peer's link (`rate_kbps`); unreliable ones may also be
/// dropped, duplicated or reordered. Reliable ones keep their order and are
/// never dropped (the reliability layer is below this decorator).
std::unique_ptr<Transport> condition(std::unique_ptr<Transport> inner, const Conditions& conditions);

/// What a conditioner did so far (counts of datagrams).
using ConditionerStats = SchedulerStats;

/// The counters of a transport made by condition(); zeros for any other.
ConditionerStats conditioner_stats(const Transport& transport);

}  // namespace jetrace::net
