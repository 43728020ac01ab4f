// TickClock: the fixed-step clock of the server and the client.
#include "jetrace/core/tick_clock.hpp"

#include <gtest/gtest.h>

#include <cstdint>

using jetrace::TickClock;

namespace {

int pop_all(TickClock& c, std::uint64_t now_us, double rate = 1.0) {
    int n = 0;
    while (c.pop(now_us, rate)) ++n;
    return n;
}

}  // namespace

TEST(TickClock, RunsOneTickPerPeriodFromItsStart) {
    TickClock c(1e6 / 120);  // 8333 µs: the period is truncated to whole µs per tick
    c.restart(1000);
    EXPECT_EQ(pop_all(c, 999), 0);
    EXPECT_EQ(pop_all(c, 1000), 1);
    EXPECT_EQ(c.next_due_us(), 1000u + 8333u);
    // One second later: 120 ticks (the 120th falls due at 1000 + 119 * 8333).
    EXPECT_EQ(pop_all(c, 1000 + 119 * 8333), 119);
    EXPECT_EQ(pop_all(c, 1000 + 120 * 8333 - 1), 0);
}

TEST(TickClock, DropsABacklogBeyondACatchUpOfAQuarterSecond) {
    TickClock c(10000);  // 100 Hz
    c.restart(0);
    const std::uint64_t stall_end = 2'000'000;  // 2 s without an update
    c.skip_backlog(stall_end);
    EXPECT_EQ(c.next_due_us(), stall_end - TickClock::kMaxCatchUp_us);
    // 250 ms of backlog at 10 ms: 25 ticks plus the one due now.
    EXPECT_EQ(pop_all(c, stall_end), 26);
    // A short backlog is kept whole.
    c.skip_backlog(stall_end + 50000);
    EXPECT_EQ(pop_all(c, stall_end + 50000), 5);
}

TEST(TickClock, ARateStretchesOrShrinksThePeriod) {
    TickClock fast(10000);
    TickClock slow(10000);
    fast.restart(0);
    slow.restart(0);
    EXPECT_EQ(pop_all(fast, 99999, 0.5), 20);  // ticks every 5 ms
    EXPECT_EQ(pop_all(slow, 99999, 2.0), 5);   // every 20 ms
}

TEST(TickClock, BringingForwardStopsAtTimeZero) {
    TickClock c(10000);
    c.restart(30000);
    c.bring_forward(20000);
    EXPECT_EQ(c.next_due_us(), 10000u);
    c.bring_forward(50000);
    EXPECT_EQ(c.next_due_us(), 0u);
}
