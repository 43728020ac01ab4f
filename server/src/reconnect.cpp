// RaceServer: players leaving, and coming back with their reconnect token
// (docs/PROTOCOL.md, "Reconnecting").
#include "jetrace/server/race_server.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::server {

const RaceServer::Client* RaceServer::owner_of(int slot) const {
    const net::PeerId peer = slot_peer_[static_cast<std::size_t>(slot)];
    if (peer == kHeldPeer) return &held_.at(slot).client;
    const auto it = clients_.find(peer);
    return it != clients_.end() ? &it->second : nullptr;
}

void RaceServer::retire(const ReconnectToken& token, std::string why) {
    if (retired_.size() >= kRetiredTokens) retired_.pop_front();
    retired_.emplace_back(token, std::move(why));
}

void RaceServer::release(Client&& c, bool may_return, std::string why) {
    if (c.slot < 0) return;
    const auto s = static_cast<std::size_t>(c.slot);
    if (may_return && config_.reconnect_grace_s > 0 && !done_) {
        // Its car stays in the race (neutral inputs) and the slot stays
        // taken: only its reconnect token gets them back.
        spdlog::info("'{}' (slot {}) dropped: slot{} held {:.1f} s for a reconnect", c.name, c.slot,
                     world_.cars[s].active ? " and car" : "", config_.reconnect_grace_s);
        slot_peer_[s] = kHeldPeer;
        const int slot = c.slot;
        held_[slot] = Held{std::move(c), now_us_ + static_cast<std::uint64_t>(config_.reconnect_grace_s * 1e6)};
        return;
    }
    retire(c.reconnect_token, std::move(why));
    slot_peer_[s] = kNoPeer;
    if (world_.cars[s].active) {
        remove_car(world_, c.slot);  // the race goes on without it
        pending_removals_.push_back(static_cast<std::uint8_t>(c.slot));
    }
    broadcast_status();
}

void RaceServer::expire_held() {
    for (auto it = held_.begin(); it != held_.end();) {
        if (now_us_ < it->second.until_us) {
            ++it;
            continue;
        }
        Client c = std::move(it->second.client);
        it = held_.erase(it);
        spdlog::info("'{}' (slot {}) did not come back within {:.1f} s: slot freed", c.name, c.slot,
                     config_.reconnect_grace_s);
        release(std::move(c), false, "reconnect token expired: the grace period is over");
    }
}

void RaceServer::on_reconnect(Client& c, const proto::Hello& h) {
    // The token may belong to a held slot, or to a live connection the
    // server has not yet seen drop (the client noticed first): that one is
    // replaced.
    Client* owner = nullptr;
    int held_slot = -1;
    for (auto& [slot, held] : held_) {
        if (auth::equal_secret(held.client.reconnect_token, h.reconnect_token)) {
            owner = &held.client;
            held_slot = slot;
        }
    }
    net::PeerId replaced = kNoPeer;
    for (auto& [peer, other] : clients_) {
        if (!owner && other.greeted && auth::equal_secret(other.reconnect_token, h.reconnect_token)) {
            owner = &other;
            replaced = peer;
        }
    }
    if (!owner) {
        const auto spent = std::find_if(retired_.begin(), retired_.end(), [&](const auto& r) {
            return std::equal(r.first.begin(), r.first.end(), h.reconnect_token.begin(), h.reconnect_token.end());
        });
        refuse(c, h.name, Refusal::reconnect, spent != retired_.end() ? spent->second : "unknown reconnect token");
        return;
    }
    // The token is the credential, the name a cross-check: a mismatch is
    // refused and leaves the token valid for its owner.
    if (owner->hello_name != h.name) {
        refuse(c, h.name, Refusal::reconnect, "reconnect token belongs to another player name");
        return;
    }
    Client back = std::move(*owner);
    if (held_slot >= 0) held_.erase(held_slot);
    if (replaced != kNoPeer) {
        spdlog::info("'{}' (slot {}) reconnected from a new connection: closing the old one", back.name, back.slot);
        send(replaced, net::Channel::reliable, proto::Goodbye{"replaced by a reconnection of the same player",
                                                      static_cast<std::uint16_t>(proto::CloseCode::replaced)});
        transport_.disconnect(replaced);
        clients_.erase(replaced);  // its disconnect event finds nothing
    }
    retire(back.reconnect_token, "reconnect token already used");
    // The new connection starts from scratch: no inputs, no acknowledged
    // snapshot (the client forgot its own).
    back.peer = c.peer;
    back.connected_us = c.connected_us;
    back.reset_link_state();
    const auto s = static_cast<std::size_t>(back.slot);
    back.spectating = !world_.cars[s].active && phase_ != proto::RacePhase::lobby;
    slot_peer_[s] = c.peer;
    c = std::move(back);
    spdlog::info("client {} is '{}' again in slot {}{}", c.peer, c.name, c.slot,
                 world_.cars[s].active ? ", car kept" : "");
    send_welcome(c);
    broadcast_status();
}

}  // namespace jetrace::server
