// The client library: connects, keeps its clock a little ahead of the
// server's, predicts its own car with the shared core, reconciles against
// snapshots, and interpolates the other cars. No rendering: a game (or a
// bot) reads predicted() and the visual_* functions.
//
// An observer (ClientConfig::observe) has no car: it runs no prediction and
// sends no inputs, only snapshot acknowledgements. It draws the race from
// the snapshots, as a player draws the other cars: render_world() (every car
// at the render time), visual_position(slot), authoritative(), and it has
// the race's phase(), race_number(), results() and races_finished().
//
// RaceClient routes the server's messages to one unit per concept: Link
// (connection, joins, reconnects), SceneChoice (the track raced on, and
// TrackDownload: a track the client lacks, fetched from the server),
// ClientClock (the lead over the server), Predictor (prediction and
// reconciliation), SnapshotStore (received worlds, acknowledgements) and
// Interpolator (where cars are drawn).
//
// The caller owns time: update(now_us) does everything due by then.
#pragma once

#include "jetrace/client/client_clock.hpp"
#include "jetrace/client/client_config.hpp"
#include "jetrace/client/drawn_check.hpp"
#include "jetrace/client/interpolator.hpp"
#include "jetrace/client/link.hpp"
#include "jetrace/client/predictor.hpp"
#include "jetrace/client/scene_choice.hpp"
#include "jetrace/client/snapshot_store.hpp"
#include "jetrace/client/track_download.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/net/transport.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace jetrace::client {

struct ClientStats {
    /// Snapshots received and decoded.
    std::uint64_t snapshots = 0;
    /// Snapshots whose state of the own car differed from the prediction.
    std::uint64_t corrections = 0;
    /// Of them, those whose snapshot shows the tick before it stepped
    /// without this client's input (it reached the server late).
    std::uint64_t corrections_late = 0;
    /// Of the others, those with another car near the own one in the
    /// snapshot (within 4 car radii): a car whose inputs the prediction
    /// had to guess may have touched it.
    std::uint64_t corrections_near_car = 0;
    /// Snapshots of a tick the client had drawn its own car at (the first
    /// drawing of each tick, DrawnCheck), and of them those where it was
    /// drawn elsewhere than the server had it.
    std::uint64_t drawn_checked = 0;
    std::uint64_t drawn_off = 0;
    /// Of those, the ones with no known cause (DrawnCause::none): neither a
    /// late input nor a car near, at the tick or at the reconciliation
    /// whose offset was fading. A bug in the prediction shows here.
    std::uint64_t drawn_off_unexplained = 0;
    /// Largest position error found by a correction (unit: m).
    double max_correction_m = 0;
    /// Snapshots that could not be used (undecodable, baseline missing, stale).
    std::uint64_t snapshots_dropped = 0;
    /// Times the clock jumped instead of drifting to the right lead.
    std::uint64_t clock_resyncs = 0;
    /// Snapshots showing a tick the server stepped without this client's
    /// input (it arrived late or not at all).
    std::uint64_t late_inputs = 0;
    /// Times the client got its slot back after a drop.
    std::uint64_t reconnects = 0;
    /// Ticks stepped again by reconciliations (only from the first tick
    /// that can differ from the prediction).
    std::uint64_t replayed_ticks = 0;
    /// Reconciliations that found the prediction right and stepped nothing.
    std::uint64_t skipped_replays = 0;
    /// Car-steps of replayed ticks taken from the prediction instead (cars
    /// far from the others, with the inputs predicted).
    std::uint64_t reused_car_steps = 0;
    /// Round trip to the server measured in ticks, for transports that
    /// report none (a WebSocket): the predicted tick when a snapshot
    /// arrives, less the snapshot's tick and its input margin, smoothed
    /// (1/8 per snapshot); within a tick or so of the transport's figure
    /// (unit: ms; 0: none yet).
    double tick_round_trip_ms = 0;
};

/// Gives the input for the client's own car for the next tick.
using InputSource = std::function<Input(const Scene& scene, const WorldState& predicted, int slot)>;

class RaceClient {
public:
    /// Over the caller's transport; no reconnects.
    RaceClient(const ClientConfig& config, KnownScenes scenes, net::Transport& transport);
    RaceClient(const ClientConfig& config, const Scene& scene, net::Transport& transport)
        : RaceClient(config, KnownScenes{&scene}, transport) {}
    /// Connects through `connect` now, and again after a drop to take its
    /// car back (docs/PROTOCOL.md, "Reconnecting").
    RaceClient(const ClientConfig& config, KnownScenes scenes, Connector connect);
    RaceClient(const ClientConfig& config, const Scene& scene, Connector connect)
        : RaceClient(config, KnownScenes{&scene}, std::move(connect)) {}

    /// Handles the network and runs the prediction ticks due by `now_us`:
    /// receive(), then run_due().
    void update(std::uint64_t now_us, const InputSource& input);
    /// update()'s halves, for a caller driving many clients: receive()
    /// handles the network (snapshots, their reconciliation: the costly
    /// part), run_due() runs the ticks due and sends their inputs. Running
    /// run_due() for every client before their receive() sends each input
    /// without waiting for the other clients' reconciliations.
    void receive(std::uint64_t now_us);
    void run_due(std::uint64_t now_us, const InputSource& input);
    /// Says goodbye and closes.
    void leave(const std::string& reason, proto::CloseCode why = proto::CloseCode::local_left) {
        link_.leave(reason, why);
    }

    ClientState state() const { return link_.client_state(); }
    /// The track being raced: the one the Welcome named (before it, the
    /// first known one).
    const Scene& scene() const { return scenes_.current(); }
    /// Why the client closed (refusal, goodbye, disconnect, error).
    const std::string& close_reason() const { return link_.close_reason(); }
    /// Why it closed, as a number: the server's code (Refuse: 2000-2999,
    /// Goodbye: 1000-1999 or 4000-4999) or the client's own (3000-3999);
    /// proto::CloseCode, docs/PROTOCOL.md "Close codes". 0 while open.
    std::uint16_t close_code() const { return link_.close_code(); }
    /// The own car's slot (-1: none yet, or an observer).
    int slot() const { return slot_; }
    bool spectating() const { return spectating_; }
    /// Welcomed as an observer (ClientConfig::observe): no car, no inputs.
    bool observer() const { return observer_; }
    /// Fetching the server's track (welcomed; snapshots wait for it).
    bool downloading_track() const { return download_.active(); }
    std::uint32_t race_number() const { return race_number_; }
    proto::RacePhase phase() const { return phase_; }
    /// The predicted world at predicted_tick() (thin: the newest snapshot's
    /// cars at the clock's tick; an observer predicts nothing: empty).
    const WorldState& predicted() const { return predictor_.world(); }
    std::uint32_t predicted_tick() const { return predictor_.world().tick; }
    /// The newest authoritative world from a snapshot.
    const WorldState& authoritative() const { return snapshots_.latest().state; }
    const ClientStats& stats() const { return stats_; }
    /// The newest tick whose drawn own car was compared with the server's
    /// (tick kNoTick: none yet).
    const DrawnTick& last_drawn() const { return drawn_.last(); }
    /// The last race's results (race_number 0: none yet).
    const proto::Results& results() const { return results_; }
    /// The roster of the newest RaceStatus (names and slots of the players).
    const std::vector<proto::PlayerInfo>& players() const { return players_; }
    std::uint32_t races_finished() const { return races_finished_; }
    double rtt_ms() const { return link_.rtt_ms(); }
    /// The Welcome's reconnect token (empty before a Welcome).
    const std::vector<std::uint8_t>& reconnect_token() const { return link_.reconnect_token(); }
    /// Traffic of every connection this client made so far.
    net::Totals totals() const { return link_.totals(); }

    /// Where to draw the own car: the prediction plus a correction offset
    /// that fades out (kept apart from the simulated state); no offset
    /// across a respawn.
    Vec3 visual_own_position() const;
    /// Where to draw another car: interpolated between the two stored
    /// snapshots around the render tick, which trails the newest snapshot by
    /// interpolation_snapshots snapshot intervals (never extrapolated; a car
    /// that respawned between the two is drawn at the older one).
    Vec3 visual_position(int slot) const { return interpolator_.other(snapshots_, slot, now_us_, clock_.period_us()); }
    /// The render tick now (the tick visual_position() draws; fractional,
    /// unit: ticks; 0 before the first snapshot).
    double render_tick() const { return interpolator_.render_tick(snapshots_, now_us_, clock_.period_us()); }
    /// The world to draw now: every car at the render tick, interpolated as
    /// visual_position() is (velocity alike, orientation normalised
    /// linearly), the other car fields from the snapshot at or before it;
    /// start_tick, laps and the cars no stored snapshot brackets as in the
    /// newest snapshot (empty before the first). For drawing, never stepped.
    /// The ticks of the stored snapshots render_world() interpolates between
    /// now (false: none on one side; it draws the nearest as it is).
    bool render_span(std::uint32_t& from, std::uint32_t& to) const {
        return Interpolator::span(snapshots_, render_tick(), from, to);
    }
    WorldState render_world() const {
        WorldState w;
        interpolator_.world(snapshots_, now_us_, clock_.period_us(), w);
        return w;
    }

private:
    void init();
    void on_event(const net::Event& e);
    void on_message(const proto::Message& m);
    void on_welcome(const proto::Welcome& w);
    /// The Welcome's track is known: races on it at the server's rates.
    bool take_scene(const proto::Welcome& w);
    /// Takes the slot (or the observer's place) of the Welcome.
    void welcomed(const proto::Welcome& w);
    void request_track();
    void on_track_chunk(const proto::TrackChunk& c);
    void on_snapshot(const proto::Snapshot& s);
    /// Updates ClientStats::tick_round_trip_ms from a new snapshot.
    void measure_round_trip(const proto::Snapshot& s);
    /// Starts the prediction from the newest snapshot, ahead by the lead.
    void start_world();
    /// Forgets the prediction and snapshots: the next snapshot restarts them.
    void reset_world();
    void reconcile(const proto::WorldSnapshot& snap);
    /// Why the own car's prediction for the snapshot's tick may have missed
    /// it: late_input, near_car or none.
    DrawnCause cause_of(const proto::WorldSnapshot& snap) const;
    /// Compares where the own car was drawn at the snapshot's tick.
    void check_drawn(const proto::WorldSnapshot& snap, DrawnCause cause);
    void run_tick(const InputSource& input);
    void send_inputs();
    /// An observer's update: acknowledges the newest snapshot.
    void observe();

    ClientConfig config_;
    SceneChoice scenes_;
    Link link_;
    ClientClock clock_;
    Predictor predictor_;
    SnapshotStore snapshots_;
    Interpolator interpolator_;
    DrawnCheck drawn_;
    /// The cause of the reconciliation that left the fading offset.
    DrawnCause offset_cause_ = DrawnCause::none;

    int slot_ = -1;
    bool spectating_ = false;
    bool observer_ = false;
    /// An observer has a newer snapshot to acknowledge.
    bool ack_pending_ = false;
    proto::RacePhase phase_ = proto::RacePhase::lobby;
    std::uint32_t race_number_ = 0;
    std::uint32_t races_finished_ = 0;
    proto::Results results_;
    std::vector<proto::PlayerInfo> players_;
    std::uint64_t now_us_ = 0;
    /// The prediction runs (from a snapshot of this race).
    bool have_world_ = false;
    // Thin: the own input, computed on the newest snapshot of this tick.
    Input thin_input_{};
    std::uint32_t thin_input_for_ = proto::kNoTick;
    // The newest snapshot waits for the end of the update's events.
    bool reconcile_pending_ = false;
    proto::RacePhase pending_phase_ = proto::RacePhase::lobby;
    std::int16_t pending_margin_ticks_ = 0;
    /// The last receive() polled the link (false: closed, nothing to run).
    bool polled_ = false;
    ClientStats stats_;
    std::vector<net::Event> events_;
    TrackDownload download_;
    /// The Welcome whose track is being downloaded.
    proto::Welcome download_welcome_;
};

}  // namespace jetrace::client
