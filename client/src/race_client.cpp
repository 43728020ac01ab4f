#include "jetrace/client/race_client.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace jetrace::client {

namespace {

}  // namespace

RaceClient::RaceClient(const ClientConfig& config, KnownScenes scenes, net::Transport& transport)
    : config_(config), scenes_(std::move(scenes)), transport_(&transport), predictor_(!config.predict) {
    init();
}

RaceClient::RaceClient(const ClientConfig& config, KnownScenes scenes, Connector connect)
    : config_(config), scenes_(std::move(scenes)), connector_(std::move(connect)), predictor_(!config.predict) {
    init();
    owned_ = connector_ ? connector_() : nullptr;
    transport_ = owned_.get();
    if (!transport_) close("cannot open a connection", proto::CloseCode::local_connection_lost);
}

void RaceClient::init() {
    assert(!scenes_.empty());
    for (const Scene* s : scenes_) identities_.push_back(s->track.identity());
    scene_ = scenes_.front();
    clock_.set_period(1e6 / scene_->physics.tick_rate_hz);
    predictor_.reset();
    for (auto& r : received_) r.first = proto::kNoTick;
}

double RaceClient::rtt_ms() const { return transport_ ? transport_->peer_stats(0).rtt_ms : 0.0; }

net::Totals RaceClient::totals() const {
    net::Totals t = past_totals_;
    if (transport_) {
        const net::Totals now = transport_->totals();
        t.bytes_sent += now.bytes_sent;
        t.bytes_received += now.bytes_received;
        t.packets_sent += now.packets_sent;
        t.packets_received += now.packets_received;
    }
    return t;
}

void RaceClient::close(const std::string& reason, proto::CloseCode why) {
    if (state_ == ClientState::closed) return;
    state_ = ClientState::closed;
    close_reason_ = reason;
    close_code_ = static_cast<std::uint16_t>(why);
    spdlog::info("{}: closed: {}", config_.name, reason);
}

void RaceClient::leave(const std::string& reason, proto::CloseCode why) {
    if (state_ == ClientState::closed) return;
    if (!transport_) return close(reason, why);
    // On the wire a client's goodbye is always `left`; its own code stays here.
    transport_->send(0, net::Channel::reliable,
                     proto::encode(proto::Goodbye{reason, static_cast<std::uint16_t>(proto::CloseCode::left)}));
    transport_->disconnect(0);
    transport_->flush();
    close(reason, why);
}

void RaceClient::on_event(const net::Event& e) {
    switch (e.type) {
        case net::Event::Type::connected: send_hello(); break;
        case net::Event::Type::disconnected:
            if (state_ == ClientState::reconnecting && !close_reason_.empty()) {
                close(close_reason_, static_cast<proto::CloseCode>(server_code_));  // the server said goodbye to the new connection
            } else if (state_ == ClientState::reconnecting) {
                need_connection_ = true;  // that attempt failed: try again
            } else if (may_reconnect()) {
                spdlog::info("{}: connection lost; reconnecting to slot {}", config_.name, slot_);
                state_ = ClientState::reconnecting;
                dropped_at_us_ = now_us_;
                next_attempt_us_ = now_us_;
                need_connection_ = true;
            } else if (may_rejoin()) {
                spdlog::info("{}: {}; joining again", config_.name,
                             no_hello_ ? close_reason_ : std::string("could not connect"));
                close_reason_.clear();
                server_code_ = 0;
                no_hello_ = false;
                state_ = ClientState::reconnecting;
                rejoining_ = true;
                dropped_at_us_ = now_us_;
                next_attempt_us_ = now_us_ + static_cast<std::uint64_t>(config_.reconnect_retry_s * 1e6);
                need_connection_ = true;
            } else {
                if (close_reason_.empty()) {
                    close("disconnected", proto::CloseCode::local_connection_lost);
                } else {
                    close(close_reason_, static_cast<proto::CloseCode>(server_code_));
                }
            }
            break;
        case net::Event::Type::received: {
            proto::Message m;
            std::string error;
            if (!proto::decode(e.data, m, error)) {
                spdlog::warn("{}: ignoring a malformed message from the server: {}", config_.name, error);
                return;
            }
            on_message(m);
            break;
        }
    }
}

void RaceClient::on_message(const proto::Message& m) {
    if (const auto* w = std::get_if<proto::Welcome>(&m)) {
        if (state_ != ClientState::waiting_welcome && state_ != ClientState::reconnecting) {
            spdlog::warn("{}: ignoring an unexpected second welcome", config_.name);
            return;
        }
        std::string why;
        const Scene* chosen = scene_for(*w, why);
        if (chosen == nullptr) {
            leave(why, proto::CloseCode::local_incompatible);
        } else {
            if (chosen != scene_) predictor_.clear_scratch();  // it holds the other track's triangles
            scene_ = chosen;
            clock_.set_period(1e6 / chosen->physics.tick_rate_hz);
            if (state_ == ClientState::reconnecting) {
                ++stats_.reconnects;
                reset_world();  // the server's world went on without us
                if (w->slot != slot_) spdlog::warn("{}: reconnected to slot {}, not {}", config_.name, w->slot, slot_);
            }
            slot_ = w->slot;
            snapshot_rate_hz_ = std::max<int>(1, w->snapshot_rate_hz);
            reconnect_token_ = w->reconnect_token;
            state_ = ClientState::in_lobby;
            spdlog::info("{}: welcome, slot {}", config_.name, slot_);
        }
    } else if (const auto* r = std::get_if<proto::Refuse>(&m)) {
        close("refused: " + r->reason, static_cast<proto::CloseCode>(r->code));
    } else if (const auto* g = std::get_if<proto::Goodbye>(&m)) {
        close_reason_ = "server: " + g->reason;
        server_code_ = g->code;
        // The server never got our Hello (lost on a bad link): it admitted
        // nothing, so joining again is safe.
        no_hello_ = state_ == ClientState::waiting_welcome &&
                    g->code == static_cast<std::uint16_t>(proto::CloseCode::no_hello);
    } else if (const auto* s = std::get_if<proto::RaceStatus>(&m)) {
        phase_ = s->phase;
        for (const auto& p : s->players) {
            if (p.slot == slot_) spectating_ = p.spectating;
        }
    } else if (const auto* res = std::get_if<proto::Results>(&m)) {
        if (res->race_number != results_.race_number) ++races_finished_;
        results_ = *res;
    } else if (const auto* snap = std::get_if<proto::Snapshot>(&m)) {
        on_snapshot(*snap);
    }
}

void RaceClient::on_snapshot(const proto::Snapshot& s) {
    if (slot_ < 0) return;
    if (s.race_number < race_number_) return;  // from a finished race
    if (s.race_number > race_number_) {
        // A new race: a fresh world whose ticks start again from 0.
        race_number_ = s.race_number;
        reset_world();
    }
    const proto::WorldSnapshot* base = nullptr;
    if (s.baseline_tick != proto::kNoTick) {
        const auto& r = received_[s.baseline_tick % received_.size()];
        if (r.first != s.baseline_tick) {
            ++stats_.snapshots_dropped;
            return;
        }
        base = &r.second;
    }
    std::string error;
    if (!proto::decode_world(s.world, base, decoded_, error) || decoded_.state.tick != s.server_tick ||
        decoded_.state.cars.size() <= static_cast<std::size_t>(slot_)) {
        ++stats_.snapshots_dropped;
        spdlog::debug("{}: dropped snapshot {}: {}", config_.name, s.server_tick, error);
        return;
    }
    ++stats_.snapshots;
    phase_ = s.phase;
    auto& kept = received_[s.server_tick % received_.size()];
    kept.first = s.server_tick;
    std::swap(kept.second, decoded_);  // no copy; decoded_ takes the old entry's storage
    const proto::WorldSnapshot& snap = kept.second;
    if (newest_snapshot_tick_ != proto::kNoTick && s.server_tick <= newest_snapshot_tick_) return;  // reordered
    newest_snapshot_tick_ = s.server_tick;
    if (s.last_applied_input_tick != proto::kNoTick) last_applied_input_tick_ = s.last_applied_input_tick;
    latest_ = snap;
    latest_at_us_ = now_us_;
    if (!have_world_) {
        // Join the race: start from the server's state and run ahead by the
        // estimated lead, which update() catches up right away.
        predictor_.start(snap.state);
        have_world_ = true;
        const double lead = rtt_ms() * 1000.0 / clock_.period_us() + config_.target_margin_ticks + 2.0;
        const auto lead_us = static_cast<std::uint64_t>(std::min(lead, 30.0) * clock_.period_us());
        clock_.restart(now_us_);
        clock_.bring_forward(lead_us);
        state_ = ClientState::racing;
        return;
    }
    // Reconciled once the update's events are handled, with the newest of
    // them (a backlog of snapshots costs one replay, not one each).
    reconcile_pending_ = true;
    pending_phase_ = s.phase;
    pending_margin_ticks_ = s.input_margin_ticks;
}

void RaceClient::reset_world() {
    for (auto& r : received_) r.first = proto::kNoTick;
    newest_snapshot_tick_ = proto::kNoTick;
    last_applied_input_tick_ = proto::kNoTick;
    predictor_.reset();
    thin_input_for_ = proto::kNoTick;
    reconcile_pending_ = false;
    clock_adjust_ = 0;
    visual_offset_ = Vec3::Zero();
    have_world_ = false;
}

void RaceClient::send_hello() {
    proto::Hello h;
    h.name = config_.name;
    h.connect_token = config_.connect_token;
    if (state_ == ClientState::reconnecting && !rejoining_) {
        h.reconnect_token = reconnect_token_;
    } else {
        // A join (again): from here on like the first attempt. Once the Hello
        // is out the server may admit us, so a drop now is not retried (a
        // second Hello could take a second slot, or find its connect token
        // spent).
        state_ = ClientState::waiting_welcome;
        rejoining_ = false;
        hello_sent_us_ = now_us_;
    }
    transport_->send(0, net::Channel::reliable, proto::encode(h));
}

bool RaceClient::may_reconnect() const {
    // Not after the server's Goodbye (close_reason_ holds it): it meant it.
    return connector_ && (state_ == ClientState::in_lobby || state_ == ClientState::racing) &&
           reconnect_token_.size() == proto::kTokenBytes && config_.reconnect_window_s > 0 && close_reason_.empty();
}

bool RaceClient::may_rejoin() const {
    // Only when no Hello reached the server: the connection never came up,
    // or the server's Goodbye said it never got the Hello.
    const bool nothing_admitted = (state_ == ClientState::connecting && close_reason_.empty()) ||
                                  (state_ == ClientState::waiting_welcome && no_hello_);
    return connector_ && config_.join_window_s > 0 && nothing_admitted;
}

void RaceClient::reconnect_step() {
    const double window_s = rejoining_ ? config_.join_window_s : config_.reconnect_window_s;
    if (now_us_ - dropped_at_us_ > static_cast<std::uint64_t>(window_s * 1e6)) {
        // An attempt still under way must not be admitted after we gave up.
        if (transport_) {
            transport_->disconnect(0);
            transport_->flush();
        }
        close(std::string("disconnected: could not ") + (rejoining_ ? "join" : "reconnect") + " within " +
                  std::to_string(window_s) + " s",
              proto::CloseCode::local_connection_lost);
        return;
    }
    if (!need_connection_ || now_us_ < next_attempt_us_) return;
    // The old connection is dead: keep its figures, open a new one.
    past_totals_ = totals();
    owned_.reset();
    transport_ = nullptr;
    owned_ = connector_();
    transport_ = owned_.get();
    need_connection_ = transport_ == nullptr;
    next_attempt_us_ = now_us_ + static_cast<std::uint64_t>(config_.reconnect_retry_s * 1e6);
}

void RaceClient::reconcile(const proto::WorldSnapshot& snap) {
    const auto own = static_cast<std::size_t>(slot_);
    const Vec3 before = predictor_.world().cars[own].position;
    const Predictor::Outcome o =
        predictor_.reconcile(*scene_, snap, own, !spectating_ && snap.state.cars[own].active);
    stats_.replayed_ticks = predictor_.work().replayed_ticks;
    stats_.skipped_replays = predictor_.work().skipped_replays;
    stats_.reused_car_steps = predictor_.work().reused_car_steps;
    if (o.resynced) {
        // Behind the server: the clock catches up.
        ++stats_.clock_resyncs;
        clock_.restart(now_us_);
        return;
    }
    if (o.corrected) {
        ++stats_.corrections;
        stats_.max_correction_m = std::max(stats_.max_correction_m, o.error_m);
        spdlog::debug("{}: correction at tick {}: error {:.4f} m, last applied input {}, predicted tick {}",
                      config_.name, snap.state.tick, o.error_m, last_applied_input_tick_, predicted_tick());
    }
    if (predictor_.thin()) return;
    visual_offset_ += before - predictor_.world().cars[own].position;
}

void RaceClient::adjust_clock(proto::RacePhase phase, std::int16_t input_margin_ticks) {
    if (phase != proto::RacePhase::countdown && phase != proto::RacePhase::racing) return;
    if (input_margin_ticks == -32768) return;  // no input received yet
    const double sigma_ticks = transport_->peer_stats(0).rtt_variance_ms * 1000.0 / clock_.period_us();
    const double target = config_.target_margin_ticks + config_.jitter_margin_sigmas * sigma_ticks;
    const double error = input_margin_ticks - target;
    if (error < -6.0) {
        // Inputs arrive late: jump ahead rather than drift.
        clock_.bring_forward(static_cast<std::uint64_t>(std::min(-error, 30.0) * clock_.period_us()));
        ++stats_.clock_resyncs;
        clock_adjust_ = 0;
        return;
    }
    clock_adjust_ = std::clamp(0.01 * error, -config_.max_clock_adjust, config_.max_clock_adjust);
}

void RaceClient::run_tick(const InputSource& input) {
    const WorldState& w = predictor_.world();
    const auto own = static_cast<std::size_t>(slot_);
    Input mine{};
    if (!spectating_ && w.cars[own].active && input) {
        if (!predictor_.thin()) {
            mine = input(*scene_, w, slot_);
        } else {
            // On the newest snapshot, once per snapshot.
            if (thin_input_for_ != newest_snapshot_tick_) thin_input_ = input(*scene_, w, slot_);
            thin_input_for_ = newest_snapshot_tick_;
            mine = thin_input_;
        }
    }
    predictor_.run_tick(*scene_, own, mine, latest_);
    visual_offset_ *= 1.0 - config_.smoothing_per_tick;
}

void RaceClient::send_inputs() {
    if (spectating_ || slot_ < 0) return;
    const std::uint32_t end = predicted_tick();  // inputs for ticks < end exist
    std::uint32_t first = last_applied_input_tick_ == proto::kNoTick ? 0 : last_applied_input_tick_ + 1;
    if (end > proto::kMaxInputsPerBatch && first < end - static_cast<std::uint32_t>(proto::kMaxInputsPerBatch)) {
        first = end - static_cast<std::uint32_t>(proto::kMaxInputsPerBatch);
    }
    proto::InputBatch b;
    b.ack_snapshot_tick = newest_snapshot_tick_;
    for (std::uint32_t t = first; t < end; ++t) {
        const Input* in = predictor_.my_input(t);
        if (in == nullptr) {
            b.inputs.clear();
            first = t + 1;
            continue;
        }
        b.inputs.push_back(*in);
    }
    if (b.inputs.empty()) return;
    b.first_tick = first;
    transport_->send(0, net::Channel::unreliable, proto::encode(b));
}

void RaceClient::update(std::uint64_t now_us, const InputSource& input) {
    now_us_ = now_us;
    if (state_ == ClientState::reconnecting) reconnect_step();
    if (!transport_) return;
    events_.clear();
    transport_->service(now_us / 1000, events_);
    for (const net::Event& e : events_) {
        on_event(e);
        if (need_connection_) break;  // the rest came from the dead connection
    }
    if (reconcile_pending_ && have_world_ && state_ == ClientState::racing && slot_ >= 0) {
        reconcile(latest_);
        adjust_clock(pending_phase_, pending_margin_ticks_);
    }
    reconcile_pending_ = false;
    if (state_ == ClientState::waiting_welcome && config_.welcome_timeout_s > 0 &&
        now_us_ - hello_sent_us_ > static_cast<std::uint64_t>(config_.welcome_timeout_s * 1e6)) {
        leave("no welcome within " + std::to_string(config_.welcome_timeout_s) + " s", proto::CloseCode::local_no_welcome);
    }
    if (state_ == ClientState::closed || state_ == ClientState::reconnecting || !have_world_ || slot_ < 0) {
        transport_->flush();
        return;
    }
    clock_.skip_backlog(now_us);
    int ran = 0;
    while (clock_.pop(now_us, 1.0 + clock_adjust_)) {
        run_tick(input);
        ++ran;
    }
    // Inputs go out at most every `input_interval` ticks, with every input
    // the server has not yet applied (redundancy against loss).
    if (ran > 0 && (predicted_tick() % config_.input_interval_ticks == 0 || ran > 1)) send_inputs();
    transport_->flush();
}

Vec3 RaceClient::visual_own_position() const {
    if (slot_ < 0 || !have_world_) return Vec3::Zero();
    return predicted().cars[static_cast<std::size_t>(slot_)].position + visual_offset_;
}

Vec3 RaceClient::visual_position(int slot) const {
    const auto s = static_cast<std::size_t>(slot);
    if (s >= latest_.state.cars.size() || newest_snapshot_tick_ == proto::kNoTick) return Vec3::Zero();
    // The render tick trails the newest snapshot by the interpolation delay,
    // advancing with the client's clock between snapshots.
    const double interval = static_cast<double>(scene_->physics.tick_rate_hz) / snapshot_rate_hz_;
    const double since = static_cast<double>(now_us_ - latest_at_us_) / clock_.period_us();
    const double render = newest_snapshot_tick_ + since - config_.interpolation_snapshots * interval;
    // The two stored snapshots around the render tick.
    const std::pair<std::uint32_t, proto::WorldSnapshot>* a = nullptr;
    const std::pair<std::uint32_t, proto::WorldSnapshot>* b = nullptr;
    for (const auto& r : received_) {
        if (r.first == proto::kNoTick || s >= r.second.state.cars.size() || !r.second.state.cars[s].active) continue;
        if (r.first <= render && (!a || r.first > a->first)) a = &r;
        if (r.first > render && (!b || r.first < b->first)) b = &r;
    }
    if (a && b) {
        const double f = (render - a->first) / static_cast<double>(b->first - a->first);
        const Vec3& pa = a->second.state.cars[s].position;
        return pa + (b->second.state.cars[s].position - pa) * f;
    }
    if (a) return a->second.state.cars[s].position;  // never extrapolate
    if (b) return b->second.state.cars[s].position;
    return latest_.state.cars[s].position;
}

}  // namespace jetrace::client
