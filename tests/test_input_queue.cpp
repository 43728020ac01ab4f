// TickRing and the server's InputQueue: the acceptance rules, the per-tick
// pick and what is relayed as upcoming.
#include "jetrace/core/tick_ring.hpp"
#include "jetrace/server/input_queue.hpp"

#include <gtest/gtest.h>

using jetrace::Input;
using jetrace::server::InputQueue;
namespace jp = jetrace::proto;

namespace {

Input steer(int s) { return Input::clamped(Input::kMaxThrottle, s, 0); }

jp::InputBatch batch(std::uint32_t first, std::vector<Input> inputs) {
    jp::InputBatch b;
    b.first_tick = first;
    b.inputs = std::move(inputs);
    return b;
}

}  // namespace

TEST(TickRing, FindsOnlyTheTickItHolds) {
    jetrace::TickRing<int, 8> r;
    EXPECT_FALSE(r.has(0));
    EXPECT_FALSE(r.has(r.kNoTick));
    r.insert(3, 30);
    ASSERT_NE(r.find(3), nullptr);
    EXPECT_EQ(*r.find(3), 30);
    EXPECT_EQ(r.find(11), nullptr);  // same slot, other tick
    r.insert(11, 110);               // takes the slot over
    EXPECT_EQ(r.find(3), nullptr);
    EXPECT_EQ(*r.find(11), 110);
    r.clear();
    EXPECT_EQ(r.find(11), nullptr);
}

TEST(TickRing, SurvivesTheU32Wrap) {
    jetrace::TickRing<int, 16> r;
    r.insert(0xFFFFFFFEu, 1);
    r.insert(0, 2);  // the next-but-one tick after the wrap
    EXPECT_EQ(*r.find(0xFFFFFFFEu), 1);
    EXPECT_EQ(*r.find(0), 2);
}

TEST(InputQueue, FirstInputPerTickWinsAndConflictsAreReported) {
    InputQueue q;
    auto got = q.accept(batch(10, {steer(7), steer(3)}), 10, 240);
    EXPECT_EQ(got.late, 0u);
    EXPECT_EQ(got.conflicting_tick, jp::kNoTick);
    got = q.accept(batch(11, {steer(-15)}), 10, 240);
    EXPECT_EQ(got.conflicting_tick, 11u);
    bool missing = true;
    EXPECT_EQ(q.pick(10, 60, missing).pack(), steer(7).pack());
    EXPECT_FALSE(missing);
    EXPECT_EQ(q.pick(11, 60, missing).pack(), steer(3).pack());
    EXPECT_EQ(q.last_applied_tick(), 11u);
}

TEST(InputQueue, MissingInputsRepeatTheLastAndLateOnesAreCounted) {
    InputQueue q;
    q.accept(batch(0, {steer(7)}), 0, 240);
    bool missing = false;
    EXPECT_EQ(q.pick(0, 60, missing).pack(), steer(7).pack());
    EXPECT_EQ(q.pick(1, 60, missing).pack(), steer(7).pack());
    EXPECT_TRUE(missing);
    EXPECT_EQ(q.last_applied_tick(), 0u);
    // Tick 1 was stepped without its input: it is late; tick 0 came in time.
    const auto got = q.accept(batch(0, {steer(7), steer(15), steer(15)}), 2, 240);
    EXPECT_EQ(got.late, 1u);
}

TEST(InputQueue, ASilentClientsCarGoesNeutralAfterTheHoldAndResumesWithItsInputs) {
    InputQueue q;
    q.accept(batch(0, {steer(7)}), 0, 240);
    bool missing = false;
    EXPECT_EQ(q.pick(0, 3, missing).pack(), steer(7).pack());
    for (std::uint32_t t = 1; t <= 3; ++t) {
        EXPECT_EQ(q.pick(t, 3, missing).pack(), steer(7).pack()) << "tick " << t;
        EXPECT_TRUE(missing);
    }
    EXPECT_EQ(q.pick(4, 3, missing).pack(), Input{}.pack());  // more than 3 ticks since the last input
    EXPECT_EQ(q.pick(5, 3, missing).pack(), Input{}.pack());
    EXPECT_EQ(q.last_applied_tick(), 0u);
    q.accept(batch(6, {steer(15)}), 6, 240);
    EXPECT_EQ(q.pick(6, 3, missing).pack(), steer(15).pack());
    EXPECT_FALSE(missing);
    EXPECT_EQ(q.pick(7, 3, missing).pack(), steer(15).pack());  // held again
    // A hold of 0 ticks: nothing is repeated.
    EXPECT_EQ(q.pick(8, 0, missing).pack(), Input{}.pack());
}

TEST(InputQueue, TheLeadLimitDropsTheRestOfTheBatch) {
    InputQueue q;
    const auto got = q.accept(batch(100, std::vector<Input>(10, steer(0))), 95, 8);
    EXPECT_EQ(got.too_far_tick, 104u);
    EXPECT_EQ(got.dropped, 6u);
    EXPECT_EQ(q.newest_tick(), 103u);  // capped at the limit
    std::vector<Input> up;
    q.upcoming(100, 7, up);
    EXPECT_EQ(up.size(), 4u);
}

TEST(InputQueue, UpcomingStopsAtTheFirstGapAndAtMax) {
    InputQueue q;
    q.accept(batch(5, std::vector<Input>(3, steer(0))), 5, 240);
    q.accept(batch(9, std::vector<Input>(20, steer(0))), 5, 240);
    std::vector<Input> up;
    q.upcoming(5, 7, up);
    EXPECT_EQ(up.size(), 3u);
    up.clear();
    q.upcoming(9, 7, up);
    EXPECT_EQ(up.size(), 7u);
}

TEST(InputQueue, ResetForgetsEverything) {
    InputQueue q;
    q.accept(batch(0, {steer(7)}), 0, 240);
    bool missing = false;
    q.pick(0, 60, missing);
    q.reset();
    EXPECT_EQ(q.newest_tick(), jp::kNoTick);
    EXPECT_EQ(q.last_applied_tick(), jp::kNoTick);
    EXPECT_EQ(q.pick(0, 60, missing).pack(), Input{}.pack());
    EXPECT_TRUE(missing);
}

TEST(InputQueue, AnEmptyBatchClaimsNoTick) {
    InputQueue q;
    q.accept(batch(0, {}), 50, 240);
    EXPECT_EQ(q.newest_tick(), jp::kNoTick);
}
