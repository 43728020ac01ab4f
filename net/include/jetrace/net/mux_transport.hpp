// Two transports behind one: the server's ENet socket and its WebSocket
// listener (server/web) look like one Transport to RaceServer. The second
// transport numbers its peers from `second_base` up (the first stays below
// it), so a peer id says which transport it belongs to; events of both come
// out of one service() call, the first transport's first.
#pragma once

#include "jetrace/net/transport.hpp"

#include <memory>
#include <string>

namespace jetrace::net {

/// Takes both; `second_base` is the lowest peer id `second` hands out.
std::unique_ptr<Transport> combine(std::unique_ptr<Transport> first, std::unique_ptr<Transport> second,
                                   PeerId second_base);

/// Which transport of a combine() a peer belongs to: "enet" below the base
/// and "websocket" from it; "enet" for any other transport.
std::string transport_of(const Transport& transport, PeerId peer);

/// The totals of one part of a combine() (index 0 or 1); the transport's
/// own totals for index 0 of any other transport, zeros for index 1.
Totals part_totals(const Transport& transport, int index);

}  // namespace jetrace::net
