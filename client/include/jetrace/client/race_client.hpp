// The client library: connects, keeps its clock a little ahead of the
// server's, predicts its own car with the shared core, reconciles against
// snapshots, and interpolates the other cars. No rendering: a game (or a
// bot) reads predicted() and the visual_* functions.
//
// The caller owns time: update(now_us) does everything due by then.
#pragma once

#include "jetrace/net/transport.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/proto/world_codec.hpp"
#include "jetrace/tick_clock.hpp"
#include "jetrace/world.hpp"

#include "jetrace/client/predictor.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace jetrace::client {

struct ClientConfig {
    std::string name = "player";
    /// How many ticks early the client aims for its inputs to reach the
    /// server, on top of the jitter allowance (unit: ticks).
    double target_margin_ticks = 2.0;
    /// Jitter allowance: this many RTT standard deviations (unit: 1).
    double jitter_margin_sigmas = 2.0;
    /// Largest speed-up or slow-down of the client's tick clock (unit: fraction).
    double max_clock_adjust = 0.05;
    /// Delay at which other cars are shown, behind the newest snapshot
    /// (unit: snapshot intervals).
    double interpolation_snapshots = 2.0;
    /// Inputs are sent every this many ticks, each packet carrying every
    /// input the server has not applied yet (unit: ticks).
    std::uint32_t input_interval_ticks = 3;
    /// Fraction of a visible correction removed per tick (unit: 1/tick).
    double smoothing_per_tick = 0.1;
    /// After the connection drops (no Goodbye from the server), keep trying
    /// to reconnect with the Welcome's reconnect token this long; match the
    /// server's reconnect grace. Needs the Connector constructor; 0: never
    /// (unit: s).
    double reconnect_window_s = 10.0;
    /// Pause between two reconnect or join attempts (unit: s).
    double reconnect_retry_s = 0.5;
    /// If a connection attempt fails before it comes up (the server not up
    /// yet, or unreachable for a while), keep trying to join this long after
    /// the first failure. A connection that drops after the Hello went out
    /// is not retried: the server may have admitted it. Needs the Connector
    /// constructor; 0: never (unit: s).
    double join_window_s = 10.0;
    /// Leave if no Welcome (or Refuse) comes this long after the Hello (a
    /// port that answers but is no jetrace server); 0: wait (unit: s).
    double welcome_timeout_s = 10.0;
    /// Hello.connect_token: a signed connect token for a private race
    /// (jetrace-token issue), or empty (unit: bytes).
    std::vector<std::uint8_t> connect_token;
    /// Predict (and reconcile) the world; false: a thin client, which steps
    /// nothing and drives on the newest snapshot, its input computed once a
    /// snapshot (load tests: far cheaper per client, the same protocol).
    bool predict = true;
};

enum class ClientState : std::uint8_t { connecting, waiting_welcome, in_lobby, racing, reconnecting, closed };

struct ClientStats {
    /// Snapshots received and decoded.
    std::uint64_t snapshots = 0;
    /// Snapshots whose state of the own car differed from the prediction.
    std::uint64_t corrections = 0;
    /// Largest position error found by a correction (unit: m).
    double max_correction_m = 0;
    /// Snapshots that could not be used (undecodable, baseline missing, stale).
    std::uint64_t snapshots_dropped = 0;
    /// Times the clock jumped instead of drifting to the right lead.
    std::uint64_t clock_resyncs = 0;
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
};

/// Gives the input for the client's own car for the next tick.
using InputSource = std::function<Input(const Scene& scene, const WorldState& predicted, int slot)>;

/// Opens a new connection to the server (nullptr: cannot right now).
using Connector = std::function<std::unique_ptr<net::Transport>()>;

/// The tracks a client can race on (each outlives the client; at least one).
/// The server's Welcome names its track by identity: the client races on the
/// one that matches, and leaves if none does.
using KnownScenes = std::vector<const Scene*>;

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

    /// Handles the network and runs the prediction ticks due by `now_us`.
    void update(std::uint64_t now_us, const InputSource& input);
    /// Says goodbye and closes.
    void leave(const std::string& reason, proto::CloseCode why = proto::CloseCode::local_left);

    ClientState state() const { return state_; }
    /// The track being raced: the one the Welcome named (before it, the
    /// first known one).
    const Scene& scene() const { return *scene_; }
    /// Why the client closed (refusal, goodbye, disconnect, error).
    const std::string& close_reason() const { return close_reason_; }
    /// Why it closed, as a number: the server's code (Refuse: 2000-2999,
    /// Goodbye: 1000-1999 or 4000-4999) or the client's own (3000-3999);
    /// proto::CloseCode, docs/PROTOCOL.md "Close codes". 0 while open.
    std::uint16_t close_code() const { return close_code_; }
    int slot() const { return slot_; }
    bool spectating() const { return spectating_; }
    std::uint32_t race_number() const { return race_number_; }
    proto::RacePhase phase() const { return phase_; }
    /// The predicted world at predicted_tick() (thin: the newest snapshot's
    /// cars at the clock's tick).
    const WorldState& predicted() const { return predictor_.world(); }
    std::uint32_t predicted_tick() const { return predictor_.world().tick; }
    /// The newest authoritative world from a snapshot.
    const WorldState& authoritative() const { return latest_.state; }
    const ClientStats& stats() const { return stats_; }
    /// The last race's results (race_number 0: none yet).
    const proto::Results& results() const { return results_; }
    std::uint32_t races_finished() const { return races_finished_; }
    double rtt_ms() const;
    /// The Welcome's reconnect token (empty before a Welcome).
    const std::vector<std::uint8_t>& reconnect_token() const { return reconnect_token_; }
    /// Traffic of every connection this client made so far.
    net::Totals totals() const;

    /// Where to draw the own car: the prediction plus a correction offset
    /// that fades out (kept apart from the simulated state).
    Vec3 visual_own_position() const;
    /// Where to draw another car: interpolated between the two stored
    /// snapshots around the render tick, which trails the newest snapshot by
    /// interpolation_snapshots snapshot intervals (never extrapolated).
    Vec3 visual_position(int slot) const;

private:
    void init();
    void on_event(const net::Event& e);
    void on_message(const proto::Message& m);
    void on_snapshot(const proto::Snapshot& s);
    void reconcile(const proto::WorldSnapshot& snap);
    void run_tick(const InputSource& input);
    void send_inputs();
    void close(const std::string& reason, proto::CloseCode why);
    void adjust_clock(proto::RacePhase phase, std::int16_t input_margin_ticks);
    void send_hello();
    /// Forgets the prediction and snapshots: the next snapshot restarts them.
    void reset_world();
    bool may_reconnect() const;
    bool may_rejoin() const;
    void reconnect_step();

    ClientConfig config_;
    KnownScenes scenes_;
    std::vector<std::uint64_t> identities_;  // Track::identity() of each
    const Scene* scene_ = nullptr;
    /// A known scene rebuilt at the server's tick rate (Welcome), if it
    /// differs from the known scene's.
    std::unique_ptr<Scene> adopted_scene_;
    /// The scene to race `w` on, or nullptr with `why` (the client leaves).
    const Scene* scene_for(const proto::Welcome& w, std::string& why);
    Connector connector_;
    std::unique_ptr<net::Transport> owned_;  // with a Connector
    net::Transport* transport_ = nullptr;
    net::Totals past_totals_;  // of the connections before this one
    std::vector<std::uint8_t> reconnect_token_;
    std::uint64_t dropped_at_us_ = 0;
    std::uint64_t next_attempt_us_ = 0;
    bool need_connection_ = false;
    bool rejoining_ = false;  // reconnecting state, but with no slot to take back
    std::uint64_t hello_sent_us_ = 0;
    bool no_hello_ = false;  // the server's Goodbye said it never got our Hello
    ClientState state_ = ClientState::connecting;
    std::string close_reason_;
    std::uint16_t close_code_ = 0;
    /// The code of the server's Goodbye (0: none), kept until the disconnect.
    std::uint16_t server_code_ = 0;
    int slot_ = -1;
    bool spectating_ = false;
    proto::RacePhase phase_ = proto::RacePhase::lobby;
    std::uint32_t race_number_ = 0;
    std::uint32_t races_finished_ = 0;
    proto::Results results_;

    // Clock.
    std::uint64_t now_us_ = 0;
    TickClock clock_{1e6 / 120};
    double clock_adjust_ = 0;
    bool have_world_ = false;

    // Prediction.
    Predictor predictor_;
    std::uint32_t last_applied_input_tick_ = proto::kNoTick;
    // Thin: the own input, computed on the newest snapshot of this tick.
    Input thin_input_{};
    std::uint32_t thin_input_for_ = proto::kNoTick;

    // Snapshots: decoded worlds by tick (baselines), newest and previous.
    std::array<std::pair<std::uint32_t, proto::WorldSnapshot>, 128> received_{};
    proto::WorldSnapshot latest_;
    proto::WorldSnapshot decoded_;  // decode target (keeps its storage)
    std::uint64_t latest_at_us_ = 0;
    std::uint32_t newest_snapshot_tick_ = proto::kNoTick;
    int snapshot_rate_hz_ = 60;
    // The newest snapshot waits for the end of the update's events.
    bool reconcile_pending_ = false;
    proto::RacePhase pending_phase_ = proto::RacePhase::lobby;
    std::int16_t pending_margin_ticks_ = 0;

    Vec3 visual_offset_{0, 0, 0};
    ClientStats stats_;
    std::vector<net::Event> events_;
};

}  // namespace jetrace::client
