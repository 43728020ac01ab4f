// The authoritative race server, independent of sockets and clocks: the
// caller owns time (update(now_us)) and the transport (ENet in production,
// anything that implements net::Transport in tests).
//
// Race flow: lobby -> countdown -> racing -> finished -> lobby ...
// docs/PROTOCOL.md ("Connection state machine", "Timing and input flow")
// describes what a client sees.
#pragma once

#include "jetrace/auth/token_verifier.hpp"
#include "jetrace/core/tick_clock.hpp"
#include "jetrace/core/value_range.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/net/transport.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/proto/world_codec.hpp"
#include "jetrace/replay/format.hpp"
#include "jetrace/server/counters.hpp"
#include "jetrace/server/input_queue.hpp"
#include "jetrace/server/race_observer.hpp"
#include "jetrace/server/session_table.hpp"
#include "jetrace/server/snapshot_history.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace jetrace::server {

struct ServerConfig {
    /// Laps per race (unit: laps).
    int laps = 3;
    /// Most cars in a race (unit: players).
    int max_players = 8;
    /// Most observers (clients without a car that watch: Hello.observe) at
    /// a time, on top of the players (unit: observers).
    int max_observers = 8;
    /// Players needed before the countdown starts (unit: players).
    int min_players = 1;
    /// Snapshots sent per second; must divide the tick rate (unit: Hz;
    /// jetrace-server's default is default_snapshot_rate()).
    int snapshot_rate_hz = 60;
    /// Races to host before done() turns true; 0 hosts forever (unit: races).
    int races = 0;
    /// Countdown before a race (unit: s).
    double countdown_s = 3.0;
    /// Pause on the results between races (unit: s).
    double results_pause_s = 3.0;
    /// After the first car finishes, the others have this long (unit: s).
    double finish_window_s = 60.0;
    /// A race ends after this long whatever happens (unit: s).
    double max_race_s = 1200.0;
    /// Inputs further ahead of the server tick are dropped (unit: ticks).
    int max_input_lead_ticks = 240;
    /// A player's missing input repeats its last one for at most this long
    /// after the last input that came; then the car drives with neutral
    /// inputs until inputs come again, so a client gone silent (crashed,
    /// unplugged, not yet timed out) does not hold full throttle or full
    /// lock (unit: s of the server's clock).
    double input_hold_s = 0.5;
    /// A connection that has not said Hello by then is dropped (unit: s of
    /// the caller's clock; jetrace-server scales its --hello-timeout, given
    /// in real time, by --time-scale).
    double hello_timeout_s = 5.0;
    /// With at least one but fewer than min_players players for this long,
    /// the lobby starts the race anyway, or with lobby_timeout_cancels tells
    /// the players why and lets them go (unit: s; 0 = wait forever).
    double lobby_timeout_s = 0;
    bool lobby_timeout_cancels = false;
    /// How often a waiting lobby logs "waiting N/M" (unit: s).
    double lobby_log_interval_s = 10.0;
    /// A player whose connection drops without a Goodbye keeps its slot, and
    /// its car (driven with neutral inputs), this long for a Hello with its
    /// reconnect token; 0 frees the slot at once (unit: s).
    double reconnect_grace_s = 10.0;
    /// After the last race, or shutdown(), the server keeps serving its
    /// connections until each has closed (its Results and Goodbye
    /// acknowledged, or the client's own Goodbye), at most this long; 0:
    /// done at once (unit: s of the caller's clock; jetrace-server scales its
    /// --linger, given in real time, by --time-scale).
    double linger_s = 5.0;
    /// Private race: only Hellos with a connect token signed by the secret
    /// half of this Ed25519 public key get in (unset = an open server).
    std::optional<auth::PublicKey> connect_key;
    /// Connect tokens must carry exactly this race id ("" = none).
    std::string race_id;
    /// Unexpired connect-token nonces remembered against replays; when full,
    /// new tokens are refused (unit: tokens).
    std::size_t max_connect_nonces = 4096;
    /// Nonces already spent (a restart's --nonce-file): refused like ones
    /// admitted here.
    std::vector<auth::SpentNonce> spent_nonces;
};

/// The allowed values of ServerConfig's fields: validate() checks them and
/// jetrace-server's options offer exactly them (min_players is also at most
/// max_players; the snapshot rate must divide the tick rate; --hello-timeout
/// is given in real time, and its value times --time-scale is checked).
struct ServerLimits {
    static constexpr ValueRange laps = closed(1, 1000);
    static constexpr ValueRange players = closed(1, proto::kMaxSlots);
    static constexpr ValueRange observers = closed(0, 1000);
    static constexpr ValueRange races = closed(0, 1e6);
    static constexpr ValueRange countdown_s = closed(0, 600);
    static constexpr ValueRange results_pause_s = closed(0, 600);
    static constexpr ValueRange finish_window_s = above(0, 3600);
    static constexpr ValueRange max_race_s = above(0, 86400);
    static constexpr ValueRange max_input_lead_ticks = closed(1, InputQueue::kMaxLeadTicks);
    static constexpr ValueRange input_hold_s = closed(0, 60);
    static constexpr ValueRange hello_timeout_s = closed(0.001, 86400);
    static constexpr ValueRange lobby_timeout_s = closed(0, 86400);
    static constexpr ValueRange lobby_log_interval_s = above(0, 86400);
    static constexpr ValueRange reconnect_grace_s = closed(0, 3600);
    static constexpr ValueRange linger_s = closed(0, 3600);
    static constexpr ValueRange max_connect_nonces = closed(1, 1e7);
};

/// The snapshot rate used unless one is given: the largest divisor of the
/// tick rate that is at most 60 (unit: Hz).
int default_snapshot_rate(int tick_rate_hz);

/// Empty if usable, else what is wrong.
std::string validate(const ServerConfig& c, int tick_rate_hz);

/// What clients download of `track`: its compiled .jtrack bytes, or nothing
/// for a built-in track (same name and identity as the one this build
/// makes), which every client has.
std::vector<std::uint8_t> track_file_of(const Track& track);

/// A player who had a car at the race's start.
struct Racer {
    std::uint8_t slot = 0;
    std::string name;
    /// Not connected at the end (dropped without coming back).
    bool dropped = false;
};

struct RaceEnd {
    std::uint32_t race_number = 0;
    std::uint32_t ticks = 0;
    std::uint64_t state_hash = 0;
    /// Why the race ended (drained: the drain timeout cut it short;
    /// aborted: the server stopped it at once).
    replay::EndReason reason = replay::EndReason::finished;
    /// Wall clock at the countdown's start and at the end (unit: s since
    /// 1970 UTC; 0 = the caller never set it).
    std::int64_t start_unix_s = 0;
    std::int64_t end_unix_s = 0;
    /// The cars still in the race, in order (what clients get in Results).
    std::vector<proto::StandingEntry> standings;
    /// Everyone who had a car at the start, in slot order, dropped ones too.
    std::vector<Racer> racers;
};

class RaceServer {
public:
    RaceServer(const ServerConfig& config, const Scene& scene, net::Transport& transport);

    /// Handles the network and runs every tick due by `now_us` (the caller's
    /// clock). Returns the number of ticks stepped.
    int update(std::uint64_t now_us);
    /// The same, and sets the wall clock connect tokens expire by (unit: s
    /// since 1970 UTC). A private race refuses every token until it is set.
    int update(std::uint64_t now_us, std::int64_t unix_time_s);

    /// Ends the race in progress at once (reported as aborted; a race still
    /// in its countdown is not reported), tells every client why, and stops
    /// ticking; done() turns true once every connection has closed or after
    /// ServerConfig::linger_s, whichever comes first.
    void shutdown(const std::string& reason);
    /// Lets the race under way finish within `timeout_s` (then it ends as
    /// drained), refusing new players meanwhile, then shuts down. With no
    /// race under way it shuts down at once; a second call does too, and a
    /// call during the linger after shutdown() makes done() true at once.
    void drain(const std::string& reason, double timeout_s);
    bool draining() const { return draining_; }

    bool done() const { return done_; }
    proto::RacePhase phase() const { return phase_; }
    const WorldState& world() const { return world_; }
    std::uint32_t races_completed() const { return races_completed_; }
    std::uint64_t ticks() const { return ticks_; }
    int max_players_seen() const { return max_players_seen_; }
    /// Connection requests the transport dropped because their address
    /// already held its cap of connections without a Hello (unit: datagrams;
    /// net::Totals::connects_refused).
    std::uint64_t refused_pre_hello() const { return transport_.totals().connects_refused; }
    /// Welcomed players (connected, spectating ones included; no observers).
    int players() const;
    /// Welcomed observers.
    int observers() const { return sessions_.observers(); }
    /// Slots held for players who dropped, waiting for their reconnect.
    int held_slots() const { return static_cast<int>(sessions_.held().size()); }
    /// The race under way or last run (0 before the first).
    std::uint32_t race_number() const { return race_number_; }
    /// What the server counted so far (server/src/observe.cpp).
    RaceCounters counters() const;
    /// Every player, connected or held, by slot.
    std::vector<PlayerStatus> player_status() const;
    /// The track file clients download (empty: a built-in track).
    const std::vector<std::uint8_t>& track_file() const { return track_file_; }

    /// Called at the end of every race that started (the caller writes the
    /// results file: the library does no file I/O).
    std::function<void(const RaceEnd&)> on_race_end;
    /// Sees every race tick by tick (jetrace-server's ReplayRecorder writes
    /// the replay); nullptr = none. Must outlive the server.
    RaceObserver* observer = nullptr;
    /// Called after a connect token was admitted, with the verifier whose
    /// spent nonces changed (jetrace-server's --nonce-file saves them).
    std::function<void(const auth::TokenVerifier&)> on_nonce_spent;

private:
    /// Odd but harmless client behaviour: the data is ignored, the first
    /// occurrence of each kind per client is logged (a flood never floods the
    /// log). Inputs too far ahead are also what an honest client sends for
    /// the previous race until it sees the new one, hence only info.
    enum Anomaly : std::uint8_t {
        kConflictingInput = 1,
        kInputTooFarAhead = 2,
        kInputWhileSpectating = 4,
        kInputFromObserver = 8,
    };
    void note(Client& c, Anomaly kind, const std::string& what);

    void on_event(const net::Event& e);
    void on_message(Client& c, const proto::Message& m);
    void on_hello(Client& c, const proto::Hello& h);
    /// Checks a Hello's connect token in a private race (refusing it if it
    /// does not hold); `ticket` is then the token to admit.
    bool check_connect_token(Client& c, const proto::Hello& h, std::optional<auth::ConnectToken>& ticket);
    void welcome_observer(Client& c, const proto::Hello& h);
    void on_inputs(Client& c, const proto::InputBatch& b);
    /// Answers a TrackRequest with one TrackChunk (server/src/track_serve.cpp).
    void on_track_request(Client& c, const proto::TrackRequest& r);
    /// Takes a snapshot acknowledgement (InputBatch or SnapshotAck).
    void take_ack(Client& c, std::uint32_t ack_snapshot_tick);
    void drop(net::PeerId peer, DropReason why, const std::string& reason);
    void refuse(Client& c, const std::string& name, Refusal why, const std::string& reason);
    void send_welcome(Client& c);

    // Reconnects (server/src/reconnect.cpp).
    /// A welcomed client is gone: hold its slot for the grace period if
    /// `may_return`, else free the slot, remove its car and remember `why`
    /// its reconnect token is void.
    void release(Client&& c, bool may_return, std::string why);
    void expire_held();
    void on_reconnect(Client& c, const proto::Hello& h);
    void send(net::PeerId peer, net::Channel ch, const proto::Message& m);
    proto::RaceStatus status() const;
    void broadcast_status();

    void tick();
    void step_race();
    void start_race();
    void end_race(replay::EndReason reason);
    void send_snapshots();
    void lobby_tick();
    void cancel_lobby(const std::string& reason);
    void check_drain();
    /// After shutdown(): done once no connection is left or the linger is over.
    void check_linger();
    void observe_start();
    void observe_end(replay::EndReason reason, std::uint64_t hash);
    std::vector<proto::StandingEntry> current_standings() const;
    std::vector<Racer> racers() const;

    ServerConfig config_;
    const Scene& scene_;
    net::Transport& transport_;
    TickClock clock_;
    bool started_clock_ = false;
    std::uint64_t now_us_ = 0;

    SessionTable sessions_;
    /// The track as a compiled .jtrack file, for clients that download it
    /// (empty: a built-in track, which every client has).
    std::vector<std::uint8_t> track_file_;
    std::unique_ptr<auth::TokenVerifier> verifier_;  // private races only
    std::int64_t unix_time_s_ = -1;                  // -1: not set

    proto::RacePhase phase_ = proto::RacePhase::lobby;
    std::uint32_t race_number_ = 0;
    std::uint32_t races_completed_ = 0;
    WorldState world_;
    StepScratch scratch_;
    std::vector<Input> applied_;
    std::vector<std::uint8_t> pending_removals_;
    std::uint32_t first_finish_tick_ = proto::kNoTick;
    std::uint64_t results_until_us_ = 0;
    SnapshotHistory snapshots_;
    RaceCounters counters_;
    std::uint64_t ticks_ = 0;
    int max_players_seen_ = 0;
    bool done_ = false;
    std::vector<net::Event> events_;
    /// The lobby has had players (fewer than min_players) since then.
    bool lobby_waiting_ = false;
    std::uint64_t lobby_since_us_ = 0;
    std::uint64_t next_lobby_log_us_ = 0;
    bool draining_ = false;
    /// shutdown() is under way (the race it ends must not shut down again).
    bool shutting_down_ = false;
    std::string drain_reason_;
    std::uint64_t drain_until_us_ = 0;
    std::uint64_t linger_until_us_ = 0;
    std::int64_t race_start_unix_s_ = 0;
    std::vector<std::pair<std::uint8_t, std::string>> racers_at_start_;
};

}  // namespace jetrace::server
