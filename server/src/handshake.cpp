// RaceServer: the handshake: a Hello checked and answered with a Welcome
// (a player's slot, or an observer's place) or a Refuse.
#include "jetrace/server/race_server.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::server {

void RaceServer::on_hello(Client& c, const proto::Hello& h) {
    if (c.greeted) {
        drop(c.peer, DropReason::protocol, "protocol violation: second hello");
        return;
    }
    if (h.protocol_version != proto::kProtocolVersion) {
        refuse(c, h.name, Refusal::version, "protocol version " + std::to_string(h.protocol_version) + " not supported (server speaks " +
                      std::to_string(proto::kProtocolVersion) + ")");
        return;
    }
    if (!h.reconnect_token.empty() && !h.observe) {
        on_reconnect(c, h);
        return;
    }
    if (draining_) {
        refuse(c, h.name, Refusal::draining, "server draining: it finishes the race under way and accepts no new players");
        return;
    }
    std::optional<auth::ConnectToken> ticket;
    if (!check_connect_token(c, h, ticket)) return;
    const int slot = h.observe ? -1 : sessions_.first_free_slot();
    if (h.observe && sessions_.observers() >= config_.max_observers) {
        refuse(c, h.name, Refusal::observers_full,
               "no room for another observer (" + std::to_string(config_.max_observers) + " observers)");
        return;
    }
    if (!h.observe && slot < 0) {
        refuse(c, h.name, Refusal::full, "server full (" + std::to_string(config_.max_players) + " players)");
        return;
    }
    if (ticket) {
        verifier_->admit(*ticket);  // spent only once it got the player in
        if (on_nonce_spent) on_nonce_spent(*verifier_);
    }
    if (h.observe) return welcome_observer(c, h);
    c.greeted = true;
    c.hello_name = h.name;
    c.name = h.name.empty() ? "player" + std::to_string(slot) : h.name;
    c.slot = slot;
    c.spectating = phase_ != proto::RacePhase::lobby;
    sessions_.seat(c);
    max_players_seen_ = std::max(max_players_seen_, players());
    spdlog::info("client {} is '{}' in slot {}{}", c.peer, c.name, slot, c.spectating ? " (spectating until the next race)" : "");
    send_welcome(c);
    broadcast_status();
}

bool RaceServer::check_connect_token(Client& c, const proto::Hello& h, std::optional<auth::ConnectToken>& ticket) {
    if (!verifier_) return true;
    if (unix_time_s_ < 0) {
        spdlog::error("private race: the caller never set the wall clock, so no connect token can be checked");
        refuse(c, h.name, Refusal::clock, "server clock not set: cannot check connect tokens");
        return false;
    }
    auth::Verdict v = verifier_->check(h.connect_token, h.name, unix_time_s_);
    if (!v.ok()) {
        refuse(c, h.name, Refusal::token, v.refusal);
        return false;
    }
    ticket = std::move(v.token);
    return true;
}

void RaceServer::welcome_observer(Client& c, const proto::Hello& h) {
    // No slot, no car, not in the roster: the race goes exactly as without it.
    c.greeted = true;
    c.observer = true;
    c.hello_name = h.name;
    c.name = h.name.empty() ? "observer" : h.name;
    spdlog::info("client {} is '{}', observing ({} of at most {} observers)", c.peer, c.name, sessions_.observers(),
                 config_.max_observers);
    send_welcome(c);
    send(c.peer, net::Channel::reliable, status());
}

void RaceServer::send_welcome(Client& c) {
    // Past its Hello: the connection no longer counts against its address's
    // pre-Hello cap (net::ServerConfig::max_pending_per_address).
    transport_.admit(c.peer);
    // A fresh secret for every Welcome: the one a reconnect used is spent.
    // An observer has none: it holds nothing to come back to.
    if (!c.observer) auth::random_bytes(c.reconnect_token);
    proto::Welcome w;
    w.slot = static_cast<std::uint8_t>(c.observer ? 0 : c.slot);
    w.observer = c.observer;
    w.max_players = static_cast<std::uint8_t>(config_.max_players);
    w.tick_rate_hz = static_cast<std::uint16_t>(scene_.physics.tick_rate_hz);
    w.snapshot_rate_hz = static_cast<std::uint16_t>(config_.snapshot_rate_hz);
    w.track_name = scene_.track.name;
    w.track_identity = scene_.track.identity();
    w.physics_hash = proto::physics_hash(scene_.physics);
    w.physics = scene_.physics;
    w.server_tick = world_.tick;
    w.track_bytes = static_cast<std::uint32_t>(track_file_.size());
    if (!c.observer) w.reconnect_token.assign(c.reconnect_token.begin(), c.reconnect_token.end());
    send(c.peer, net::Channel::reliable, w);
}

}  // namespace jetrace::server
