#include "jetrace/client/client_clock.hpp"

#include <algorithm>

namespace jetrace::client {

namespace {

/// Input margin the server reports before it has any input from us.
constexpr std::int16_t kNoMargin = -32768;
/// Longest lead the clock starts with or jumps by (unit: ticks).
constexpr double kMaxJumpTicks = 30.0;
/// Inputs arriving later than this behind the target jump the clock instead
/// of drifting it (unit: ticks).
constexpr double kJumpBehindTicks = 6.0;
/// Rate adjustment per tick of margin error (unit: fraction/tick).
constexpr double kAdjustPerTick = 0.01;

}  // namespace

ClientClock::ClientClock(const ClientConfig& config)
    : target_margin_ticks_(config.target_margin_ticks),
      jitter_margin_sigmas_(config.jitter_margin_sigmas),
      max_adjust_(config.max_clock_adjust),
      input_delay_ticks_(config.input_delay_ticks) {}

void ClientClock::start(std::uint64_t now_us, double rtt_ms) {
    const double lead = rtt_ms * 1000.0 / clock_.period_us() + target_margin_ticks_ + 2.0;
    const auto lead_us = static_cast<std::uint64_t>(std::min(lead, kMaxJumpTicks) * clock_.period_us());
    clock_.restart(now_us);
    clock_.bring_forward(lead_us);
}

void ClientClock::resync(std::uint64_t now_us, double rtt_ms) {
    ++resyncs_;
    start(now_us, rtt_ms);
}

void ClientClock::adjust(proto::RacePhase phase, std::int16_t input_margin_ticks, double rtt_variance_ms) {
    if (phase != proto::RacePhase::countdown && phase != proto::RacePhase::racing) return;
    if (input_margin_ticks == kNoMargin) return;
    const double sigma_ticks = rtt_variance_ms * 1000.0 / clock_.period_us();
    const double target = target_margin_ticks_ + jitter_margin_sigmas_ * sigma_ticks;
    // The newest input is for the predicted tick plus the input delay: the
    // margin that the prediction itself keeps is the rest.
    const double error = input_margin_ticks - input_delay_ticks_ - target;
    if (error < -kJumpBehindTicks) {
        // Inputs arrive late: jump ahead rather than drift.
        clock_.bring_forward(static_cast<std::uint64_t>(std::min(-error, kMaxJumpTicks) * clock_.period_us()));
        ++resyncs_;
        adjust_ = 0;
        return;
    }
    adjust_ = std::clamp(kAdjustPerTick * error, -max_adjust_, max_adjust_);
}

}  // namespace jetrace::client
