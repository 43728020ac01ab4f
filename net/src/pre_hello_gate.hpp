// The server's cap on connections one IP address holds before its Hello.
//
// Without it, one UDP socket that opens ENet connections and never says
// Hello (re-opening each as the server drops it after the hello timeout)
// holds every peer slot of the host, and nobody else can connect. The gate
// looks at every datagram before ENet does (ENetHost::intercept): a datagram
// addressed to no peer (header peer id ENET_PROTOCOL_MAXIMUM_PEER_ID) is a
// connection request, the only kind that makes ENet give out a slot; it is
// dropped when its source address already holds `cap` connections that the
// server has not admitted (handshakes in progress included). A well-formed
// request (connect_request.hpp) is also refused: the transport answers it
// with an ENet disconnect carrying kPreHelloRefusal, so the client's attempt
// ends at once with that close code instead of timing out as against a
// full server. The resend of a handshake the host already holds (the same
// address, port and connect id) goes through to ENet, which ignores it.
#pragma once

#include "connect_request.hpp"

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

    enum class Verdict : std::uint8_t {
        /// To ENet.
        pass,
        /// Dropped: addressed to no peer from an address at its cap, but no
        /// connection request to answer.
        drop,
        /// A connection request from an address at its cap: dropped, and
        /// `request` says whom to answer.
        refuse,
    };

    /// What to do with the datagram ENet just received (host.receivedData
    /// from host.receivedAddress); counts and logs what it drops.
    Verdict judge(const ENetHost& host, ConnectRequest& request);

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
    /// A resend of a handshake the host holds (same address, port, connect id).
    static bool held(const ENetHost& host, const ConnectRequest& request);
    void log_once(enet_uint32 address, std::size_t pending);

    std::size_t cap_;
    std::vector<bool> admitted_;
    std::unordered_set<enet_uint32> logged_;
    std::uint64_t refused_ = 0;
};

}  // namespace jetrace::net::detail
