// The fixed-step clock the server and the client step the core on.
#pragma once

#include <cstdint>

namespace jetrace {

/// A fixed-step clock driven by the caller's time: it has no clock of its
/// own (the caller passes now_us), so tests drive it with any time line.
/// Ticks more than kMaxCatchUp_us behind are skipped rather than run in one
/// burst.
class TickClock {
public:
    /// Longest backlog run after a stall (unit: µs).
    static constexpr std::uint64_t kMaxCatchUp_us = 250000;

    /// period_us: time between ticks at rate 1 (unit: µs).
    explicit TickClock(double period_us) : period_us_(period_us) {}

    void set_period(double period_us) { period_us_ = period_us; }
    double period_us() const { return period_us_; }

    /// The next tick falls due at t_us (unit: µs).
    void restart(std::uint64_t t_us) { next_us_ = t_us; }
    std::uint64_t next_due_us() const { return next_us_; }
    /// Brings the next tick forward by `us`, not before time 0 (unit: µs).
    void bring_forward(std::uint64_t us) { next_us_ = next_us_ > us ? next_us_ - us : 0; }

    /// Called once per update before pop(): a backlog beyond kMaxCatchUp_us
    /// is dropped.
    void skip_backlog(std::uint64_t now_us) {
        if (now_us > next_us_ + kMaxCatchUp_us) next_us_ = now_us - kMaxCatchUp_us;
    }

    /// True when a tick is due at now_us; the one after it is then scheduled
    /// one period later, the period scaled by `rate` (1 + a clock adjustment).
    bool pop(std::uint64_t now_us, double rate = 1.0) {
        if (now_us < next_us_) return false;
        next_us_ += static_cast<std::uint64_t>(period_us_ * rate);
        return true;
    }

private:
    double period_us_;
    std::uint64_t next_us_ = 0;
};

}  // namespace jetrace
