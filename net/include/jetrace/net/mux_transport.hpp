// Two transports behind one: the server's ENet socket and its WebSocket
// listener (server/web) look like one Transport to RaceServer. The second
// transport numbers its peers from `second_base` up (the first stays below
// it), so a peer id says which transport it belongs to; events of both come
// out of one service() call, the first transport's first.
#pragma once

#include "jetrace/net/transport.hpp"

#include <memory>
#include <string>
#include <utility>

namespace jetrace::net {

/// Takes both; `second_base` is the lowest peer id `second` hands out, and
/// `second_name` names its peers' transport (metrics, /status). Combines
/// nest: combine(combine(enet, websocket, base1), webrtc, base2, "webrtc").
std::unique_ptr<Transport> combine(std::unique_ptr<Transport> first, std::unique_ptr<Transport> second,
                                   PeerId second_base, std::string second_name = "websocket");

/// Which transport of a (nested) combine() a peer belongs to: the name of
/// the second part holding it, else "enet"; "enet" for any other transport.
std::string transport_of(const Transport& transport, PeerId peer);

/// The totals of the part of a (nested) combine() named `name` ("enet" is
/// the innermost first part; the transport's own totals for "enet" of any
/// other transport, zeros for a name not there).
Totals part_totals(const Transport& transport, const std::string& name);

}  // namespace jetrace::net
