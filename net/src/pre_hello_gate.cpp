#include "pre_hello_gate.hpp"

#include "jetrace/net/transport.hpp"

#include <spdlog/spdlog.h>

#include <array>
#include <cstring>

namespace jetrace::net::detail {
namespace {

// The peer id field of a datagram's ENet header (its flag and session bits cleared).
bool addressed_to_no_peer(const ENetHost& host) {
    if (host.receivedData == nullptr || host.receivedDataLength < sizeof(enet_uint16)) return false;
    enet_uint16 raw = 0;
    std::memcpy(&raw, host.receivedData, sizeof raw);
    const unsigned id = ENET_NET_TO_HOST_16(raw) & ~static_cast<unsigned>(ENET_PROTOCOL_HEADER_FLAG_MASK |
                                                                          ENET_PROTOCOL_HEADER_SESSION_MASK);
    return id == ENET_PROTOCOL_MAXIMUM_PEER_ID;
}

// States of a slot whose connection the server has not seen yet.
bool handshaking(ENetPeerState state) {
    return state == ENET_PEER_STATE_ACKNOWLEDGING_CONNECT || state == ENET_PEER_STATE_CONNECTION_PENDING ||
           state == ENET_PEER_STATE_CONNECTION_SUCCEEDED;
}

std::size_t slot_of(const ENetHost& host, const ENetPeer& peer) { return static_cast<std::size_t>(&peer - host.peers); }

}  // namespace

PreHelloGate::Verdict PreHelloGate::judge(const ENetHost& host, ConnectRequest& request) {
    if (cap_ == 0 || !addressed_to_no_peer(host)) return Verdict::pass;
    const enet_uint32 from = host.receivedAddress.host;
    const std::size_t pending = pending_from(host, from);
    if (pending < cap_) return Verdict::pass;
    const bool is_request = read_connect_request(host.receivedData, host.receivedDataLength, request);
    if (is_request && held(host, request)) return Verdict::pass;
    ++refused_;
    log_once(from, pending);
    return is_request ? Verdict::refuse : Verdict::drop;
}

bool PreHelloGate::held(const ENetHost& host, const ConnectRequest& request) {
    for (std::size_t i = 0; i < host.peerCount; ++i) {
        const ENetPeer& p = host.peers[i];
        if (p.state != ENET_PEER_STATE_DISCONNECTED && p.address.host == host.receivedAddress.host &&
            p.address.port == host.receivedAddress.port && p.connectID == request.connect_id) {
            return true;
        }
    }
    return false;
}

void PreHelloGate::admit(const ENetHost& host, const ENetPeer& peer) {
    const std::size_t i = slot_of(host, peer);
    if (i < admitted_.size()) admitted_[i] = true;
}

void PreHelloGate::forget(const ENetHost& host, const ENetPeer& peer) {
    const std::size_t i = slot_of(host, peer);
    if (i < admitted_.size()) admitted_[i] = false;
}

std::size_t PreHelloGate::pending_from(const ENetHost& host, enet_uint32 address) const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < host.peerCount && i < admitted_.size(); ++i) {
        const ENetPeer& p = host.peers[i];
        if (p.state == ENET_PEER_STATE_DISCONNECTED || p.address.host != address) continue;
        if (handshaking(p.state) || !admitted_[i]) ++n;
    }
    return n;
}

void PreHelloGate::log_once(enet_uint32 address, std::size_t pending) {
    if (logged_.size() > kMaxLoggedAddresses || logged_.count(address) > 0) return;
    if (logged_.size() == kMaxLoggedAddresses) {
        logged_.insert(address);  // one past the limit: says so once, then is full
        spdlog::warn("pre-Hello cap: {} addresses refused and logged; further ones are only counted",
                     kMaxLoggedAddresses);
        return;
    }
    logged_.insert(address);
    ENetAddress a{};
    a.host = address;
    std::array<char, 64> text{};
    if (enet_address_get_host_ip(&a, text.data(), text.size()) != 0) std::strcpy(text.data(), "?");
    spdlog::warn("pre-Hello cap: refusing connection requests from {}: it holds {} connections without a Hello "
                 "(cap {}); they are answered with close code {}; logged once per address, counted in "
                 "connects_refused",
                 text.data(), pending, cap_, kPreHelloRefusal);
}

}  // namespace jetrace::net::detail
