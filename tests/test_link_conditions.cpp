// jetrace::net::condition_link over the in-memory network (a clock the test
// owns): both directions delayed, a stream's losses become retransmissions
// that hold back what follows, datagrams' losses are gone, a disconnection
// follows what was received before it; SequenceDelayMeter against the
// delays those rules imply; parse_conditions' errors. Random tests print
// their seed (JETRACE_TEST_SEED repeats one).
#include "jetrace/net/condition_spec.hpp"
#include "jetrace/net/link_conditions.hpp"
#include "jetrace/net/memory_transport.hpp"

#include "support/test_seed.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace {

using namespace jetrace::net;

// A datagram carrying sequence numbers first..last (8 bytes).
std::vector<std::uint8_t> numbers(std::uint32_t first, std::uint32_t last) {
    std::vector<std::uint8_t> d(8);
    std::memcpy(d.data(), &first, 4);
    std::memcpy(d.data() + 4, &last, 4);
    return d;
}

std::optional<SequenceRange> range_of(std::span<const std::uint8_t> d) {
    if (d.size() != 8) return std::nullopt;
    SequenceRange r;
    std::memcpy(&r.first, d.data(), 4);
    std::memcpy(&r.last, d.data() + 4, 4);
    return r;
}

struct Received {
    double at_ms;
    std::uint32_t last;
};

// A server end wrapped in condition_link and one client end; the client
// sends datagram i (numbers i-redundancy..i) every `every_ms`.
struct Rig {
    MemoryHub hub;
    SequenceDelayMeter meter{range_of};
    std::unique_ptr<Transport> server;
    std::unique_ptr<Transport> client;
    PeerId peer = 0;
    std::uint64_t now = 0;
    std::vector<Event> events;

    explicit Rig(const LinkConditions& link) {
        server = condition_link(hub.listen(), link, &meter);
        client = hub.connect();
        for (int i = 0; i < 10 && (peer == 0 || !client_connected); ++i) {
            tick();
            for (const Event& e : events)
                if (e.type == Event::Type::connected) peer = e.peer;
        }
    }
    void tick() {
        ++now;
        events.clear();
        std::vector<Event> at_client;
        client->service(now, at_client);
        for (const Event& e : at_client) client_connected |= e.type == Event::Type::connected;
        server->service(now, events);
    }
    bool client_connected = false;
    // Sends `count` datagrams from the client, then runs until `until_ms`;
    // what the server received, in order.
    std::vector<Received> run(std::uint32_t count, std::uint32_t every_ms, std::uint32_t redundancy,
                              std::uint64_t until_ms, Channel channel = Channel::unreliable) {
        std::vector<Received> got;
        const std::uint64_t start = now;
        while (now < until_ms) {
            const std::uint64_t since = now - start;
            if (since % every_ms == 0 && since / every_ms < count) {
                const auto i = static_cast<std::uint32_t>(since / every_ms) + 1000;
                client->send(0, channel, numbers(i > 1000 + redundancy ? i - redundancy : 1000, i));
            }
            tick();
            for (const Event& e : events) {
                if (e.type != Event::Type::received) continue;
                got.push_back({static_cast<double>(now), range_of(e.data)->last});
            }
        }
        return got;
    }
};

LinkConditions lossy(Delivery delivery, double loss, std::uint64_t seed) {
    LinkConditions l;
    l.delivery = delivery;
    l.incoming.latency_ms = l.outgoing.latency_ms = 50;
    l.incoming.loss = l.outgoing.loss = loss;
    l.incoming.retransmit_ms = l.outgoing.retransmit_ms = 125;
    l.incoming.seed = seed;
    l.outgoing.seed = seed + 1;
    return l;
}

TEST(LinkConditions, StreamLosesNothingAndHoldsBackWhatFollowsALoss) {
    const std::uint64_t seed = jetrace::test::test_seed(41);
    Rig rig(lossy(Delivery::stream, 0.05, seed));
    ASSERT_NE(rig.peer, 0u);
    const std::uint64_t start = rig.now;
    const auto got = rig.run(1000, 8, 0, start + 8000 + 5000);
    ASSERT_EQ(got.size(), 1000u) << "a stream lost a message";
    for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i].last, 1000 + i) << "out of order";
    const std::vector<double>& d = rig.meter.delays_ms();
    ASSERT_EQ(d.size(), 1000u);
    // In-memory delivery costs a tick (1 ms) beyond the 50 ms.
    EXPECT_GE(quantile(d, 0.0), 50.0);
    EXPECT_LE(quantile(d, 0.0), 52.0);
    EXPECT_GE(quantile(d, 0.99), 50.0 + 125.0 - 8.0) << "a retransmission did not hold back what followed";
    // Each of the ~50 losses holds back the ~15 messages sent while it is
    // resent: far more messages are late than were lost.
    const auto late = std::count_if(d.begin(), d.end(), [](double ms) { return ms > 60.0; });
    EXPECT_GT(late, 200);
}

TEST(LinkConditions, DatagramsLoseSomeAndRedundancyCostsOneInterval) {
    const std::uint64_t seed = jetrace::test::test_seed(43);
    Rig rig(lossy(Delivery::datagrams, 0.05, seed));
    ASSERT_NE(rig.peer, 0u);
    const std::uint64_t start = rig.now;
    const auto got = rig.run(1000, 8, 3, start + 8000 + 1000);
    EXPECT_LT(got.size(), 990u);
    EXPECT_GT(got.size(), 900u);
    const std::vector<double>& d = rig.meter.delays_ms();
    EXPECT_GE(d.size(), 995u) << "redundancy of 3 should cover nearly every loss";
    EXPECT_LE(quantile(d, 0.5), 52.0);
    // A lost datagram's numbers come with the next one, 8 ms later (two in a
    // row: 16 ms); nothing waits for a retransmission.
    EXPECT_GE(quantile(d, 1.0), 58.0);
    EXPECT_LE(quantile(d, 1.0), 50.0 + 3 * 8.0 + 2.0);
}

TEST(LinkConditions, ReliableDatagramsAreResentNotLost) {
    Rig rig(lossy(Delivery::datagrams, 0.2, jetrace::test::test_seed(47)));
    ASSERT_NE(rig.peer, 0u);
    const auto got = rig.run(200, 8, 0, rig.now + 1600 + 8000, Channel::reliable);
    ASSERT_EQ(got.size(), 200u);
    for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i].last, 1000 + i);
}

TEST(LinkConditions, OutgoingIsDelayedAndDisconnectFollowsWhatWasReceived) {
    LinkConditions l;
    l.outgoing.latency_ms = 30;
    l.incoming.latency_ms = 20;
    Rig rig(l);
    ASSERT_NE(rig.peer, 0u);
    ASSERT_TRUE(rig.server->send(rig.peer, Channel::unreliable, numbers(1, 1)));
    const std::uint64_t sent = rig.now;
    std::uint64_t arrived = 0;
    for (int i = 0; i < 100 && arrived == 0; ++i) {
        std::vector<Event> at_client;
        ++rig.now;
        rig.server->service(rig.now, rig.events);
        rig.client->service(rig.now, at_client);
        for (const Event& e : at_client)
            if (e.type == Event::Type::received) arrived = rig.now;
    }
    EXPECT_GE(arrived - sent, 30u);
    EXPECT_LE(arrived - sent, 32u);

    // Two datagrams, then the client leaves: the server sees both, then the
    // disconnection, 20 ms later.
    rig.client->send(0, Channel::unreliable, numbers(5, 5));
    rig.client->send(0, Channel::reliable, numbers(6, 6));
    rig.client->disconnect(0);
    const std::uint64_t left = rig.now;
    std::vector<Event::Type> seen;
    std::uint64_t gone_at = 0;
    for (int i = 0; i < 100 && gone_at == 0; ++i) {
        rig.tick();
        for (const Event& e : rig.events) {
            seen.push_back(e.type);
            if (e.type == Event::Type::disconnected) gone_at = rig.now;
        }
    }
    ASSERT_EQ(seen.size(), 3u);
    EXPECT_EQ(seen[0], Event::Type::received);
    EXPECT_EQ(seen[1], Event::Type::received);
    EXPECT_EQ(seen[2], Event::Type::disconnected);
    EXPECT_GE(gone_at - left, 20u);
}

TEST(SequenceDelayMeter, FirstArrivalToFirstHandOnPerPeer) {
    SequenceDelayMeter m(range_of);
    m.arrived(1, 0, numbers(3010, 3012));
    m.arrived(2, 0, numbers(3010, 3010));
    m.arrived(1, 5, numbers(3011, 3013));     // 3011, 3012 already arrived at 0
    m.delivered(1, 40, numbers(3011, 3013));  // 3010 comes later than 3011: not measured
    m.delivered(1, 45, numbers(3010, 3012));  // older: nothing new
    m.delivered(2, 7, numbers(3010, 3010));
    EXPECT_EQ(m.delays_ms(), (std::vector<double>{40, 40, 35, 7}));
    EXPECT_EQ(m.skipped(), 0u);
    m.delivered(1, 60, numbers(3015, 3015));  // 3014 never handed on
    EXPECT_EQ(m.skipped(), 1u);
    // A new race: ticks from 0 again.
    m.arrived(1, 100, numbers(0, 1));
    m.delivered(1, 150, numbers(0, 1));
    EXPECT_EQ(m.delays_ms().back(), 50);
    EXPECT_EQ(m.delays_ms().size(), 6u);
    // A race that ended at tick 400 and one that starts at 0: the old
    // first arrivals of ticks 0..400 must not be taken for the new ones.
    SequenceDelayMeter r(range_of);
    for (std::uint32_t t = 0; t <= 400; ++t) r.arrived(3, t, numbers(t, t));
    for (std::uint32_t t = 0; t <= 400; ++t) r.delivered(3, t + 10.0, numbers(t, t));
    r.arrived(3, 1000, numbers(0, 2));
    r.delivered(3, 1020, numbers(0, 2));
    EXPECT_EQ(r.delays_ms().back(), 20) << "a new race's ticks measured against the last race's arrivals";
}

TEST(ConditionSpec, ParsesKnownNamesAndRejectsTheRest) {
    Conditions c;
    std::string error;
    ASSERT_TRUE(parse_conditions("latency=50,loss=0.05,retransmit=125", c, error)) << error;
    EXPECT_EQ(c.latency_ms, 50);
    EXPECT_EQ(c.loss, 0.05);
    EXPECT_EQ(c.retransmit_ms, 125);
    for (const char* bad : {"latency", "latency=", "latency=nan", "latency=inf", "loss=1.5", "loss=-0.1",
                            "speed=3", "latency=5,latency=6", "latency=5x", ",", "latency=1e999"}) {
        Conditions d;
        error.clear();
        EXPECT_FALSE(parse_conditions(bad, d, error)) << bad;
        EXPECT_FALSE(error.empty()) << bad;
        EXPECT_EQ(d.latency_ms, 0) << bad << ": a failed parse changed the conditions";
    }
    Conditions e;
    EXPECT_TRUE(parse_conditions("", e, error));
}

}  // namespace
