// The settings of a RaceClient (and of its link, clock and interpolation).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace jetrace::client {

/// Largest ClientConfig::input_delay_ticks (unit: ticks).
inline constexpr std::uint32_t kMaxInputDelayTicks = 30;

struct ClientConfig {
    std::string name = "player";
    /// How many ticks early the client aims for its inputs to reach the
    /// server, on top of the jitter allowance (unit: ticks).
    double target_margin_ticks = 2.0;
    /// Input delay: the input the caller gives at a tick is for the tick
    /// this many later, and is sent at once, so the server and through its
    /// snapshots the other clients hold it that much earlier. The client's
    /// clock still runs the prediction target_margin_ticks ahead of the
    /// server (the inputs then arrive target_margin_ticks + this early).
    /// 0: for the tick it is given at (unit: ticks, at most
    /// kMaxInputDelayTicks).
    std::uint32_t input_delay_ticks = 0;
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
    /// Pause between two reconnect or join attempts. After attempts the
    /// server's pre-Hello cap refused (proto::CloseCode::
    /// refused_pre_hello_cap) in a row: this, twice this, then 4 times
    /// this, each spread at random over 0.5 to 1.5 times (unit: s).
    double reconnect_retry_s = 0.5;
    /// If a connection attempt fails before it comes up (the server not up
    /// yet, unreachable for a while, or its pre-Hello cap refused the
    /// connection), keep trying to join this long after the first failure. A connection that drops after the Hello went out
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
    /// Join as an observer (Hello.observe): no car, no slot, no inputs (the
    /// client acknowledges snapshots only); it follows the race for drawing
    /// (RaceClient::render_world(), visual_position(), results()). An
    /// observer has no reconnect token: a dropped connection closes it.
    bool observe = false;
    /// Largest track file the client downloads when the server races on a
    /// track it does not know (Welcome.track_bytes; 0: never download;
    /// unit: bytes, at most proto::kMaxTrackBytes).
    std::uint32_t max_track_bytes = 16u << 20;
};

}  // namespace jetrace::client
