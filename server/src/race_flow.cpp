// RaceServer: the tick, the race phases, snapshots and results.
#include "jetrace/core/race.hpp"
#include "jetrace/replay/format.hpp"
#include "jetrace/server/race_server.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>

namespace jetrace::server {

void RaceServer::tick() {
    ++ticks_;
    switch (phase_) {
        case proto::RacePhase::lobby: lobby_tick(); break;
        case proto::RacePhase::countdown:
        case proto::RacePhase::racing: step_race(); break;
        case proto::RacePhase::finished:
            if (now_us_ >= results_until_us_) {
                phase_ = proto::RacePhase::lobby;
                for (auto& [peer, c] : sessions_.clients()) c.spectating = false;
                broadcast_status();
            }
            break;
    }
}

void RaceServer::start_race() {
    ++race_number_;
    ++counters_.races_started;
    const auto countdown = static_cast<std::uint32_t>(config_.countdown_s * scene_.physics.tick_rate_hz + 0.5);
    world_ = make_world(config_.max_players, config_.laps, countdown);
    scratch_ = StepScratch{};
    applied_.assign(world_.cars.size(), Input{});
    pending_removals_.clear();
    first_finish_tick_ = proto::kNoTick;
    snapshots_.clear();
    race_start_unix_s_ = unix_time_s_ > 0 ? unix_time_s_ : 0;
    racers_at_start_.clear();
    for (auto& [peer, c] : sessions_.clients()) {
        c.reset_link_state();
        if (!c.greeted || c.slot < 0) continue;
        c.spectating = false;
        spawn_car(scene_, world_, c.slot, c.slot);
        racers_at_start_.emplace_back(static_cast<std::uint8_t>(c.slot), c.name);
    }
    std::sort(racers_at_start_.begin(), racers_at_start_.end());
    phase_ = proto::RacePhase::countdown;
    spdlog::info("race {} on '{}': {} players, {} laps, start in {:.1f} s", race_number_, scene_.track.name, players(),
                 config_.laps, config_.countdown_s);
    observe_start();
    broadcast_status();
    send_snapshots();
}

void RaceServer::step_race() {
    // Exactly one input per car per tick; a missing one repeats the last for
    // at most the input hold, then is neutral.
    const auto hold_ticks = static_cast<std::uint32_t>(config_.input_hold_s * scene_.physics.tick_rate_hz + 0.5);
    for (std::size_t s = 0; s < world_.cars.size(); ++s) {
        applied_[s] = Input{};
        // A held car (its player dropped) drives on with neutral inputs.
        Client* driver = sessions_.driver_of(s);
        if (!driver || !world_.cars[s].active) continue;
        bool missing = false;
        applied_[s] = driver->inputs.pick(world_.tick, hold_ticks, missing);
        if (missing) ++counters_.inputs_missing;
    }
    if (observer) observer->before_step(world_.tick, pending_removals_, applied_);
    pending_removals_.clear();
    step(scene_, world_, applied_, scratch_);
    if (observer) observer->after_step(world_);

    if (phase_ == proto::RacePhase::countdown && world_.tick >= world_.start_tick) {
        phase_ = proto::RacePhase::racing;
        spdlog::info("race {}: go", race_number_);
        broadcast_status();
    }
    bool any = false, all_finished = true;
    for (const CarState& car : world_.cars) {
        if (!car.active) continue;
        any = true;
        all_finished = all_finished && car.finished;
        if (car.finished && first_finish_tick_ == proto::kNoTick) first_finish_tick_ = world_.tick;
    }
    const double rate = scene_.physics.tick_rate_hz;
    const bool window_over = first_finish_tick_ != proto::kNoTick &&
                             world_.tick - first_finish_tick_ >= config_.finish_window_s * rate;
    const bool too_long = world_.tick >= world_.start_tick + config_.max_race_s * rate;
    if (phase_ == proto::RacePhase::racing && (!any || all_finished || window_over || too_long)) {
        using replay::EndReason;
        end_race(!any           ? EndReason::abandoned
                 : all_finished ? EndReason::finished
                 : window_over  ? EndReason::finish_window
                                : EndReason::time_limit);
        return;
    }
    if (world_.tick % static_cast<std::uint32_t>(scene_.physics.tick_rate_hz / config_.snapshot_rate_hz) == 0) {
        send_snapshots();
    }
}

void RaceServer::send_snapshots() {
    proto::WorldSnapshot now;
    now.state = world_;
    now.last_inputs = applied_;
    now.last_inputs.resize(world_.cars.size());
    now.tick_rate_hz = static_cast<std::uint16_t>(scene_.physics.tick_rate_hz);
    // The inputs already received for the coming ticks, so that clients
    // replay the other cars exactly instead of guessing.
    now.upcoming.assign(world_.cars.size(), {});
    for (std::size_t s = 0; s < world_.cars.size(); ++s) {
        Client* driver = sessions_.driver_of(s);
        if (!driver || !world_.cars[s].active) continue;
        driver->inputs.upcoming(world_.tick, proto::kMaxUpcomingInputs, now.upcoming[s]);
    }
    snapshots_.begin(std::move(now));
    for (auto& [peer, c] : sessions_.clients()) {
        if (!c.greeted) continue;
        proto::Snapshot snap;
        snap.server_tick = world_.tick;
        snap.world = snapshots_.encoded_for(c.acked_snapshot, snap.baseline_tick);
        snap.last_applied_input_tick = c.inputs.last_applied_tick();
        const std::uint32_t newest = c.inputs.newest_tick();
        const std::int64_t margin =
            newest == proto::kNoTick ? -32768 : std::int64_t{newest} - std::int64_t{world_.tick};
        snap.input_margin_ticks = static_cast<std::int16_t>(std::clamp<std::int64_t>(margin, -32768, 32767));
        snap.phase = phase_;
        snap.race_number = race_number_;
        send(peer, net::Channel::unreliable, snap);
    }
    snapshots_.commit();
}

std::vector<proto::StandingEntry> RaceServer::current_standings() const {
    std::vector<proto::StandingEntry> out;
    for (const Standing& s : standings(scene_.track, world_.cars, world_.start_tick, scene_.physics.tick_rate_hz)) {
        proto::StandingEntry e;
        e.slot = static_cast<std::uint8_t>(s.slot);
        const Client* owner = sessions_.owner_of(s.slot);
        e.name = owner ? owner->name : "player" + std::to_string(s.slot);
        e.finished = s.finished;
        e.lap = static_cast<std::uint16_t>(s.lap);
        e.finish_time_s = s.finish_time_s;
        out.push_back(e);
    }
    return out;
}

void RaceServer::observe_start() {
    if (!observer) return;
    replay::Header h = replay::header_for(scene_, world_);
    h.race_number = race_number_;
    h.start_unix_s = race_start_unix_s_;
    h.names.assign(world_.cars.size(), std::string());
    for (const auto& [peer, c] : sessions_.clients()) {
        if (c.greeted && c.slot >= 0) h.names[static_cast<std::size_t>(c.slot)] = c.name;
    }
    observer->race_started(h);
}

void RaceServer::observe_end(replay::EndReason reason, std::uint64_t hash) {
    if (!observer) return;
    replay::Trailer t;
    t.final_tick = world_.tick;
    t.final_state_hash = hash;
    t.reason = reason;
    t.end_unix_s = unix_time_s_ > 0 ? unix_time_s_ : 0;
    t.removed = pending_removals_;
    t.results = replay::results_of(scene_, world_);
    observer->race_ended(t);
}

void RaceServer::end_race(replay::EndReason reason) {
    using replay::EndReason;
    const bool by_rules = reason != EndReason::aborted && reason != EndReason::abandoned && reason != EndReason::drained;
    ++(by_rules ? counters_.races_finished : counters_.races_aborted);
    RaceEnd end;
    end.race_number = race_number_;
    end.ticks = world_.tick;
    end.state_hash = state_hash(world_);
    end.reason = reason;
    end.start_unix_s = race_start_unix_s_;
    end.end_unix_s = unix_time_s_ > 0 ? unix_time_s_ : 0;
    end.standings = current_standings();
    end.racers = racers();
    observe_end(reason, end.state_hash);
    spdlog::info("race {} over after {} ticks ({})", race_number_, end.ticks, replay::end_reason_name(reason));
    if (on_race_end) on_race_end(end);
    proto::Results r;
    r.race_number = race_number_;
    r.standings = end.standings;
    r.state_hash = end.state_hash;
    send_snapshots();  // the final state, so clients can check the hash
    for (const auto& [peer, c] : sessions_.clients()) {
        if (c.greeted) send(peer, net::Channel::reliable, r);
    }
    phase_ = proto::RacePhase::finished;
    ++races_completed_;
    results_until_us_ = now_us_ + static_cast<std::uint64_t>(config_.results_pause_s * 1e6);
    broadcast_status();
    if (shutting_down_) {
        // shutdown() ended this race: it goes on with its own reason.
    } else if (draining_) {
        shutdown(drain_reason_);
    } else if (config_.races > 0 && races_completed_ >= static_cast<std::uint32_t>(config_.races)) {
        shutdown("the server hosted its last race");
    }
}

}  // namespace jetrace::server
