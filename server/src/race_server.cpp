// RaceServer: connections, the handshake and client messages.
#include "jetrace/server/race_server.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::server {

namespace {

proto::CloseCode close_code(DropReason why) {
    switch (why) {
        case DropReason::no_hello: return proto::CloseCode::no_hello;
        case DropReason::malformed: return proto::CloseCode::malformed;
        case DropReason::protocol:
        case DropReason::count: break;
    }
    return proto::CloseCode::protocol_violation;
}

proto::CloseCode close_code(Refusal why) {
    switch (why) {
        case Refusal::version: return proto::CloseCode::refused_version;
        case Refusal::token: return proto::CloseCode::refused_token;
        case Refusal::clock: return proto::CloseCode::refused_clock;
        case Refusal::full: return proto::CloseCode::refused_full;
        case Refusal::reconnect: return proto::CloseCode::refused_reconnect;
        case Refusal::observers_full: return proto::CloseCode::refused_observers_full;
        case Refusal::draining:
        case Refusal::count: break;
    }
    return proto::CloseCode::refused_draining;
}

}  // namespace

RaceServer::RaceServer(const ServerConfig& config, const Scene& scene, net::Transport& transport)
    : config_(config),
      scene_(scene),
      transport_(transport),
      clock_(1e6 / scene.physics.tick_rate_hz),
      sessions_(config.max_players),
      track_file_(track_file_of(scene.track)) {
    world_ = make_world(config_.max_players, config_.laps);
    if (config_.connect_key) {
        verifier_ = std::make_unique<auth::TokenVerifier>(
            auth::VerifierConfig{*config_.connect_key, config_.race_id, config_.max_connect_nonces});
        std::string error;
        if (!verifier_->restore(config_.spent_nonces, error)) spdlog::error("spent connect-token nonces: {}", error);
    }
}

int RaceServer::players() const { return sessions_.players(); }

void RaceServer::send(net::PeerId peer, net::Channel ch, const proto::Message& m) {
    const std::vector<std::uint8_t> bytes = proto::encode(m);
    transport_.send(peer, ch, bytes);
}

void RaceServer::drop(net::PeerId peer, DropReason why, const std::string& reason) {
    const Client* c = sessions_.find(peer);
    if (!c) return;
    ++counters_.dropped[static_cast<std::size_t>(why)];
    spdlog::warn("dropping client {} ({}): {}", peer, c->name.empty() ? "no name" : c->name, reason);
    std::string text = reason;
    if (text.size() > proto::kMaxReasonBytes) {
        // Cut at a character boundary: drop continuation bytes, then the lead byte.
        text.resize(proto::kMaxReasonBytes);
        while (!text.empty() && (static_cast<unsigned char>(text.back()) & 0xC0) == 0x80) text.pop_back();
        if (!text.empty() && (static_cast<unsigned char>(text.back()) & 0x80) != 0) text.pop_back();
    }
    send(peer, net::Channel::reliable, proto::Goodbye{text, static_cast<std::uint16_t>(close_code(why))});
    transport_.disconnect(peer);
    release(sessions_.take(peer), false, "reconnect token no longer valid: the server dropped the player");
}

void RaceServer::refuse(Client& c, const std::string& name, Refusal why, const std::string& reason) {
    ++counters_.refused[static_cast<std::size_t>(why)];
    spdlog::warn("refusing client {} ({}): {}", c.peer, name, reason);
    send(c.peer, net::Channel::reliable, proto::Refuse{reason, static_cast<std::uint16_t>(close_code(why))});
    transport_.disconnect(c.peer);
}

void RaceServer::on_event(const net::Event& e) {
    switch (e.type) {
        case net::Event::Type::connected:
            if (shutting_down_) {
                transport_.disconnect(e.peer);  // no more races here
                break;
            }
            sessions_.connect(e.peer, now_us_);
            spdlog::info("client {} connected", e.peer);
            break;
        case net::Event::Type::disconnected: {
            const Client* c = sessions_.find(e.peer);
            if (!c) break;
            spdlog::info("client {} ({}) disconnected", e.peer, c->name);
            // Without a Goodbye (which forgets the client at once) the
            // connection dropped: the player may come back.
            release(sessions_.take(e.peer), true,
                    "reconnect token no longer valid: this server keeps no slot for a dropped player");
            break;
        }
        case net::Event::Type::received: {
            Client* c = sessions_.find(e.peer);
            if (!c) break;
            proto::Message m;
            std::string error;
            if (!proto::decode(e.data, m, error)) {
                drop(e.peer, DropReason::malformed, "malformed message: " + error);
                break;
            }
            on_message(*c, m);
            break;
        }
    }
}

void RaceServer::on_message(Client& c, const proto::Message& m) {
    if (const auto* hello = std::get_if<proto::Hello>(&m)) {
        on_hello(c, *hello);
    } else if (const auto* inputs = std::get_if<proto::InputBatch>(&m)) {
        if (!c.greeted) {
            drop(c.peer, DropReason::protocol, "protocol violation: inputs before hello");
            return;
        }
        on_inputs(c, *inputs);
    } else if (const auto* ack = std::get_if<proto::SnapshotAck>(&m)) {
        if (!c.greeted) {
            drop(c.peer, DropReason::protocol, "protocol violation: acknowledgement before hello");
            return;
        }
        take_ack(c, ack->ack_snapshot_tick);
    } else if (const auto* request = std::get_if<proto::TrackRequest>(&m)) {
        if (!c.greeted) {
            drop(c.peer, DropReason::protocol, "protocol violation: track request before hello");
            return;
        }
        on_track_request(c, *request);
    } else if (std::holds_alternative<proto::Goodbye>(m)) {
        // Forgotten at once: the slot is free for others now, whenever ENet
        // reports the disconnect, and the player cannot reconnect.
        spdlog::info("client {} ({}) said goodbye", c.peer, c.name);
        transport_.disconnect(c.peer);
        // `c` is gone too.
        release(sessions_.take(c.peer), false, "reconnect token no longer valid: the player said goodbye");
    } else {
        drop(c.peer, DropReason::protocol, "protocol violation: clients may not send this message");
    }
}

void RaceServer::take_ack(Client& c, std::uint32_t ack_snapshot_tick) {
    if (ack_snapshot_tick != proto::kNoTick && ack_snapshot_tick <= world_.tick &&
        (c.acked_snapshot == proto::kNoTick || ack_snapshot_tick > c.acked_snapshot)) {
        c.acked_snapshot = ack_snapshot_tick;
    }
}

void RaceServer::on_inputs(Client& c, const proto::InputBatch& b) {
    if (c.observer) {
        // Nothing of it counts, its acknowledgement included: an observer
        // acknowledges with SnapshotAck.
        note(c, kInputFromObserver, "inputs from an observer (it has no car); ignored");
        return;
    }
    take_ack(c, b.ack_snapshot_tick);
    if (phase_ != proto::RacePhase::countdown && phase_ != proto::RacePhase::racing) return;
    if (c.spectating || c.slot < 0) {
        note(c, kInputWhileSpectating, "inputs while spectating (no car until the next race); ignored");
        return;
    }
    const InputQueue::Accepted got = c.inputs.accept(b, world_.tick, config_.max_input_lead_ticks);
    counters_.inputs_late += got.late;
    counters_.inputs_dropped += got.dropped;
    if (got.too_far_tick != proto::kNoTick) {
        note(c, kInputTooFarAhead,
             fmt::format("input for tick {} is more than {} ticks ahead of tick {}; dropped", got.too_far_tick,
                         config_.max_input_lead_ticks, world_.tick));
    }
    if (got.conflicting_tick != proto::kNoTick) {
        note(c, kConflictingInput,
             fmt::format("a second, different input for tick {}; only the first one received counts",
                         got.conflicting_tick));
    }
}

void RaceServer::note(Client& c, Anomaly kind, const std::string& what) {
    if ((c.logged_anomalies & kind) != 0) return;
    c.logged_anomalies |= kind;
    spdlog::log(kind == kInputTooFarAhead ? spdlog::level::info : spdlog::level::warn,
                "client {} ({}): {} (logged once per client)", c.peer, c.name, what);
}

proto::RaceStatus RaceServer::status() const {
    proto::RaceStatus s;
    s.phase = phase_;
    s.race_number = race_number_;
    s.start_tick = world_.start_tick;
    s.laps = static_cast<std::uint16_t>(config_.laps);
    for (const auto& [peer, c] : sessions_.clients()) {
        if (!c.greeted || c.observer) continue;
        s.players.push_back({static_cast<std::uint8_t>(c.slot), c.name, c.spectating});
    }
    for (const auto& [slot, h] : sessions_.held()) {
        s.players.push_back({static_cast<std::uint8_t>(slot), h.client.name, h.client.spectating});
    }
    return s;
}

void RaceServer::broadcast_status() {
    const proto::RaceStatus s = status();
    for (const auto& [peer, c] : sessions_.clients()) {
        if (c.greeted) send(peer, net::Channel::reliable, s);
    }
}

int RaceServer::update(std::uint64_t now_us, std::int64_t unix_time_s) {
    unix_time_s_ = unix_time_s;
    return update(now_us);
}

int RaceServer::update(std::uint64_t now_us) {
    now_us_ = now_us;
    if (!started_clock_) {
        started_clock_ = true;
        clock_.restart(now_us);
    }
    events_.clear();
    transport_.service(now_us / 1000, events_);
    for (const net::Event& e : events_) on_event(e);
    // Drop connections that never said hello.
    for (net::PeerId p : sessions_.silent(now_us, static_cast<std::uint64_t>(config_.hello_timeout_s * 1e6))) {
        drop(p, DropReason::no_hello, std::string(proto::kNoHelloReason) + " " + std::to_string(config_.hello_timeout_s) + " s");
    }
    expire_held();
    check_drain();
    check_linger();

    int stepped = 0;
    clock_.skip_backlog(now_us);
    while (!shutting_down_ && clock_.pop(now_us)) {
        tick();
        ++stepped;
    }
    transport_.flush();
    return stepped;
}

}  // namespace jetrace::server
