// The client's tick clock: the shared TickClock run a little ahead of the
// server's, so that each input reaches the server a few ticks before the
// server steps its tick. It starts ahead by the estimated lead, then drifts
// (a rate adjustment) towards the margin the server reports, or jumps when
// far behind (docs/PROTOCOL.md, "Timing and input flow"). With an input
// delay of D ticks the newest input the server holds is for the predicted
// tick + D: the clock keeps the target margin for the predicted tick, so
// the inputs arrive D ticks earlier still, and the prediction stays ahead
// of the server as without a delay.
#pragma once

#include "jetrace/client/client_config.hpp"
#include "jetrace/core/tick_clock.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>

namespace jetrace::client {

class ClientClock {
public:
    explicit ClientClock(const ClientConfig& config);

    void set_tick_rate(int tick_rate_hz) { clock_.set_period(1e6 / tick_rate_hz); }
    /// Time between ticks at rate 1 (unit: µs).
    double period_us() const { return clock_.period_us(); }

    /// Ticks from `now_us` on, ahead of the server by the estimated lead
    /// (the round trip, the target margin and two ticks; at most 30 ticks).
    void start(std::uint64_t now_us, double rtt_ms);
    /// The prediction fell behind the server (it took a snapshot's state):
    /// ticks from `now_us` on, ahead by the lead again, as start() (a
    /// restart without it would leave the client at the server's tick,
    /// every input late, until the next snapshot put it behind again).
    void resync(std::uint64_t now_us, double rtt_ms);
    /// Steers the lead by the server's input margin of a snapshot (only
    /// while the race counts down or runs, and once the server has inputs),
    /// less the input delay.
    void adjust(proto::RacePhase phase, std::int16_t input_margin_ticks, double rtt_variance_ms);
    /// Forgets the rate adjustment.
    void reset() { adjust_ = 0; }

    /// Called once per update before pop(): drops a backlog beyond the
    /// TickClock's catch-up cap.
    void skip_backlog(std::uint64_t now_us) { clock_.skip_backlog(now_us); }
    /// True when a tick is due at now_us (the next one then scheduled).
    bool pop(std::uint64_t now_us) { return clock_.pop(now_us, 1.0 + adjust_); }

    /// Times the clock jumped instead of drifting to the right lead.
    std::uint64_t resyncs() const { return resyncs_; }

private:
    double target_margin_ticks_;
    double jitter_margin_sigmas_;
    double max_adjust_;
    double input_delay_ticks_;  // ClientConfig::input_delay_ticks (unit: ticks)
    TickClock clock_{1e6 / 120};
    /// Rate adjustment: the period is scaled by 1 + adjust_ (unit: fraction).
    double adjust_ = 0;
    std::uint64_t resyncs_ = 0;
};

}  // namespace jetrace::client
