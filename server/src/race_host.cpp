// RaceServer: the host's controls: the lobby timeout, the drain, shutdown.
#include "jetrace/server/race_server.hpp"

#include <spdlog/spdlog.h>

namespace jetrace::server {

void RaceServer::lobby_tick() {
    const int waiting = players();
    if (waiting >= config_.min_players) {
        lobby_waiting_ = false;
        start_race();
        return;
    }
    if (waiting == 0) {
        lobby_waiting_ = false;
        return;
    }
    if (!lobby_waiting_) {
        lobby_waiting_ = true;
        lobby_since_us_ = now_us_;
        next_lobby_log_us_ = now_us_;
    }
    if (now_us_ >= next_lobby_log_us_) {
        spdlog::info("lobby: waiting {}/{} players", waiting, config_.min_players);
        next_lobby_log_us_ = now_us_ + static_cast<std::uint64_t>(config_.lobby_log_interval_s * 1e6);
    }
    if (config_.lobby_timeout_s <= 0 ||
        now_us_ - lobby_since_us_ < static_cast<std::uint64_t>(config_.lobby_timeout_s * 1e6)) {
        return;
    }
    lobby_waiting_ = false;
    const std::string what = fmt::format("lobby timed out after {:g} s with {} of {} players", config_.lobby_timeout_s,
                                         waiting, config_.min_players);
    if (config_.lobby_timeout_cancels) {
        cancel_lobby(what + ": race cancelled");
    } else {
        spdlog::info("{}: starting anyway", what);
        start_race();
    }
}

void RaceServer::cancel_lobby(const std::string& reason) {
    spdlog::info("{}", reason);
    for (net::PeerId peer : sessions_.player_peers()) {
        send(peer, net::Channel::reliable,
             proto::Goodbye{reason, static_cast<std::uint16_t>(proto::CloseCode::lobby_cancelled)});
        transport_.disconnect(peer);
        release(sessions_.take(peer), false, "reconnect token no longer valid: the lobby was cancelled");
    }
    broadcast_status();
}

void RaceServer::drain(const std::string& reason, double timeout_s) {
    if (done_) return;
    if (shutting_down_) {
        spdlog::info("{}: stopping at once ({} connections still open)", reason, sessions_.clients().size());
        done_ = true;
        return;
    }
    const bool under_way = phase_ == proto::RacePhase::countdown || phase_ == proto::RacePhase::racing;
    if (draining_ || !under_way) {
        shutdown(draining_ ? reason + " (again: stopping at once)" : reason);
        return;
    }
    draining_ = true;
    drain_reason_ = reason;
    drain_until_us_ = now_us_ + static_cast<std::uint64_t>(timeout_s * 1e6);
    spdlog::info("{}: draining: race {} may finish within {:g} s of the server clock; new players are refused", reason, race_number_,
                 timeout_s);
}

void RaceServer::check_drain() {
    if (!draining_ || done_ || now_us_ < drain_until_us_) return;
    if (phase_ == proto::RacePhase::racing) {
        spdlog::info("drain timeout: race {} is cut short", race_number_);
        end_race(replay::EndReason::drained);  // then shuts down
    } else {
        shutdown(drain_reason_);
    }
}

std::vector<Racer> RaceServer::racers() const {
    std::vector<Racer> out;
    for (const auto& [slot, name] : racers_at_start_) {
        const Client* driver = sessions_.driver_of(slot);
        const bool here = driver && driver->name == name;
        out.push_back({slot, name, !here});
    }
    return out;
}

void RaceServer::shutdown(const std::string& reason) {
    if (done_ || shutting_down_) return;
    shutting_down_ = true;
    if (phase_ == proto::RacePhase::racing) end_race(replay::EndReason::aborted);
    if (phase_ == proto::RacePhase::countdown) {
        // Stopped before its start: not a result (the replay says why).
        spdlog::info("race {} stopped in its countdown: no result", race_number_);
        observe_end(replay::EndReason::aborted, state_hash(world_));
        phase_ = proto::RacePhase::lobby;
    }
    if (observer) observer->stopped();
    for (const auto& [peer, c] : sessions_.clients()) {
        send(peer, net::Channel::reliable,
             proto::Goodbye{reason, static_cast<std::uint16_t>(proto::CloseCode::server_shutdown)});
        transport_.disconnect(peer);
    }
    transport_.flush();
    linger_until_us_ = now_us_ + static_cast<std::uint64_t>(config_.linger_s * 1e6);
    spdlog::info("server shutting down: {}", reason);
    check_linger();
}

void RaceServer::check_linger() {
    if (!shutting_down_ || done_) return;
    // Each connection closes once ENet has delivered what was queued for it
    // (the Results, the Goodbye), or on the client's own Goodbye.
    const std::size_t open = sessions_.clients().size();
    if (open > 0 && now_us_ < linger_until_us_) return;
    if (open > 0)
        spdlog::warn("{} connections still open after the {:g} s linger: closing them", open, config_.linger_s);
    done_ = true;
}

}  // namespace jetrace::server
