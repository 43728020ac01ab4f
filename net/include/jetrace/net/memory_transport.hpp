// An in-memory network: one server end and any number of client ends in one
// process, no sockets, no threads, no wall clock (benchmarks and tests that
// must repeat bit for bit). Every end is a net::Transport and behaves as the
// ENet one does towards RaceServer and RaceClient:
//
// - A client end from connect() reaches the server end, which reports
//   `connected` with a new PeerId (1, 2, ... as listen_enet's); then the
//   client end reports `connected` for peer 0 and may send. Beyond
//   MemoryHubConfig::max_connections, or with no server end, the client
//   end reports `disconnected` instead.
// - Datagrams of one connection arrive in the order they were sent, each
//   exactly once, on either channel (nothing is lost: both channels behave
//   as the reliable one). Across connections, the server end receives in
//   the order the clients sent.
// - disconnect(peer) is graceful: what was sent before it arrives first;
//   the other end then reports `disconnected`, and the end that
//   disconnected does once the other end has seen it. Data arriving at an
//   end that already disconnected is discarded. A destroyed end disconnects
//   all its connections the same way.
//
// Time is the caller's: the hub's clock is the largest now_ms given to any
// end's service(); a datagram (or connect, or disconnect) sent at hub time T
// is handed out by the first service() of the receiving end at or after
// T + latency_ms. send() queues for the other end at once, so flush() has
// nothing to do. Totals count payload bytes (no transport headers) and
// datagrams: sent when send() accepts them, received when service() hands
// them out. The hub and its ends are for one thread.
#pragma once

#include "jetrace/net/transport.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>

namespace jetrace::net {

struct MemoryHubConfig {
    /// Most connections the server end holds at once; a connect beyond them
    /// is refused (unit: connections).
    std::size_t max_connections = 72;
    /// One-way delay of every datagram, connect and disconnect on the hub's
    /// clock (unit: ms). peer_stats() reports twice it as the round trip.
    std::uint32_t latency_ms = 0;
};

namespace detail {
struct MemoryNetwork;
}

class MemoryHub {
public:
    explicit MemoryHub(const MemoryHubConfig& config = {});
    ~MemoryHub();
    MemoryHub(const MemoryHub&) = delete;
    MemoryHub& operator=(const MemoryHub&) = delete;

    /// The server end; nullptr while another one of this hub exists. Its
    /// ends may outlive the hub.
    std::unique_ptr<Transport> listen();
    /// A new client end, connecting to the server end (peer 0, as
    /// connect_enet's).
    std::unique_ptr<Transport> connect();

private:
    std::shared_ptr<detail::MemoryNetwork> net_;
};

}  // namespace jetrace::net
