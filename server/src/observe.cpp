// RaceServer: read-only views for metrics and status (counters, players).
#include "jetrace/net/mux_transport.hpp"
#include "jetrace/server/race_server.hpp"

#include <algorithm>

namespace jetrace::server {

RaceCounters RaceServer::counters() const { return counters_; }

std::vector<PlayerStatus> RaceServer::player_status() const {
    std::vector<PlayerStatus> out;
    const auto with_car = [&](const Client& c, bool connected, net::PeerId peer) {
        PlayerStatus p;
        p.transport = net::transport_of(transport_, peer);
        p.slot = c.slot;
        p.name = c.name;
        p.connected = connected;
        p.spectating = c.spectating;
        const auto s = static_cast<std::size_t>(c.slot);
        if (s < world_.cars.size() && world_.cars[s].active) {
            p.lap = world_.cars[s].lap;
            p.finished = world_.cars[s].finished;
        }
        out.push_back(std::move(p));
    };
    for (const auto& [peer, c] : sessions_.clients()) {
        if (c.greeted && c.slot >= 0) with_car(c, true, peer);
    }
    for (const auto& [slot, h] : sessions_.held()) with_car(h.client, false, h.client.peer);
    std::sort(out.begin(), out.end(), [](const PlayerStatus& a, const PlayerStatus& b) { return a.slot < b.slot; });
    return out;
}

}  // namespace jetrace::server
