#include "connect_request.hpp"

#include <cstddef>
#include <cstring>

namespace jetrace::net::detail {
namespace {

enet_uint16 read16(const enet_uint8* p) { return static_cast<enet_uint16>((p[0] << 8) | p[1]); }

void write16(enet_uint8* p, unsigned v) {
    p[0] = static_cast<enet_uint8>(v >> 8);
    p[1] = static_cast<enet_uint8>(v);
}

void write32(enet_uint8* p, enet_uint32 v) {
    write16(p, v >> 16);
    write16(p + 2, v & 0xFFFFu);
}

constexpr std::size_t kShortHeaderBytes = 2;  // the peer id field alone
constexpr std::size_t kConnectBytes = sizeof(ENetProtocolConnect);
static_assert(kConnectBytes == 48, "ENet's CONNECT command is 48 bytes");
static_assert(sizeof(ENetProtocolDisconnect) == kRefusalBytes - kShortHeaderBytes,
              "ENet's DISCONNECT command is 8 bytes");

}  // namespace

bool read_connect_request(const enet_uint8* data, std::size_t size, ConnectRequest& out) {
    if (data == nullptr || size < kShortHeaderBytes) return false;
    const unsigned field = read16(data);
    const unsigned flags = field & ENET_PROTOCOL_HEADER_FLAG_MASK;
    const unsigned peer =
        field & ~static_cast<unsigned>(ENET_PROTOCOL_HEADER_FLAG_MASK | ENET_PROTOCOL_HEADER_SESSION_MASK);
    if (peer != ENET_PROTOCOL_MAXIMUM_PEER_ID || (flags & ENET_PROTOCOL_HEADER_FLAG_COMPRESSED) != 0) return false;
    const std::size_t header = (flags & ENET_PROTOCOL_HEADER_FLAG_SENT_TIME) != 0 ? sizeof(ENetProtocolHeader)
                                                                                 : kShortHeaderBytes;
    if (size < header + kConnectBytes) return false;
    const enet_uint8* command = data + header;
    if ((command[0] & ENET_PROTOCOL_COMMAND_MASK) != ENET_PROTOCOL_COMMAND_CONNECT) return false;
    const enet_uint16 client_peer = read16(command + offsetof(ENetProtocolConnect, outgoingPeerID));
    if (client_peer >= ENET_PROTOCOL_MAXIMUM_PEER_ID) return false;
    out.client_peer = client_peer;
    std::memcpy(&out.connect_id, command + offsetof(ENetProtocolConnect, connectID), sizeof out.connect_id);
    return true;
}

std::array<enet_uint8, kRefusalBytes> refusal_datagram(const ConnectRequest& request, enet_uint32 code) {
    std::array<enet_uint8, kRefusalBytes> d{};
    write16(d.data(), request.client_peer);  // no flags, session 0
    enet_uint8* command = d.data() + kShortHeaderBytes;
    command[0] = ENET_PROTOCOL_COMMAND_DISCONNECT;  // unacknowledged: nothing to resend
    command[1] = 0xFF;                              // no channel, as ENet's own DISCONNECT
    write16(command + 2, 0);                        // reliable sequence number: unused
    write32(command + 4, code);
    return d;
}

void answer_request(ENetHost& host, const ConnectRequest& request, enet_uint32 code) {
    auto bytes = refusal_datagram(request, code);
    ENetBuffer buffer{};
    buffer.data = bytes.data();
    buffer.dataLength = bytes.size();
    const int sent = enet_socket_send(host.socket, &host.receivedAddress, &buffer, 1);
    if (sent <= 0) return;
    host.totalSentData += static_cast<enet_uint32>(sent);
    ++host.totalSentPackets;
}

}  // namespace jetrace::net::detail
