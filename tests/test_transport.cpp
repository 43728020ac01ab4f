// jetrace::net: the ENet transport over 127.0.0.1 and the network conditioner.
// Every wait is bounded in wall time, so a failure never hangs the suite.
#include "jetrace/net/transport.hpp"
#include "support/scripted_transport.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace jetrace::net;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

std::uint64_t now_ms() {
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now().time_since_epoch()).count());
}

std::vector<std::uint8_t> u64_bytes(std::uint64_t a, std::uint64_t b = 0) {
    std::vector<std::uint8_t> out(16);
    std::memcpy(out.data(), &a, 8);
    std::memcpy(out.data() + 8, &b, 8);
    return out;
}
std::uint64_t first_u64(const std::vector<std::uint8_t>& d) {
    std::uint64_t v = 0;
    if (d.size() >= 8) std::memcpy(&v, d.data(), 8);
    return v;
}
std::uint64_t second_u64(const std::vector<std::uint8_t>& d) {
    std::uint64_t v = 0;
    if (d.size() >= 16) std::memcpy(&v, d.data() + 8, 8);
    return v;
}

// One transport plus everything it reported, with the time it was reported.
struct End {
    std::unique_ptr<Transport> t;
    std::vector<Event> events;
    std::vector<std::uint64_t> times;
    std::uint64_t last_service_ms = 0;

    void service() {
        const std::uint64_t now = now_ms();
        last_service_ms = now;
        t->service(now, events);
        times.resize(events.size(), now);
    }
    std::size_t count(Event::Type type) const {
        return static_cast<std::size_t>(
            std::count_if(events.begin(), events.end(), [&](const Event& e) { return e.type == type; }));
    }
    std::vector<std::uint64_t> received(Channel channel) const {
        std::vector<std::uint64_t> out;
        for (const Event& e : events) {
            if (e.type == Event::Type::received && e.channel == channel) out.push_back(first_u64(e.data));
        }
        return out;
    }
    PeerId first_peer(Event::Type type) const {
        for (const Event& e : events) {
            if (e.type == type) return e.peer;
        }
        return ~PeerId{0};
    }
};

// Services `ends` every millisecond until done() holds or max_ms passes.
bool pump(std::initializer_list<End*> ends, const std::function<bool()>& done, int max_ms = 5000) {
    const auto deadline = Clock::now() + std::chrono::milliseconds(max_ms);
    for (;;) {
        for (End* e : ends) e->service();
        if (done()) return true;
        if (Clock::now() >= deadline) return false;
        std::this_thread::sleep_for(1ms);
    }
}

End make_server(std::size_t max_connections = 8, std::uint32_t timeout_ms = 3000) {
    ServerConfig config;
    config.bind = "127.0.0.1";
    config.port = 0;
    config.max_connections = max_connections;
    config.timeout_ms = timeout_ms;
    std::string error;
    End end;
    end.t = listen_enet(config, error);
    EXPECT_TRUE(end.t) << error;
    if (end.t) {
        EXPECT_NE(end.t->local_port(), 0);
    }
    return end;
}

End make_client(std::uint16_t port, std::uint32_t timeout_ms = 3000) {
    std::string error;
    End end;
    end.t = connect_enet("127.0.0.1", port, timeout_ms, error);
    EXPECT_TRUE(end.t) << error;
    return end;
}

// A server and a client (optionally conditioned), connected.
struct Link {
    End server;
    End client;
    PeerId client_id = 0;  // the client as the server names it
};

void connect_link(Link& link, const Conditions* client_conditions = nullptr) {
    link.server = make_server();
    ASSERT_TRUE(link.server.t);
    link.client = make_client(link.server.t->local_port());
    ASSERT_TRUE(link.client.t);
    if (client_conditions != nullptr) link.client.t = condition(std::move(link.client.t), *client_conditions);
    ASSERT_TRUE(pump({&link.server, &link.client}, [&] {
        return link.server.count(Event::Type::connected) == 1 && link.client.count(Event::Type::connected) == 1;
    }));
    EXPECT_EQ(link.client.first_peer(Event::Type::connected), 0u);
    link.client_id = link.server.first_peer(Event::Type::connected);
}

TEST(EnetTransport, ConnectsExchangesBothWaysAndDisconnects) {
    Link link;
    connect_link(link);
    End& server = link.server;
    End& client = link.client;
    EXPECT_NE(client.t->local_port(), 0);
    EXPECT_NE(client.t->local_port(), server.t->local_port());

    EXPECT_TRUE(client.t->send(0, Channel::reliable, u64_bytes(11)));
    EXPECT_TRUE(server.t->send(link.client_id, Channel::reliable, u64_bytes(21)));
    // Unreliable: resent until seen, should loopback ever lose one.
    ASSERT_TRUE(pump({&server, &client}, [&] {
        if (server.received(Channel::unreliable).empty()) client.t->send(0, Channel::unreliable, u64_bytes(12));
        if (client.received(Channel::unreliable).empty())
            server.t->send(link.client_id, Channel::unreliable, u64_bytes(22));
        return !server.received(Channel::unreliable).empty() && !client.received(Channel::unreliable).empty() &&
               !server.received(Channel::reliable).empty() && !client.received(Channel::reliable).empty();
    }));
    EXPECT_EQ(server.received(Channel::reliable), std::vector<std::uint64_t>{11});
    EXPECT_EQ(client.received(Channel::reliable), std::vector<std::uint64_t>{21});
    EXPECT_EQ(server.received(Channel::unreliable).front(), 12u);
    EXPECT_EQ(client.received(Channel::unreliable).front(), 22u);
    for (const Event& e : server.events) EXPECT_EQ(e.peer, link.client_id);
    for (const Event& e : client.events) EXPECT_EQ(e.peer, 0u);

    // Unknown peers, too large datagrams; an empty one is fine.
    EXPECT_FALSE(client.t->send(7, Channel::reliable, u64_bytes(1)));
    EXPECT_FALSE(server.t->send(link.client_id + 100, Channel::unreliable, u64_bytes(1)));
    EXPECT_FALSE(server.t->send(link.client_id, Channel::reliable, std::vector<std::uint8_t>(64 * 1024 + 1)));
    EXPECT_TRUE(server.t->send(link.client_id, Channel::reliable, std::vector<std::uint8_t>(64 * 1024)));
    EXPECT_TRUE(server.t->send(link.client_id, Channel::reliable, std::vector<std::uint8_t>{}));
    ASSERT_TRUE(pump({&server, &client}, [&] { return client.received(Channel::reliable).size() == 3; }));
    EXPECT_EQ(client.events.back().data.size(), 0u);

    // A large unreliable datagram travels as unreliable fragments and arrives whole.
    std::vector<std::uint8_t> big(5000);
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<std::uint8_t>(i * 7);
    ASSERT_TRUE(pump({&server, &client}, [&] {
        const auto it = std::find_if(server.events.begin(), server.events.end(),
                                     [](const Event& e) { return e.data.size() == 5000; });
        if (it == server.events.end()) {
            client.t->send(0, Channel::unreliable, big);
            return false;
        }
        EXPECT_EQ(it->channel, Channel::unreliable);
        EXPECT_EQ(it->data, big);
        return true;
    }));

    client.t->disconnect(0);
    ASSERT_TRUE(pump({&server, &client}, [&] {
        return server.count(Event::Type::disconnected) == 1 && client.count(Event::Type::disconnected) == 1;
    }));
    EXPECT_EQ(server.first_peer(Event::Type::disconnected), link.client_id);
    EXPECT_EQ(client.first_peer(Event::Type::disconnected), 0u);
    EXPECT_FALSE(client.t->send(0, Channel::reliable, u64_bytes(1)));
    EXPECT_FALSE(server.t->send(link.client_id, Channel::reliable, u64_bytes(1)));
}

TEST(EnetTransport, ServerDisconnectReachesClientAndIdsAreNotReused) {
    Link link;
    connect_link(link);
    link.server.t->disconnect(link.client_id);
    ASSERT_TRUE(pump({&link.server, &link.client}, [&] {
        return link.server.count(Event::Type::disconnected) == 1 && link.client.count(Event::Type::disconnected) == 1;
    }));
    End second = make_client(link.server.t->local_port());
    ASSERT_TRUE(pump({&link.server, &second}, [&] { return link.server.count(Event::Type::connected) == 2; }));
    EXPECT_NE(link.server.events.back().peer, link.client_id);
}

TEST(EnetTransport, TotalsGrowAndRttIsMeasured) {
    Link link;
    connect_link(link);
    const Totals c0 = link.client.t->totals();
    const Totals s0 = link.server.t->totals();
    EXPECT_GT(c0.bytes_sent, 0u);  // the handshake
    EXPECT_GT(s0.packets_received, 0u);
    std::uint64_t sent = 0;
    ASSERT_TRUE(pump({&link.server, &link.client}, [&] {
        ++sent;
        link.client.t->send(0, Channel::reliable, u64_bytes(sent));
        link.server.t->send(link.client_id, Channel::reliable, u64_bytes(sent));
        return sent >= 200 && link.server.received(Channel::reliable).size() >= 200 &&
               link.client.received(Channel::reliable).size() >= 200;
    }));
    const Totals c1 = link.client.t->totals();
    const Totals s1 = link.server.t->totals();
    EXPECT_GT(c1.bytes_sent, c0.bytes_sent + 200 * 16);  // payload plus ENet headers
    EXPECT_GT(c1.bytes_received, c0.bytes_received + 200 * 16);
    EXPECT_GT(c1.packets_sent, c0.packets_sent);
    EXPECT_GT(c1.packets_received, c0.packets_received);
    EXPECT_GT(s1.bytes_sent, s0.bytes_sent + 200 * 16);
    EXPECT_GT(s1.packets_received, s0.packets_received);
    const PeerStats cs = link.client.t->peer_stats(0);
    const PeerStats ss = link.server.t->peer_stats(link.client_id);
    EXPECT_GT(cs.rtt_ms, 0.0);
    EXPECT_LT(cs.rtt_ms, 500.0);  // below ENet's initial guess: measured
    EXPECT_GT(ss.rtt_ms, 0.0);
    EXPECT_LT(ss.rtt_ms, 500.0);
    EXPECT_EQ(link.server.t->peer_stats(link.client_id + 100).rtt_ms, 0.0);
}

TEST(EnetTransport, ConnectionBeyondMaxConnectionsFails) {
    End server = make_server(2);
    ASSERT_TRUE(server.t);
    End a = make_client(server.t->local_port(), 600);
    End b = make_client(server.t->local_port(), 600);
    End c = make_client(server.t->local_port(), 600);
    auto outcome = [](const End& e) {
        return e.count(Event::Type::connected) + e.count(Event::Type::disconnected);
    };
    ASSERT_TRUE(pump({&server, &a, &b, &c}, [&] { return outcome(a) + outcome(b) + outcome(c) == 3; }, 3000));
    const std::size_t connected =
        a.count(Event::Type::connected) + b.count(Event::Type::connected) + c.count(Event::Type::connected);
    EXPECT_EQ(connected, 2u);
    EXPECT_EQ(server.count(Event::Type::connected), 2u);
    EXPECT_EQ(server.count(Event::Type::disconnected), 0u);
}

TEST(EnetTransport, ConnectingToNothingTimesOut) {
    std::uint16_t port = 0;
    {
        End probe = make_server();
        ASSERT_TRUE(probe.t);
        port = probe.t->local_port();
    }
    End client = make_client(port, 300);
    ASSERT_TRUE(client.t);
    EXPECT_EQ(client.t->peer_stats(0).rtt_ms, 0.0);  // nothing measured yet
    EXPECT_FALSE(client.t->send(0, Channel::reliable, u64_bytes(1)));  // not connected yet
    const auto start = Clock::now();
    ASSERT_TRUE(pump({&client}, [&] { return client.count(Event::Type::disconnected) == 1; }, 2000));
    EXPECT_LT(Clock::now() - start, 1000ms);
    EXPECT_EQ(client.count(Event::Type::connected), 0u);
    EXPECT_EQ(client.first_peer(Event::Type::disconnected), 0u);
}

TEST(EnetTransport, SilentPeerIsDroppedWithinTimeout) {
    End server = make_server(4, 600);
    ASSERT_TRUE(server.t);
    End client = make_client(server.t->local_port());
    ASSERT_TRUE(pump({&server, &client}, [&] { return server.count(Event::Type::connected) == 1; }));
    const auto start = Clock::now();  // the client stops answering from here on
    ASSERT_TRUE(pump({&server}, [&] { return server.count(Event::Type::disconnected) == 1; }, 6000));
    // Dropped by the 600 ms timeout, not by ENet's default of 5 s or more
    // (generous: the shared CI machine can stall this process for a while).
    EXPECT_LT(Clock::now() - start, 3000ms);
}

TEST(EnetTransport, BindFailuresGiveNullAndAMessage) {
    End first = make_server();
    ASSERT_TRUE(first.t);
    ServerConfig config;
    config.bind = "127.0.0.1";
    config.port = first.t->local_port();
    std::string error;
    EXPECT_FALSE(listen_enet(config, error));
    EXPECT_NE(error.find(std::to_string(config.port)), std::string::npos) << error;

    config.bind = "192.0.2.1";  // TEST-NET-1: not an address of this machine
    config.port = 0;
    error.clear();
    EXPECT_FALSE(listen_enet(config, error));
    EXPECT_NE(error.find("192.0.2.1"), std::string::npos) << error;

    config.bind = "127.0.0.1";
    config.max_connections = 0;
    error.clear();
    EXPECT_FALSE(listen_enet(config, error));
    EXPECT_FALSE(error.empty());

    error.clear();
    EXPECT_FALSE(connect_enet("127.0.0.1", 0, 1000, error));
    EXPECT_FALSE(error.empty());
}

// --- conditioner over real ENet (conditions on the client's sending side) ---

TEST(Conditioner, LatencyDelaysReliableMessagesInOrder) {
    Conditions conditions;
    conditions.latency_ms = 50;
    Link link;
    connect_link(link, &conditions);
    for (std::uint64_t i = 0; i < 20; ++i) {
        link.client.service();  // the conditioner's clock is that of its latest service()
        ASSERT_TRUE(link.client.t->send(0, Channel::reliable, u64_bytes(i, link.client.last_service_ms)));
        link.server.service();
        std::this_thread::sleep_for(2ms);
    }
    ASSERT_TRUE(pump({&link.server, &link.client}, [&] { return link.server.received(Channel::reliable).size() == 20; }));
    std::vector<std::uint64_t> expected(20);
    for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = i;
    EXPECT_EQ(link.server.received(Channel::reliable), expected);
    for (std::size_t i = 0; i < link.server.events.size(); ++i) {
        const Event& e = link.server.events[i];
        if (e.type != Event::Type::received) continue;
        EXPECT_GE(link.server.times[i], second_u64(e.data) + 50) << "message " << first_u64(e.data);
    }
    EXPECT_EQ(conditioner_stats(*link.client.t).delayed, 20u);
    EXPECT_EQ(conditioner_stats(*link.server.t).delayed, 0u);  // not a conditioner
}

// Sends `unreliable` + `reliable` numbered datagrams from the client in
// batches, then waits for every reliable one (plus a short grace period).
void blast(Link& link, std::uint64_t unreliable, std::uint64_t reliable) {
    const std::uint64_t rounds = 20;
    for (std::uint64_t r = 0; r < rounds; ++r) {
        link.client.service();
        for (std::uint64_t i = r * unreliable / rounds; i < (r + 1) * unreliable / rounds; ++i)
            ASSERT_TRUE(link.client.t->send(0, Channel::unreliable, u64_bytes(i)));
        for (std::uint64_t i = r * reliable / rounds; i < (r + 1) * reliable / rounds; ++i)
            ASSERT_TRUE(link.client.t->send(0, Channel::reliable, u64_bytes(i)));
        link.client.t->flush();
        link.server.service();
        std::this_thread::sleep_for(2ms);
    }
    ASSERT_TRUE(pump({&link.server, &link.client},
                     [&] { return link.server.received(Channel::reliable).size() >= reliable; }));
    pump({&link.server, &link.client}, [] { return false; }, 100);
    std::vector<std::uint64_t> expected(reliable);
    for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = i;
    EXPECT_EQ(link.server.received(Channel::reliable), expected);
}

TEST(Conditioner, LossDropsAboutHalfOfUnreliableButNoReliable) {
    Conditions conditions;
    conditions.loss = 0.5;
    conditions.seed = 7;
    Link link;
    connect_link(link, &conditions);
    blast(link, 2000, 200);
    const std::size_t arrived = link.server.received(Channel::unreliable).size();
    EXPECT_GE(arrived, 700u);
    EXPECT_LE(arrived, 1300u);
    const ConditionerStats stats = conditioner_stats(*link.client.t);
    EXPECT_LE(arrived, 2000u - stats.dropped);
    EXPECT_GE(stats.dropped, 700u);
    EXPECT_LE(stats.dropped, 1300u);
}

TEST(Conditioner, DuplicatesArrive) {
    Conditions conditions;
    conditions.duplicate = 1.0;
    Link link;
    connect_link(link, &conditions);
    blast(link, 100, 20);
    std::map<std::uint64_t, int> seen;
    for (std::uint64_t v : link.server.received(Channel::unreliable)) ++seen[v];
    int twice = 0;
    for (const auto& [value, n] : seen) {
        EXPECT_LE(n, 2) << value;
        twice += n == 2 ? 1 : 0;
    }
    EXPECT_GE(twice, 90);
    EXPECT_EQ(conditioner_stats(*link.client.t).duplicated, 100u);
}

TEST(Conditioner, ReorderChangesArrivalOrderOfUnreliable) {
    Conditions conditions;
    conditions.reorder = 1.0;
    Link link;
    connect_link(link, &conditions);
    blast(link, 100, 20);
    const std::vector<std::uint64_t> got = link.server.received(Channel::unreliable);
    ASSERT_GE(got.size(), 90u);
    EXPECT_FALSE(std::is_sorted(got.begin(), got.end()));
    // Held back behind the next one: 1, 0, 3, 2, ...
    EXPECT_EQ(got[0], 1u);
    EXPECT_EQ(got[1], 0u);
    EXPECT_EQ(conditioner_stats(*link.client.t).reordered, 50u);
}

// --- conditioner over a scripted transport: exact, deterministic behaviour ---

using jetrace::test::ScriptedTransport;

struct Sent {
    std::uint64_t at;
    PeerId peer;
    Channel channel;
    std::uint64_t value;  // ~0 for a disconnect
    bool operator==(const Sent&) const = default;
};

// What reached the scripted transport, each datagram by its first value.
std::vector<Sent> sent_log(const ScriptedTransport& inner) {
    std::vector<Sent> out;
    for (const ScriptedTransport::Record& r : inner.log()) {
        const bool gone = r.kind == ScriptedTransport::Record::Kind::disconnect;
        out.push_back({r.at_ms, r.peer, r.channel, gone ? ~std::uint64_t{0} : first_u64(r.data)});
    }
    return out;
}

std::vector<Sent> run_fake(const Conditions& conditions, ConditionerStats* stats = nullptr) {
    std::uint64_t clock = 1000;
    auto fake = std::make_unique<ScriptedTransport>(&clock);
    fake->connect(1);
    const ScriptedTransport& inner = *fake;
    auto t = condition(std::move(fake), conditions);
    std::vector<Event> events;
    t->service(clock, events);
    for (std::uint64_t i = 0; i < 300; ++i) {
        clock = 1000 + i;
        t->service(clock, events);
        EXPECT_TRUE(t->send(1, i % 3 == 0 ? Channel::reliable : Channel::unreliable, u64_bytes(i)));
    }
    EXPECT_FALSE(t->send(2, Channel::reliable, u64_bytes(0)));  // unknown peer
    t->disconnect(1);
    EXPECT_FALSE(t->send(1, Channel::reliable, u64_bytes(0)));  // closing
    for (clock = 1300; clock < 1600; ++clock) t->service(clock, events);
    if (stats != nullptr) *stats = conditioner_stats(*t);
    return sent_log(inner);
}

TEST(Conditioner, FakeInnerIsDeterministicAndKeepsReliableOrder) {
    Conditions conditions;
    conditions.latency_ms = 20;
    conditions.jitter_ms = 15;
    conditions.loss = 0.2;
    conditions.duplicate = 0.2;
    conditions.reorder = 0.2;
    conditions.seed = 42;
    ConditionerStats stats;
    const std::vector<Sent> log = run_fake(conditions, &stats);
    EXPECT_EQ(log, run_fake(conditions));
    conditions.seed = 43;
    EXPECT_NE(log, run_fake(conditions));

    std::vector<std::uint64_t> reliable;
    for (const Sent& s : log) {
        if (s.channel == Channel::reliable && s.value != ~std::uint64_t{0}) reliable.push_back(s.value);
        if (s.value != ~std::uint64_t{0}) {
            EXPECT_GE(s.at, 1000 + s.value + 20);
        }
    }
    std::vector<std::uint64_t> expected;
    for (std::uint64_t i = 0; i < 300; i += 3) expected.push_back(i);
    EXPECT_EQ(reliable, expected);
    ASSERT_FALSE(log.empty());
    EXPECT_EQ(log.back().value, ~std::uint64_t{0});  // the disconnect goes last
    for (std::size_t i = 1; i < log.size(); ++i) EXPECT_LE(log[i - 1].at, log[i].at);
    EXPECT_GT(stats.dropped, 0u);
    EXPECT_GT(stats.duplicated, 0u);
    EXPECT_GT(stats.reordered, 0u);
    EXPECT_EQ(log.size(), 300 - stats.dropped + stats.duplicated + 1);
}

TEST(Conditioner, HeldDatagramWithoutSuccessorIsReleasedEventually) {
    std::uint64_t clock = 0;
    Conditions conditions;
    conditions.reorder = 1.0;
    auto fake = std::make_unique<ScriptedTransport>(&clock);
    fake->connect(1);
    const ScriptedTransport& inner = *fake;
    auto t = condition(std::move(fake), conditions);
    std::vector<Event> events;
    t->service(clock, events);
    ASSERT_TRUE(t->send(1, Channel::unreliable, u64_bytes(5)));
    clock = 50;
    t->service(clock, events);
    EXPECT_TRUE(inner.log().empty());
    clock = 100;
    t->service(clock, events);
    const std::vector<Sent> log = sent_log(inner);
    ASSERT_EQ(log.size(), 1u);
    EXPECT_EQ(log[0].value, 5u);
    EXPECT_EQ(conditioner_stats(*t).reordered, 0u);
    const ScriptedTransport plain;
    EXPECT_EQ(conditioner_stats(plain).dropped, 0u);
}

}  // namespace
