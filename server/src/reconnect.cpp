// RaceServer: players leaving, and coming back with their reconnect token
// (docs/PROTOCOL.md, "Reconnecting").
#include "jetrace/server/race_server.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::server {

void RaceServer::release(Client&& c, bool may_return, std::string why) {
    if (c.slot < 0) return;
    if (shutting_down_) {
        // No race any more: nothing to hold, remove or tell the others.
        sessions_.retire(c.reconnect_token, std::move(why));
        sessions_.free_slot(c.slot);
        return;
    }
    const auto s = static_cast<std::size_t>(c.slot);
    if (may_return && config_.reconnect_grace_s > 0) {
        // Its car stays in the race (neutral inputs) and the slot stays
        // taken: only its reconnect token gets them back.
        spdlog::info("'{}' (slot {}) dropped: slot{} held {:.1f} s for a reconnect", c.name, c.slot,
                     world_.cars[s].active ? " and car" : "", config_.reconnect_grace_s);
        sessions_.hold(std::move(c), now_us_ + static_cast<std::uint64_t>(config_.reconnect_grace_s * 1e6));
        return;
    }
    sessions_.retire(c.reconnect_token, std::move(why));
    sessions_.free_slot(c.slot);
    if (world_.cars[s].active) {
        remove_car(world_, c.slot);  // the race goes on without it
        pending_removals_.push_back(static_cast<std::uint8_t>(c.slot));
    }
    broadcast_status();
}

void RaceServer::expire_held() {
    Client c;
    while (sessions_.take_expired(now_us_, c)) {
        spdlog::info("'{}' (slot {}) did not come back within {:.1f} s: slot freed", c.name, c.slot,
                     config_.reconnect_grace_s);
        release(std::move(c), false, "reconnect token expired: the grace period is over");
    }
}

void RaceServer::on_reconnect(Client& c, const proto::Hello& h) {
    // The token may belong to a held slot, or to a live connection the
    // server has not yet seen drop (the client noticed first): that one is
    // replaced.
    const SessionTable::TokenOwner owner = sessions_.owner_of_token(h.reconnect_token);
    if (!owner.client) {
        const std::string spent = sessions_.retired_reason(h.reconnect_token);
        refuse(c, h.name, Refusal::reconnect, spent.empty() ? "unknown reconnect token" : spent);
        return;
    }
    // The token is the credential, the name a cross-check: a mismatch is
    // refused and leaves the token valid for its owner.
    if (owner.client->hello_name != h.name) {
        refuse(c, h.name, Refusal::reconnect, "reconnect token belongs to another player name");
        return;
    }
    Client back = sessions_.take(owner);
    if (const net::PeerId replaced = owner.live_peer; replaced != SessionTable::kNoPeer) {
        spdlog::info("'{}' (slot {}) reconnected from a new connection: closing the old one", back.name, back.slot);
        send(replaced, net::Channel::reliable, proto::Goodbye{"replaced by a reconnection of the same player",
                                                      static_cast<std::uint16_t>(proto::CloseCode::replaced)});
        transport_.disconnect(replaced);
    }
    sessions_.retire(back.reconnect_token, "reconnect token already used");
    // The new connection starts from scratch: no inputs, no acknowledged
    // snapshot (the client forgot its own).
    back.peer = c.peer;
    back.connected_us = c.connected_us;
    back.reset_link_state();
    const auto s = static_cast<std::size_t>(back.slot);
    back.spectating = !world_.cars[s].active && phase_ != proto::RacePhase::lobby;
    c = std::move(back);
    sessions_.seat(c);
    spdlog::info("client {} is '{}' again in slot {}{}", c.peer, c.name, c.slot,
                 world_.cars[s].active ? ", car kept" : "");
    send_welcome(c);
    broadcast_status();
}

}  // namespace jetrace::server
