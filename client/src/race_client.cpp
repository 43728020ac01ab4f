#include "jetrace/client/race_client.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::client {

RaceClient::RaceClient(const ClientConfig& config, KnownScenes scenes, net::Transport& transport)
    : config_(config), scenes_(config.name, std::move(scenes)), link_(config, transport), clock_(config),
      predictor_(!config.predict, config.input_delay_ticks),
      interpolator_(config.interpolation_snapshots, config.smoothing_per_tick) {
    init();
}

RaceClient::RaceClient(const ClientConfig& config, KnownScenes scenes, Connector connect)
    : config_(config), scenes_(config.name, std::move(scenes)), link_(config, std::move(connect)), clock_(config),
      predictor_(!config.predict, config.input_delay_ticks),
      interpolator_(config.interpolation_snapshots, config.smoothing_per_tick) {
    init();
}

void RaceClient::init() {
    clock_.set_tick_rate(scene().physics.tick_rate_hz);
    interpolator_.set_rates(scene().physics.tick_rate_hz);
    predictor_.reset();
}

void RaceClient::on_event(const net::Event& e) {
    if (e.type != net::Event::Type::received) return link_.on_connection_event(e);
    proto::Message m;
    std::string error;
    if (!proto::decode(e.data, m, error)) {
        spdlog::warn("{}: ignoring a malformed message from the server: {}", config_.name, error);
        return;
    }
    on_message(m);
}

void RaceClient::on_message(const proto::Message& m) {
    if (const auto* w = std::get_if<proto::Welcome>(&m)) {
        on_welcome(*w);
    } else if (const auto* r = std::get_if<proto::Refuse>(&m)) {
        link_.on_refuse(*r);
    } else if (const auto* g = std::get_if<proto::Goodbye>(&m)) {
        link_.on_goodbye(*g);
    } else if (const auto* s = std::get_if<proto::RaceStatus>(&m)) {
        phase_ = s->phase;
        players_ = s->players;
        for (const auto& p : s->players) {
            if (p.slot == slot_) spectating_ = p.spectating;
        }
    } else if (const auto* res = std::get_if<proto::Results>(&m)) {
        if (res->race_number != results_.race_number) ++races_finished_;
        results_ = *res;
    } else if (const auto* snap = std::get_if<proto::Snapshot>(&m)) {
        on_snapshot(*snap);
    } else if (const auto* chunk = std::get_if<proto::TrackChunk>(&m)) {
        on_track_chunk(*chunk);
    }
}

void RaceClient::on_welcome(const proto::Welcome& w) {
    if (!link_.awaits_welcome()) {
        spdlog::warn("{}: ignoring an unexpected second welcome", config_.name);
        return;
    }
    if (w.observer != config_.observe) {
        return link_.leave(config_.observe ? "the server did not take us as an observer"
                                           : "the server took us as an observer",
                           proto::CloseCode::local_incompatible);
    }
    if (!scenes_.knows(w.track_identity) && w.track_bytes > 0) {
        // A track we lack: welcomed now, racing once it is downloaded.
        std::string why;
        if (!download_.start(w.track_bytes, w.track_identity, config_.max_track_bytes, why)) {
            return link_.leave(why, proto::CloseCode::local_bad_track);
        }
        spdlog::info("{}: downloading the server's track '{}' ({} bytes)", config_.name, w.track_name, w.track_bytes);
        download_welcome_ = w;
        welcomed(w);
        return request_track();
    }
    if (take_scene(w)) welcomed(w);
}

bool RaceClient::take_scene(const proto::Welcome& w) {
    bool changed = false;
    std::string why;
    if (!scenes_.choose(w, changed, why)) {
        link_.leave(why, proto::CloseCode::local_incompatible);
        return false;
    }
    if (changed) predictor_.clear_scratch();  // it holds the other track's triangles
    clock_.set_tick_rate(scene().physics.tick_rate_hz);
    interpolator_.set_rates(scene().physics.tick_rate_hz, w.snapshot_rate_hz);
    return true;
}

void RaceClient::welcomed(const proto::Welcome& w) {
    if (link_.on_welcome(w)) {
        ++stats_.reconnects;
        reset_world();  // the server's world went on without us
    }
    observer_ = w.observer;
    slot_ = observer_ ? -1 : w.slot;
    if (observer_) spdlog::info("{}: welcome, observing", config_.name);
    else spdlog::info("{}: welcome, slot {}", config_.name, slot_);
}

void RaceClient::request_track() {
    std::uint32_t offset = 0;
    while (link_.transport() && download_.next_request(offset)) {
        link_.transport()->send(0, net::Channel::reliable, proto::encode(proto::TrackRequest{offset}));
    }
}

void RaceClient::on_track_chunk(const proto::TrackChunk& c) {
    std::string why;
    if (!download_.add(c, why)) return link_.leave(why, proto::CloseCode::local_bad_track);
    if (!download_.complete()) return request_track();
    Track track;
    if (!download_.finish(track, why)) return link_.leave(why, proto::CloseCode::local_bad_track);
    const proto::Welcome& w = download_welcome_;
    PhysicsSettings physics = scene().physics;
    if (w.physics && validate(*w.physics).empty()) physics = *w.physics;
    spdlog::info("{}: downloaded the track '{}' ({} triangles)", config_.name, track.name, track.triangles.size());
    scenes_.add(std::make_unique<Scene>(Scene::make(std::move(track), physics)));
    take_scene(w);
}

void RaceClient::on_snapshot(const proto::Snapshot& s) {
    if (slot_ < 0 && !observer_) return;  // not welcomed
    if (download_.active()) return;  // no track to race on yet
    if (s.race_number < race_number_) return;  // from a finished race
    if (s.race_number > race_number_) {
        // A new race: a fresh world whose ticks start again from 0.
        race_number_ = s.race_number;
        reset_world();
    }
    std::string error;
    const auto added = snapshots_.add(s, static_cast<std::size_t>(slot_ + 1), now_us_, error);
    if (added == SnapshotStore::Added::no_baseline || added == SnapshotStore::Added::undecodable) {
        ++stats_.snapshots_dropped;
        if (added == SnapshotStore::Added::undecodable)
            spdlog::debug("{}: dropped snapshot {}: {}", config_.name, s.server_tick, error);
        return;
    }
    ++stats_.snapshots;
    phase_ = s.phase;
    if (added == SnapshotStore::Added::older) return;  // reordered
    if (observer_) {
        ack_pending_ = true;
        have_world_ = true;
        return link_.start_racing();
    }
    if (!have_world_) return start_world();
    measure_round_trip(s);
    // Reconciled once the update's events are handled, with the newest of
    // them (a backlog of snapshots costs one replay, not one each).
    reconcile_pending_ = true;
    pending_phase_ = s.phase;
    pending_margin_ticks_ = s.input_margin_ticks;
    // The server stepped the tick before this one without our input.
    if (!spectating_ && s.phase == proto::RacePhase::racing && s.last_applied_input_tick != proto::kNoTick &&
        s.last_applied_input_tick + 1 < s.server_tick) {
        ++stats_.late_inputs;
    }
}

void RaceClient::measure_round_trip(const proto::Snapshot& s) {
    // The client runs `lead` ticks ahead of the server: an input sent at
    // predicted tick P arrives `lead - margin` ticks later, and a snapshot
    // of server tick S arrives when the client is at P' = S + down + lead.
    // So up + down = P' - S - margin.
    const double ticks = static_cast<double>(predictor_.world().tick) - static_cast<double>(s.server_tick) -
                         static_cast<double>(s.input_margin_ticks);
    if (ticks < 0 || s.last_applied_input_tick == proto::kNoTick) return;
    const double ms = ticks * static_cast<double>(clock_.period_us()) / 1000.0;
    double& rtt = stats_.tick_round_trip_ms;
    rtt = rtt == 0 ? ms : rtt + (ms - rtt) / 8.0;
}

void RaceClient::start_world() {
    // Join the race: start from the server's state and run ahead by the
    // estimated lead, which update() catches up right away.
    predictor_.start(snapshots_.latest().state);
    have_world_ = true;
    clock_.start(now_us_, link_.rtt_ms());
    link_.start_racing();
}

void RaceClient::reset_world() {
    snapshots_.reset();
    predictor_.reset();
    thin_input_for_ = proto::kNoTick;
    reconcile_pending_ = false;
    clock_.reset();
    interpolator_.reset();
    drawn_.clear();
    have_world_ = false;
}

void RaceClient::reconcile(const proto::WorldSnapshot& snap) {
    const auto own = static_cast<std::size_t>(slot_);
    const DrawnCause cause = cause_of(snap);
    check_drawn(snap, cause);
    const Vec3 before = predictor_.world().cars[own].position;
    const std::uint32_t respawns_before = predictor_.world().cars[own].respawns;
    const Predictor::Outcome o = predictor_.reconcile(scene(), snap, own, !spectating_ && snap.state.cars[own].active);
    stats_.replayed_ticks = predictor_.work().replayed_ticks;
    stats_.skipped_replays = predictor_.work().skipped_replays;
    stats_.reused_car_steps = predictor_.work().reused_car_steps;
    if (o.resynced) return clock_.resync(now_us_, link_.rtt_ms());  // behind the server: the clock catches up
    if (o.corrected) {
        ++stats_.corrections;
        if (cause == DrawnCause::late_input) ++stats_.corrections_late;
        if (cause == DrawnCause::near_car) ++stats_.corrections_near_car;
        stats_.max_correction_m = std::max(stats_.max_correction_m, o.error_m);
        spdlog::debug("{}: correction at tick {}: error {:.4f} m, last applied input {}, predicted tick {}",
                      config_.name, snap.state.tick, o.error_m, snapshots_.last_applied_input_tick(), predicted_tick());
    }
    if (!predictor_.thin()) {
        const CarState& after = predictor_.world().cars[own];
        interpolator_.correct(before, after.position, after.respawns != respawns_before);
        // The replay moved the present: a car near the own one on the way
        // (whose guessed inputs the snapshot corrected), else the snapshot's
        // cause.
        if (!(before == after.position)) offset_cause_ = o.near_car ? DrawnCause::near_car : cause;
    }
}

DrawnCause RaceClient::cause_of(const proto::WorldSnapshot& snap) const {
    const std::uint32_t applied = snapshots_.last_applied_input_tick();
    if (applied != proto::kNoTick && applied + 1 < snap.state.tick) return DrawnCause::late_input;
    const bool near = near_other_car(scene(), snap.state, static_cast<std::size_t>(slot_));
    return near ? DrawnCause::near_car : DrawnCause::none;
}

void RaceClient::check_drawn(const proto::WorldSnapshot& snap, DrawnCause cause) {
    const auto own = static_cast<std::size_t>(slot_);
    if (spectating_ || !snap.state.cars[own].active) return;
    if (!drawn_.confirm(snap.state.tick, snap.state.cars[own].position, cause)) return;
    ++stats_.drawn_checked;
    if (drawn_.last().same) return;
    ++stats_.drawn_off;
    if (drawn_.last().cause == DrawnCause::none) ++stats_.drawn_off_unexplained;
}

void RaceClient::run_tick(const InputSource& input) {
    const WorldState& w = predictor_.world();
    const auto own = static_cast<std::size_t>(slot_);
    Input mine{};
    if (!spectating_ && w.cars[own].active && input) {
        if (!predictor_.thin()) {
            mine = input(scene(), w, slot_);
        } else {
            // On the newest snapshot, once per snapshot.
            if (thin_input_for_ != snapshots_.newest_tick()) thin_input_ = input(scene(), w, slot_);
            thin_input_for_ = snapshots_.newest_tick();
            mine = thin_input_;
        }
    }
    const std::uint32_t respawns = predictor_.world().cars[own].respawns;
    predictor_.run_tick(scene(), own, mine, snapshots_.latest());
    // A predicted respawn: what is left of a correction offset belongs to
    // where the car was, not to its last gate.
    if (predictor_.world().cars[own].respawns != respawns) interpolator_.reset();
    interpolator_.tick();
    if (!predictor_.thin()) {
        drawn_.record(predicted_tick(), visual_own_position(), interpolator_.smoothing(), offset_cause_);
    }
}

void RaceClient::send_inputs() {
    if (spectating_ || slot_ < 0) return;
    proto::InputBatch b;
    b.ack_snapshot_tick = snapshots_.newest_tick();
    if (!predictor_.unapplied_inputs(snapshots_.last_applied_input_tick(), b)) return;
    link_.transport()->send(0, net::Channel::unreliable, proto::encode(b));
}

void RaceClient::update(std::uint64_t now_us, const InputSource& input) {
    receive(now_us);
    run_due(now_us, input);
}

void RaceClient::receive(std::uint64_t now_us) {
    now_us_ = now_us;
    polled_ = link_.poll(now_us, events_);
    if (!polled_) return;
    for (const net::Event& e : events_) {
        on_event(e);
        if (link_.connection_due()) break;  // the rest came from the dead connection
    }
    if (reconcile_pending_ && have_world_ && link_.state() == LinkState::racing && slot_ >= 0) {
        reconcile(snapshots_.latest());
        clock_.adjust(pending_phase_, pending_margin_ticks_, link_.rtt_variance_ms());
        stats_.clock_resyncs = clock_.resyncs();
    }
    reconcile_pending_ = false;
    link_.check_welcome_timeout();
}

void RaceClient::run_due(std::uint64_t now_us, const InputSource& input) {
    now_us_ = now_us;
    if (!polled_) return;
    if (observer_) return observe();
    if (link_.state() != LinkState::racing || !have_world_ || slot_ < 0) return link_.flush();
    clock_.skip_backlog(now_us);
    int ran = 0;
    while (clock_.pop(now_us)) {
        run_tick(input);
        ++ran;
    }
    // Inputs go out at most every `input_interval` ticks, with every input
    // the server has not yet applied (redundancy against loss).
    if (ran > 0 && (predicted_tick() % config_.input_interval_ticks == 0 || ran > 1)) send_inputs();
    link_.flush();
}

void RaceClient::observe() {
    // No ticks, no inputs: only the acknowledgement, so that the next
    // snapshots come delta-encoded against it.
    if (ack_pending_ && link_.state() == LinkState::racing && link_.transport()) {
        link_.transport()->send(0, net::Channel::unreliable, proto::encode(proto::SnapshotAck{snapshots_.newest_tick()}));
    }
    ack_pending_ = false;
    link_.flush();
}

Vec3 RaceClient::visual_own_position() const {
    if (slot_ < 0 || !have_world_) return Vec3::Zero();
    return interpolator_.own(predicted().cars[static_cast<std::size_t>(slot_)].position);
}

}  // namespace jetrace::client
