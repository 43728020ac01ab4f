// The server's cap on connections one IP address holds before its Hello.
//
// Without it, one UDP socket that opens ENet connections and never says
// Hello (re-opening each as the server drops it after the hello timeout)
// holds every peer slot of the host, and nobody else can connect. The gate
// looks at every datagram before ENet does (ENetHost::intercept): a datagram
// addressed to no peer (header peer id ENET_PROTOCOL_MAXIMUM_PEER_ID) is a
// connection request, the only kind that makes ENet give out a slot; it is
// dropped when its source address already holds `cap` connections that the
// server has not admitted (handshakes in progress included). A dropped
// request looks to the client like a lost datagram: its ENet retries it
// (0.5, 1.5, 3.5 s after the first try) and times out after that, as
// against a full server.
#pragma once

#include <enet/enet.h>

#include <cstddef>
#include <cstdint>
#include <unordered_set>
#include <vector>

namespace jetrace::net::detail {

class PreHelloGate {
public:
    /// cap 0: the gate lets everything through.
    explicit PreHelloGate(std::size_t cap) : cap_(cap) {}

    /// The host's peer slots (call once, before the first datagram).
    void attach(const ENetHost& host) { admitted_.assign(host.peerCount, false); }

    /// Whether to drop the datagram ENet just received (host.receivedData
    /// from host.receivedAddress); counts and logs what it drops.
    bool refuse(const ENetHost& host);

    /// The server accepted the peer's Hello.
    void admit(const ENetHost& host, const ENetPeer& peer);
    /// The slot starts a new connection, or its connection ended.
    void forget(const ENetHost& host, const ENetPeer& peer);

    /// Requests dropped so far (unit: datagrams).
    std::uint64_t refused() const { return refused_; }

private:
    // Distinct addresses logged; past it, refusals are only counted.
    static constexpr std::size_t kMaxLoggedAddresses = 4096;

    std::size_t pending_from(const ENetHost& host, enet_uint32 address) const;
    void log_once(enet_uint32 address, std::size_t pending);

    std::size_t cap_;
    std::vector<bool> admitted_;
    std::unordered_set<enet_uint32> logged_;
    std::uint64_t refused_ = 0;
};

}  // namespace jetrace::net::detail
