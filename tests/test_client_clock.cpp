// jetrace::client::ClientClock on a time line the test owns: the lead it
// starts with, and the same lead after a resync (a client that fell behind
// the server and took a snapshot's state must get ahead again at once).
#include "jetrace/client/client_clock.hpp"
#include "jetrace/client/race_client.hpp"

#include <gtest/gtest.h>

namespace {

using jetrace::client::ClientClock;
using jetrace::client::ClientConfig;

// Ticks due at `now_us` (run at once).
int due(ClientClock& clock, std::uint64_t now_us) {
    int n = 0;
    clock.skip_backlog(now_us);
    while (clock.pop(now_us)) ++n;
    return n;
}

TEST(ClientClock, StartsAheadByTheRoundTripAndTheMargin) {
    ClientClock clock{ClientConfig{}};
    clock.set_tick_rate(120);
    // 20 ms is 2.4 ticks; with the target margin (2) and 2 ticks: 6.4
    // ticks ahead, so 7 ticks are due at once.
    clock.start(1'000'000, 20.0);
    EXPECT_EQ(due(clock, 1'000'000), 7);
    EXPECT_EQ(due(clock, 1'000'000 + 8'334), 1);
    EXPECT_EQ(clock.resyncs(), 0u);
}

TEST(ClientClock, ResyncGetsAheadAgainByTheSameLead) {
    ClientClock clock{ClientConfig{}};
    clock.set_tick_rate(120);
    clock.start(1'000'000, 20.0);
    EXPECT_EQ(due(clock, 1'000'000), 7);
    // A stall; the next snapshot is at or past the predicted tick: the
    // prediction takes the server's state and the clock resyncs.
    clock.resync(5'000'000, 20.0);
    EXPECT_EQ(clock.resyncs(), 1u);
    EXPECT_EQ(due(clock, 5'000'000), 7) << "a resync must restore the lead, not restart at the server's tick";
    // The lead is capped at 30 ticks (250 ms): the tick due now and 30 more.
    clock.resync(9'000'000, 1000.0);
    EXPECT_EQ(due(clock, 9'000'000), 31);
}

}  // namespace
