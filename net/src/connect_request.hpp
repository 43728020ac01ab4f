// ENet connection requests read from a received datagram (untrusted bytes),
// and the datagram that refuses one.
//
// ENet 1.3.17 facts relied on (protocol.h, protocol.c):
// - A datagram starts with a big-endian 16-bit header: the peer id in its
//   low 12 bits, a session in bits 12-13, COMPRESSED in bit 14 and SENT_TIME
//   in bit 15; a 16-bit sent time follows when SENT_TIME is set. Commands
//   follow, each starting with a 4-byte command header whose first byte
//   holds the command number in its low 4 bits.
// - A connection request is addressed to no peer (peer id 0xFFF) and its
//   command is CONNECT (sizeof(ENetProtocolConnect) = 48 bytes), whose
//   outgoingPeerID names the client's peer slot and whose connectID (kept
//   as sent, never byte-swapped) tells this attempt from the client's other
//   ones. ENet resends the request unchanged until it is answered.
// - A client peer still connecting takes a DISCONNECT command (8 bytes: the
//   command header and a 32-bit data) addressed to its slot from the
//   address it connects to, without a session check (it has none yet): the
//   attempt ends and the client's host reports ENET_EVENT_TYPE_DISCONNECT
//   with the command's data. (A peer past its handshake would first check
//   the answer's session bits, 0, against its session.)
#pragma once

#include <enet/enet.h>

#include <array>
#include <cstddef>
#include <cstdint>

namespace jetrace::net::detail {

struct ConnectRequest {
    /// The client's peer slot (CONNECT's outgoingPeerID), below 0xFFF.
    enet_uint16 client_peer = 0;
    /// The attempt's id as it travels (compared as is, like ENet does).
    enet_uint32 connect_id = 0;
};

/// Bytes of the answer refusing a connection request: a 2-byte header and
/// one DISCONNECT command (unit: bytes).
inline constexpr std::size_t kRefusalBytes = 2 + 8;

/// Whether `data` is a connection request, read into `out`: addressed to no
/// peer, not compressed, its first command a whole CONNECT naming a client
/// slot below 0xFFF. False for anything else (too short included).
bool read_connect_request(const enet_uint8* data, std::size_t size, ConnectRequest& out);

/// The datagram that ends the client's attempt `request` with `code` as its
/// disconnect data: smaller than any request it answers, so that answering
/// a forged source address sends less than the forger did.
std::array<enet_uint8, kRefusalBytes> refusal_datagram(const ConnectRequest& request, enet_uint32 code);

/// Sends refusal_datagram(request, code) on the host's socket to where the
/// datagram it just received came from (host.receivedAddress), counted in
/// the host's totals. A send that fails is as if lost: the client's ENet
/// resends its request.
void answer_request(ENetHost& host, const ConnectRequest& request, enet_uint32 code);

}  // namespace jetrace::net::detail
