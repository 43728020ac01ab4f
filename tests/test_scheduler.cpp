// jetrace::net::DatagramScheduler on a clock the test owns: latency and
// jitter bounds, loss, duplication, reordering, the token bucket, reliable
// datagrams, barriers, determinism. Random tests print their seed
// (JETRACE_TEST_SEED repeats one).
#include "jetrace/net/scheduler.hpp"

#include "support/test_seed.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <vector>

namespace {

using jetrace::net::Conditions;
using jetrace::net::DatagramScheduler;
using jetrace::net::ScheduledDatagram;

ScheduledDatagram datagram(std::uint64_t flow, std::uint64_t id, bool reliable = false, std::size_t bytes = 16) {
    ScheduledDatagram d;
    d.flow = flow;
    d.reliable = reliable;
    d.tag = 7;
    d.data.assign(std::max<std::size_t>(bytes, 8), 0);
    std::memcpy(d.data.data(), &id, 8);
    return d;
}

std::uint64_t id_of(const ScheduledDatagram& d) {
    std::uint64_t id = 0;
    std::memcpy(&id, d.data.data(), 8);
    return id;
}

struct Send {
    double at_ms;
    ScheduledDatagram d;
};
struct Arrival {
    double at_ms;
    std::uint64_t flow;
    std::uint64_t id;
    bool reliable;
    std::size_t bytes;
    bool operator==(const Arrival&) const = default;
};

// Pushes each send at its time and pops every `step_ms` until `until_ms`.
std::vector<Arrival> run(DatagramScheduler& s, std::vector<Send> sends, double step_ms, double until_ms) {
    std::vector<Arrival> out;
    std::vector<ScheduledDatagram> due;
    std::size_t next = 0;
    for (double now = 0; now <= until_ms; now += step_ms) {
        while (next < sends.size() && sends[next].at_ms <= now) {
            s.push(now, std::move(sends[next].d));
            ++next;
        }
        due.clear();
        s.pop_due(now, due);
        for (const auto& d : due) {
            EXPECT_EQ(d.tag, 7u);
            out.push_back({now, d.flow, id_of(d), d.reliable, d.data.size()});
        }
    }
    return out;
}

// n unreliable datagrams of `bytes` on flow 1, one every `every_ms`.
std::vector<Send> stream(std::size_t n, double every_ms, std::size_t bytes = 16, std::uint64_t flow = 1) {
    std::vector<Send> sends;
    for (std::size_t i = 0; i < n; ++i) sends.push_back({static_cast<double>(i) * every_ms, datagram(flow, i, false, bytes)});
    return sends;
}

TEST(Scheduler, NoConditionsReleasesAtOnceInOrder) {
    DatagramScheduler s(Conditions{});
    const auto got = run(s, stream(100, 1.0), 1.0, 200);
    ASSERT_EQ(got.size(), 100u);
    for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].id, i);
        EXPECT_EQ(got[i].at_ms, static_cast<double>(i));
    }
    EXPECT_EQ(s.stats().offered, 100u);
    EXPECT_EQ(s.stats().released, 100u);
    EXPECT_EQ(s.stats().delayed, 0u);
    EXPECT_EQ(s.pending(), 0u);
    EXPECT_EQ(s.next_due_ms(), std::numeric_limits<double>::infinity());
}

TEST(Scheduler, LatencyAndJitterStayInBounds) {
    Conditions c;
    c.latency_ms = 40;
    c.jitter_ms = 20;
    c.seed = jetrace::test::test_seed(11);
    DatagramScheduler s(c);
    const auto got = run(s, stream(2000, 0.5), 0.25, 1200);
    ASSERT_EQ(got.size(), 2000u);
    double sum = 0;
    bool out_of_order = false;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const double delay = got[i].at_ms - 0.5 * static_cast<double>(got[i].id);
        EXPECT_GE(delay, 40.0) << "datagram " << got[i].id;
        EXPECT_LE(delay, 60.25) << "datagram " << got[i].id;
        sum += delay;
        if (i > 0 && got[i].id < got[i - 1].id) out_of_order = true;
    }
    EXPECT_NEAR(sum / 2000.0, 50.0 + 0.125, 1.0);  // uniform jitter: mean 10, plus half a step
    EXPECT_TRUE(out_of_order) << "20 ms of jitter on datagrams 0.5 ms apart must reorder some";
    EXPECT_EQ(s.stats().delayed, 2000u);
}

TEST(Scheduler, LossMatchesItsProbability) {
    Conditions c;
    c.loss = 0.05;
    c.seed = jetrace::test::test_seed(12);
    DatagramScheduler s(c);
    const auto got = run(s, stream(20000, 0.1), 0.1, 2001);
    // Binomial(20000, 0.05): mean 1000, standard deviation 31.
    EXPECT_GT(s.stats().dropped, 860u);
    EXPECT_LT(s.stats().dropped, 1140u);
    EXPECT_EQ(got.size(), 20000u - s.stats().dropped);
    EXPECT_EQ(s.stats().released, got.size());
}

TEST(Scheduler, CertainDuplicationAndReordering) {
    Conditions dup;
    dup.duplicate = 1.0;
    DatagramScheduler d(dup);
    std::map<std::uint64_t, int> copies;
    for (const Arrival& a : run(d, stream(50, 1.0), 1.0, 100)) ++copies[a.id];
    ASSERT_EQ(copies.size(), 50u);
    for (const auto& [id, n] : copies) EXPECT_EQ(n, 2) << id;
    EXPECT_EQ(d.stats().duplicated, 50u);

    Conditions reorder;
    reorder.reorder = 1.0;
    DatagramScheduler r(reorder);
    const auto got = run(r, stream(10, 1.0), 1.0, 300);
    std::vector<std::uint64_t> ids;
    for (const Arrival& a : got) ids.push_back(a.id);
    EXPECT_EQ(ids, (std::vector<std::uint64_t>{1, 0, 3, 2, 5, 4, 7, 6, 9, 8}));
    EXPECT_EQ(r.stats().reordered, 5u);
}

TEST(Scheduler, HeldDatagramWithoutSuccessorLeavesAfterTheHoldLimit) {
    Conditions c;
    c.reorder = 1.0;
    c.latency_ms = 10;
    DatagramScheduler s(c);
    s.push(0, datagram(1, 5));
    EXPECT_EQ(s.pending(), 1u);
    EXPECT_EQ(s.next_due_ms(), 10 + DatagramScheduler::kMaxHoldMs);
    std::vector<ScheduledDatagram> due;
    s.pop_due(109, due);
    EXPECT_TRUE(due.empty());
    s.pop_due(110, due);
    ASSERT_EQ(due.size(), 1u);
    EXPECT_EQ(id_of(due[0]), 5u);
    EXPECT_EQ(s.stats().reordered, 0u);
}

TEST(Scheduler, ReliableDatagramsAreNeverDroppedDuplicatedOrReordered) {
    Conditions c;
    c.latency_ms = 5;
    c.jitter_ms = 50;
    c.loss = 1.0;
    c.duplicate = 1.0;
    c.reorder = 1.0;
    c.rate_kbps = 8;  // 1 byte per ms: a 16-byte datagram takes 16 ms
    c.burst_bytes = 16;
    c.seed = jetrace::test::test_seed(13);
    DatagramScheduler s(c);
    std::vector<Send> sends;
    for (std::uint64_t i = 0; i < 200; ++i) sends.push_back({static_cast<double>(i), datagram(i % 2, i, i % 4 < 2)});
    const auto got = run(s, std::move(sends), 1.0, 5000);
    std::map<std::uint64_t, std::vector<std::uint64_t>> per_flow;
    for (const Arrival& a : got) {
        ASSERT_TRUE(a.reliable) << "an unreliable datagram passed with loss 1";
        per_flow[a.flow].push_back(a.id);
    }
    ASSERT_EQ(per_flow.size(), 2u);
    for (const auto& [flow, ids] : per_flow) {
        EXPECT_EQ(ids.size(), 50u) << "flow " << flow;
        EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end())) << "flow " << flow;
    }
    // Each flow's link sends 16 bytes per 16 ms: the 50th reliable datagram
    // of a flow cannot leave before 49 * 16 ms.
    EXPECT_GE(got.back().at_ms, 49 * 16.0);
    EXPECT_EQ(s.stats().dropped, 100u);
    EXPECT_EQ(s.stats().duplicated, 0u);
}

// The stream model: a "lost" reliable datagram is resent a retransmission
// later, and every later one of its flow waits behind it (head-of-line
// blocking); nothing is dropped and the order holds.
TEST(Scheduler, RetransmissionHoldsBackTheRestOfTheStream) {
    Conditions c;
    c.latency_ms = 50;
    c.loss = 0.05;
    c.retransmit_ms = 125;
    c.seed = jetrace::test::test_seed(29);
    DatagramScheduler s(c);
    std::vector<Send> sends;
    for (std::uint64_t i = 0; i < 2000; ++i) sends.push_back({static_cast<double>(i) * 8.0, datagram(1, i, true)});
    const auto got = run(s, std::move(sends), 1.0, 2000 * 8.0 + 20000);
    ASSERT_EQ(got.size(), 2000u) << "a reliable datagram was lost";
    std::size_t late = 0;
    double worst = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_EQ(got[i].id, i) << "out of order";
        const double delay = got[i].at_ms - static_cast<double>(i) * 8.0;
        ASSERT_GE(delay, 50.0);
        worst = std::max(worst, delay);
        if (delay > 60.0) ++late;
    }
    const auto resent = s.stats().retransmitted;
    // About 5 % are resent; each holds back the ~15 sent during its 125 ms.
    EXPECT_GT(resent, 60u);
    EXPECT_LT(resent, 150u);
    EXPECT_GT(late, resent * 5) << "the datagrams behind a resent one did not wait";
    EXPECT_GE(worst, 175.0);
    EXPECT_EQ(s.stats().dropped, 0u);

    // Without retransmit_ms reliable datagrams pass untouched by loss.
    c.retransmit_ms = 0;
    DatagramScheduler plain(c);
    std::vector<Send> again;
    for (std::uint64_t i = 0; i < 100; ++i) again.push_back({static_cast<double>(i), datagram(1, i, true)});
    for (const Arrival& a : run(plain, std::move(again), 1.0, 500)) EXPECT_EQ(a.at_ms, static_cast<double>(a.id) + 50);
    EXPECT_EQ(plain.stats().retransmitted, 0u);
}

TEST(Scheduler, RateLimitsThroughputAndBoundsTheQueue) {
    Conditions c;
    c.rate_kbps = 800;  // 100 bytes per ms
    c.burst_bytes = 3000;
    c.rate_queue_ms = 50;
    DatagramScheduler s(c);
    // Twice the link's rate for 10 s: 1000 bytes every 5 ms.
    const auto got = run(s, stream(2000, 5.0, 1000), 0.5, 10100);
    double bytes = 0, worst_wait = 0;
    for (const Arrival& a : got) {
        bytes += static_cast<double>(a.bytes);
        worst_wait = std::max(worst_wait, a.at_ms - 5.0 * static_cast<double>(a.id));
    }
    const double last = got.back().at_ms;
    EXPECT_NEAR(bytes / last, 100.0, 3.0) << "bytes per ms through an 800 kbit/s link";
    EXPECT_NEAR(static_cast<double>(s.stats().rate_limited), 1000.0, 40.0);
    EXPECT_EQ(got.size() + s.stats().rate_limited, 2000u);
    EXPECT_LE(worst_wait, 50.5) << "a datagram waited longer than rate_queue_ms";
}

TEST(Scheduler, RateBelowCapacityOnlyDelaysBursts) {
    Conditions c;
    c.rate_kbps = 800;  // 100 bytes per ms
    c.burst_bytes = 3000;
    DatagramScheduler s(c);
    // Three 1000-byte datagrams at once fit the bucket; the fourth waits 10 ms.
    s.push(0, datagram(1, 0, false, 1000));
    s.push(0, datagram(1, 1, false, 1000));
    s.push(0, datagram(1, 2, false, 1000));
    s.push(0, datagram(1, 3, false, 1000));
    std::vector<ScheduledDatagram> due;
    s.pop_due(0, due);
    EXPECT_EQ(due.size(), 3u);
    EXPECT_EQ(s.next_due_ms(), 10.0);
    s.pop_due(10, due);
    EXPECT_EQ(due.size(), 4u);

    // Half the rate, steadily: nothing dropped, each leaves when it comes.
    DatagramScheduler steady(c);
    const auto got = run(steady, stream(1000, 20.0, 1000), 1.0, 20100);
    ASSERT_EQ(got.size(), 1000u);
    for (const Arrival& a : got) EXPECT_EQ(a.at_ms, 20.0 * static_cast<double>(a.id));
    EXPECT_EQ(steady.stats().rate_limited, 0u);
}

TEST(Scheduler, EachFlowHasItsOwnLink) {
    Conditions c;
    c.rate_kbps = 80;  // 10 bytes per ms
    c.burst_bytes = 100;
    c.rate_queue_ms = 1000;
    DatagramScheduler s(c);
    std::vector<Send> sends;
    for (std::uint64_t i = 0; i < 20; ++i) {
        sends.push_back({0, datagram(1, i, false, 100)});
        sends.push_back({0, datagram(2, 100 + i, false, 100)});
    }
    const auto got = run(s, std::move(sends), 1.0, 1000);
    ASSERT_EQ(got.size(), 40u);
    std::map<std::uint64_t, double> last;
    for (const Arrival& a : got) last[a.flow] = std::max(last[a.flow], a.at_ms);
    // 20 datagrams of 100 bytes at 10 bytes/ms, the first from the full bucket.
    EXPECT_EQ(last[1], 190.0);
    EXPECT_EQ(last[2], 190.0);
}

TEST(Scheduler, SameSeedSameOutcomeOtherSeedOther) {
    Conditions c;
    c.latency_ms = 20;
    c.jitter_ms = 15;
    c.loss = 0.2;
    c.duplicate = 0.2;
    c.reorder = 0.2;
    c.rate_kbps = 400;
    c.seed = jetrace::test::test_seed(42);
    const auto once = [&](const Conditions& conditions) {
        DatagramScheduler s(conditions);
        std::vector<Send> sends;
        for (std::uint64_t i = 0; i < 600; ++i)
            sends.push_back({static_cast<double>(i) * 0.7, datagram(i % 3, i, i % 5 == 0, 40 + i % 300)});
        return run(s, std::move(sends), 0.5, 2000);
    };
    const auto a = once(c);
    EXPECT_EQ(a, once(c));
    c.seed += 1;
    EXPECT_NE(a, once(c));
}

TEST(Scheduler, BarrierFollowsEverythingQueuedAndForgetDiscardsAFlow) {
    Conditions c;
    c.latency_ms = 10;
    c.jitter_ms = 30;
    c.reorder = 0.5;
    c.seed = jetrace::test::test_seed(14);
    DatagramScheduler s(c);
    for (std::uint64_t i = 0; i < 20; ++i) s.push(0, datagram(1, i, i % 2 == 0));
    for (std::uint64_t i = 0; i < 5; ++i) s.push(0, datagram(2, 100 + i));
    ScheduledDatagram marker = datagram(1, 999, true);
    s.push_barrier(1, std::move(marker));
    s.forget(2);
    std::vector<ScheduledDatagram> due;
    for (double now = 0; now < 500; now += 1) s.pop_due(now, due);
    ASSERT_EQ(due.size(), 21u) << "flow 2 was forgotten; flow 1 has 20 datagrams and the barrier";
    EXPECT_EQ(id_of(due.back()), 999u);
    for (const auto& d : due) EXPECT_EQ(d.flow, 1u);
    EXPECT_EQ(s.pending(), 0u);
}

TEST(Scheduler, NonsenseConditionsAreClamped) {
    Conditions c;
    c.latency_ms = std::numeric_limits<double>::quiet_NaN();
    c.jitter_ms = -5;
    c.loss = -1;
    c.duplicate = 7;
    c.reorder = std::numeric_limits<double>::infinity();
    c.rate_kbps = -100;
    DatagramScheduler s(c);
    EXPECT_EQ(s.conditions().latency_ms, 0.0);
    EXPECT_EQ(s.conditions().jitter_ms, 0.0);
    EXPECT_EQ(s.conditions().loss, 0.0);
    EXPECT_EQ(s.conditions().duplicate, 1.0);
    EXPECT_EQ(s.conditions().reorder, 0.0);
    EXPECT_EQ(s.conditions().rate_kbps, 0.0);
    const auto got = run(s, stream(10, 1.0), 1.0, 20);
    EXPECT_EQ(got.size(), 20u);
}

}  // namespace
