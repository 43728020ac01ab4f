// Why a connection ended, as a number on the wire (Refuse.code,
// Goodbye.code), in ranges after GameNetworkingSockets'
// ESteamNetConnectionEnd. Behaviour is decided on the code; the reason text
// next to it is for people. docs/PROTOCOL.md, "Close codes", is the table.
#pragma once

#include <cstdint>
#include <string_view>

namespace jetrace::proto {

enum class CloseCode : std::uint16_t {
    /// No code given (a peer of protocol version 3 or older).
    unspecified = 0,

    // 1000-1999: the connection ended normally.
    /// The player (or the client program) left.
    left = 1000,
    /// The server stops: its last race hosted, a shutdown or the end of a drain.
    server_shutdown = 1001,
    /// A reconnection of the same player took this connection's place.
    replaced = 1002,
    /// The lobby waited its timeout for enough players and cancelled the race.
    lobby_cancelled = 1003,

    // 3000-3999: never on the wire: why a client closed by itself.
    /// The program asked it to leave (RaceClient::leave).
    local_left = 3000,
    /// The server's track or physics is not one this client has.
    local_incompatible = 3001,
    /// No Welcome within the welcome timeout.
    local_no_welcome = 3002,
    /// The connection could not be made, or dropped and could not be made again.
    local_connection_lost = 3003,
    /// The server's track download was malformed, oversized, out of order,
    /// or not the track its Welcome named.
    local_bad_track = 3004,

    // 2000-2999: the server refused the Hello (the client may not just retry).
    refused_version = 2000,
    refused_token = 2001,
    refused_clock = 2002,
    refused_full = 2003,
    refused_reconnect = 2004,
    refused_draining = 2005,
    /// A fleet server that Agones has not allocated to a race yet.
    refused_unallocated = 2006,
    /// Every observer place is taken (--max-observers).
    refused_observers_full = 2007,
    /// The connection request itself: the client's IP address already holds
    /// the server's --pre-hello-limit connections waiting for their Hello.
    /// Not in a Refuse: the data of an ENet disconnect that answers the
    /// request (net::Event::close_code). Nothing was admitted: the client
    /// may try again once one of its address's connections is through.
    refused_pre_hello_cap = 2008,

    // 4000-4999: the peer broke the protocol or went quiet.
    /// No Hello within the hello timeout: nothing was admitted, the client
    /// may join again.
    no_hello = 4000,
    /// A message that does not decode.
    malformed = 4001,
    /// A message out of place (inputs before Hello, a second Hello, ...).
    protocol_violation = 4002,
    /// The server's send queue to this client overflowed: it reads too
    /// slowly (a WebSocket whose page stalled). Sent in the WebSocket close
    /// frame, no Goodbye.
    send_queue_full = 4003,
};

/// Ranges of CloseCode (a code this build does not know still falls in one).
enum class CloseClass : std::uint8_t { unspecified, normal, refused, local, remote_fault, other };

inline constexpr CloseClass close_class(std::uint16_t code) {
    if (code == 0) return CloseClass::unspecified;
    if (code >= 1000 && code < 2000) return CloseClass::normal;
    if (code >= 2000 && code < 3000) return CloseClass::refused;
    if (code >= 3000 && code < 4000) return CloseClass::local;
    if (code >= 4000 && code < 5000) return CloseClass::remote_fault;
    return CloseClass::other;
}

/// The code's name as in the table ("refused_full"), or "" for a code this
/// build does not know.
std::string_view close_code_name(std::uint16_t code);

}  // namespace jetrace::proto
