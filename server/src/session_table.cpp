// SessionTable: connections, slots, held slots and reconnect tokens.
#include "jetrace/server/session_table.hpp"

#include "jetrace/auth/connect_token.hpp"

#include <algorithm>
#include <cassert>
#include <utility>

namespace jetrace::server {

SessionTable::SessionTable(int max_players) : slot_peer_(static_cast<std::size_t>(max_players), kNoPeer) {}

Client& SessionTable::connect(net::PeerId peer, std::uint64_t now_us) {
    Client c;
    c.peer = peer;
    c.connected_us = now_us;
    clients_[peer] = c;
    return clients_[peer];
}

Client* SessionTable::find(net::PeerId peer) {
    const auto it = clients_.find(peer);
    return it != clients_.end() ? &it->second : nullptr;
}

Client SessionTable::take(net::PeerId peer) {
    const auto it = clients_.find(peer);
    assert(it != clients_.end());
    Client gone = std::move(it->second);
    clients_.erase(it);
    return gone;
}

int SessionTable::players() const {
    return static_cast<int>(std::count_if(clients_.begin(), clients_.end(),
                                          [](const auto& kv) { return kv.second.greeted && !kv.second.observer; }));
}

int SessionTable::observers() const {
    return static_cast<int>(std::count_if(clients_.begin(), clients_.end(),
                                          [](const auto& kv) { return kv.second.greeted && kv.second.observer; }));
}

std::vector<net::PeerId> SessionTable::player_peers() const {
    std::vector<net::PeerId> out;
    for (const auto& [peer, c] : clients_) {
        if (c.greeted && !c.observer) out.push_back(peer);
    }
    return out;
}

std::vector<net::PeerId> SessionTable::silent(std::uint64_t now_us, std::uint64_t timeout_us) const {
    std::vector<net::PeerId> out;
    for (const auto& [peer, c] : clients_) {
        if (!c.greeted && now_us - c.connected_us > timeout_us) out.push_back(peer);
    }
    return out;
}

int SessionTable::first_free_slot() const {
    for (std::size_t s = 0; s < slot_peer_.size(); ++s) {
        if (slot_peer_[s] == kNoPeer) return static_cast<int>(s);
    }
    return -1;
}

void SessionTable::seat(const Client& c) {
    assert(c.slot >= 0 && static_cast<std::size_t>(c.slot) < slot_peer_.size());
    slot_peer_[static_cast<std::size_t>(c.slot)] = c.peer;
}

void SessionTable::free_slot(int slot) { slot_peer_[static_cast<std::size_t>(slot)] = kNoPeer; }

const Client* SessionTable::owner_of(int slot) const {
    const net::PeerId peer = slot_peer_[static_cast<std::size_t>(slot)];
    if (peer == kHeldPeer) return &held_.at(slot).client;
    const auto it = clients_.find(peer);
    return it != clients_.end() ? &it->second : nullptr;
}

const Client* SessionTable::driver_of(std::size_t slot) const {
    const net::PeerId peer = slot_peer_[slot];
    if (peer == kNoPeer || peer == kHeldPeer) return nullptr;
    const auto it = clients_.find(peer);
    return it != clients_.end() ? &it->second : nullptr;
}

Client* SessionTable::driver_of(std::size_t slot) {
    return const_cast<Client*>(std::as_const(*this).driver_of(slot));
}

void SessionTable::hold(Client&& c, std::uint64_t until_us) {
    const int slot = c.slot;
    slot_peer_[static_cast<std::size_t>(slot)] = kHeldPeer;
    held_[slot] = HeldClient{std::move(c), until_us};
}

bool SessionTable::take_expired(std::uint64_t now_us, Client& out) {
    for (auto it = held_.begin(); it != held_.end(); ++it) {
        if (now_us < it->second.until_us) continue;
        out = std::move(it->second.client);
        held_.erase(it);
        return true;
    }
    return false;
}

SessionTable::TokenOwner SessionTable::owner_of_token(std::span<const std::uint8_t> token) {
    TokenOwner owner;
    for (auto& [slot, held] : held_) {
        if (auth::equal_secret(held.client.reconnect_token, token)) {
            owner.client = &held.client;
            owner.held_slot = slot;
        }
    }
    for (auto& [peer, other] : clients_) {
        if (!owner.client && other.greeted && !other.observer && auth::equal_secret(other.reconnect_token, token)) {
            owner.client = &other;
            owner.live_peer = peer;
        }
    }
    return owner;
}

Client SessionTable::take(const TokenOwner& owner) {
    assert(owner.client);
    Client back = std::move(*owner.client);
    if (owner.held_slot >= 0) held_.erase(owner.held_slot);
    if (owner.live_peer != kNoPeer) clients_.erase(owner.live_peer);  // its disconnect event finds nothing
    return back;
}

void SessionTable::retire(const ReconnectToken& token, std::string why) {
    if (retired_.size() >= kRetiredTokens) retired_.pop_front();
    retired_.emplace_back(token, std::move(why));
}

std::string SessionTable::retired_reason(std::span<const std::uint8_t> token) const {
    const auto spent = std::find_if(retired_.begin(), retired_.end(), [&](const auto& r) {
        return std::equal(r.first.begin(), r.first.end(), token.begin(), token.end());
    });
    return spent != retired_.end() ? spent->second : std::string();
}

}  // namespace jetrace::server
