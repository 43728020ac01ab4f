// jetrace::net's in-memory network (memory_transport.hpp): connects,
// datagrams (once, in order, to the right peer), disconnects from either
// side, totals, latency on the caller's clock, refusals.
#include "jetrace/net/memory_transport.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace {

using namespace jetrace::net;

/// A transport end and everything it reported so far.
struct End {
    std::unique_ptr<Transport> t;
    std::vector<Event> events;

    void service(std::uint64_t now_ms) { t->service(now_ms, events); }
    std::vector<Event> take() { return std::exchange(events, {}); }
};

std::vector<std::uint8_t> bytes(std::uint8_t tag, std::uint8_t n, std::size_t size = 4) {
    return std::vector<std::uint8_t>(size, static_cast<std::uint8_t>(tag * 16 + n));
}

/// The server end and `n` connected clients (server peers 1..n, in order).
struct Net {
    MemoryHub hub;
    End server;
    std::vector<End> clients;

    explicit Net(int n, const MemoryHubConfig& config = {}) : hub(config) {
        server.t = hub.listen();
        for (int i = 0; i < n; ++i) clients.push_back(End{hub.connect(), {}});
        server.service(0);
        for (End& c : clients) c.service(0);
    }
};

TEST(MemoryTransport, ConnectsServerFirstThenClientWithEnetPeerIds) {
    MemoryHub hub;
    End server{hub.listen(), {}};
    ASSERT_TRUE(server.t);
    EXPECT_FALSE(hub.listen()) << "one server end at a time";
    End a{hub.connect(), {}}, b{hub.connect(), {}};
    EXPECT_FALSE(a.t->send(0, Channel::reliable, bytes(1, 0))) << "not connected yet";
    a.service(0);
    EXPECT_TRUE(a.events.empty()) << "the client is connected once the server end took the connect";
    server.service(0);
    ASSERT_EQ(server.events.size(), 2u);
    EXPECT_EQ(server.events[0].type, Event::Type::connected);
    EXPECT_EQ(server.events[0].peer, 1u);
    EXPECT_EQ(server.events[1].peer, 2u);
    a.service(0);
    b.service(0);
    ASSERT_EQ(a.events.size(), 1u);
    EXPECT_EQ(a.events[0].type, Event::Type::connected);
    EXPECT_EQ(a.events[0].peer, 0u);
    EXPECT_EQ(b.events.size(), 1u);
    EXPECT_EQ(a.t->local_port(), 0u);
}

TEST(MemoryTransport, EachDatagramArrivesOnceInOrderAtTheRightPeer) {
    Net net(2);
    End& a = net.clients[0];
    End& b = net.clients[1];
    a.take();
    b.take();
    net.server.take();
    for (std::uint8_t n = 0; n < 5; ++n) {
        const Channel ch = n % 2 ? Channel::reliable : Channel::unreliable;
        ASSERT_TRUE(a.t->send(0, ch, bytes(1, n)));
        ASSERT_TRUE(b.t->send(0, ch, bytes(2, n)));
        ASSERT_TRUE(net.server.t->send(1, ch, bytes(3, n)));
        ASSERT_TRUE(net.server.t->send(2, ch, bytes(4, n)));
    }
    EXPECT_FALSE(net.server.t->send(3, Channel::reliable, bytes(5, 0))) << "no such peer";
    EXPECT_FALSE(a.t->send(1, Channel::reliable, bytes(5, 0))) << "a client's peer is 0";
    for (int round = 0; round < 2; ++round) {  // a second service hands out nothing more
        net.server.service(1);
        a.service(1);
        b.service(1);
    }
    ASSERT_EQ(net.server.events.size(), 10u);
    for (std::uint8_t n = 0; n < 5; ++n) {
        const Channel ch = n % 2 ? Channel::reliable : Channel::unreliable;
        // The server receives in the order the clients sent: a's, then b's, each round.
        const Event& from_a = net.server.events[2u * n];
        const Event& from_b = net.server.events[2u * n + 1];
        EXPECT_EQ(from_a.peer, 1u);
        EXPECT_EQ(from_a.data, bytes(1, n));
        EXPECT_EQ(from_a.channel, ch);
        EXPECT_EQ(from_b.peer, 2u);
        EXPECT_EQ(from_b.data, bytes(2, n));
        ASSERT_EQ(a.events.size(), 5u);
        EXPECT_EQ(a.events[n].data, bytes(3, n));
        EXPECT_EQ(a.events[n].channel, ch);
        EXPECT_EQ(a.events[n].type, Event::Type::received);
        ASSERT_EQ(b.events.size(), 5u);
        EXPECT_EQ(b.events[n].data, bytes(4, n));
    }
}

TEST(MemoryTransport, ClientDisconnectIsSeenByBothSidesAfterItsData) {
    Net net(1);
    End& a = net.clients[0];
    a.take();
    net.server.take();
    ASSERT_TRUE(a.t->send(0, Channel::reliable, bytes(1, 1)));
    a.t->disconnect(0);
    EXPECT_FALSE(a.t->send(0, Channel::reliable, bytes(1, 2))) << "closing: nothing more";
    net.server.service(1);
    ASSERT_EQ(net.server.events.size(), 2u);
    EXPECT_EQ(net.server.events[0].type, Event::Type::received);
    EXPECT_EQ(net.server.events[1].type, Event::Type::disconnected);
    EXPECT_EQ(net.server.events[1].peer, 1u);
    EXPECT_FALSE(net.server.t->send(1, Channel::reliable, bytes(2, 0)));
    a.service(1);
    ASSERT_EQ(a.events.size(), 1u);
    EXPECT_EQ(a.events[0].type, Event::Type::disconnected);
}

TEST(MemoryTransport, ServerDisconnectDeliversQueuedDataFirstAndDropsLaterData) {
    Net net(1);
    End& a = net.clients[0];
    a.take();
    net.server.take();
    ASSERT_TRUE(net.server.t->send(1, Channel::reliable, bytes(1, 1)));
    net.server.t->disconnect(1);
    ASSERT_TRUE(a.t->send(0, Channel::unreliable, bytes(2, 2))) << "the client cannot know yet";
    a.service(1);
    ASSERT_EQ(a.events.size(), 2u);
    EXPECT_EQ(a.events[0].data, bytes(1, 1));
    EXPECT_EQ(a.events[1].type, Event::Type::disconnected);
    net.server.service(1);
    ASSERT_EQ(net.server.events.size(), 1u) << "data to a closing end is discarded";
    EXPECT_EQ(net.server.events[0].type, Event::Type::disconnected);
    EXPECT_EQ(net.server.events[0].peer, 1u);
    EXPECT_EQ(net.server.t->totals().bytes_received, 0u);
}

TEST(MemoryTransport, DestroyedEndsDisconnectTheirPeers) {
    Net net(2);
    for (End& c : net.clients) c.take();
    net.server.take();
    net.clients[0].t.reset();
    net.server.service(1);
    ASSERT_EQ(net.server.events.size(), 1u);
    EXPECT_EQ(net.server.events[0].type, Event::Type::disconnected);
    EXPECT_EQ(net.server.events[0].peer, 1u);
    net.server.t.reset();
    End& b = net.clients[1];
    b.service(1);
    ASSERT_EQ(b.events.size(), 1u);
    EXPECT_EQ(b.events[0].type, Event::Type::disconnected);
    End late{net.hub.connect(), {}};
    late.service(2);
    ASSERT_EQ(late.events.size(), 1u) << "no server end: the connect fails";
    EXPECT_EQ(late.events[0].type, Event::Type::disconnected);
    EXPECT_TRUE(net.hub.listen()) << "a new server end once the old one is gone";
}

TEST(MemoryTransport, ConnectsBeyondTheLimitAreRefused) {
    MemoryHubConfig config;
    config.max_connections = 1;
    Net net(2, config);
    ASSERT_EQ(net.server.events.size(), 1u);
    net.clients[1].service(0);
    ASSERT_EQ(net.clients[1].events.size(), 1u);
    EXPECT_EQ(net.clients[1].events[0].type, Event::Type::disconnected);
    EXPECT_EQ(net.clients[0].events[0].type, Event::Type::connected);
}

TEST(MemoryTransport, TotalsCountPayloadBytesAndDatagrams) {
    Net net(1);
    End& a = net.clients[0];
    ASSERT_TRUE(a.t->send(0, Channel::reliable, bytes(1, 0, 100)));
    ASSERT_TRUE(a.t->send(0, Channel::unreliable, bytes(1, 1, 23)));
    ASSERT_TRUE(net.server.t->send(1, Channel::unreliable, bytes(2, 0, 1000)));
    EXPECT_FALSE(net.server.t->send(1, Channel::unreliable, bytes(2, 1, 64 * 1024 + 1))) << "too large";
    EXPECT_FALSE(net.server.t->send(1, static_cast<Channel>(2), bytes(2, 1))) << "no such channel";
    const Totals before = net.server.t->totals();
    EXPECT_EQ(before.bytes_sent, 1000u);
    EXPECT_EQ(before.packets_sent, 1u);
    EXPECT_EQ(before.bytes_received, 0u) << "counted when handed out";
    net.server.service(1);
    a.service(1);
    const Totals s = net.server.t->totals();
    EXPECT_EQ(s.bytes_received, 123u);
    EXPECT_EQ(s.packets_received, 2u);
    const Totals c = a.t->totals();
    EXPECT_EQ(c.bytes_sent, 123u);
    EXPECT_EQ(c.packets_sent, 2u);
    EXPECT_EQ(c.bytes_received, 1000u);
    EXPECT_EQ(c.packets_received, 1u);
}

TEST(MemoryTransport, LatencyDelaysEveryItemOnTheCallersClock) {
    MemoryHubConfig config;
    config.latency_ms = 10;
    MemoryHub hub(config);
    End server{hub.listen(), {}}, a{hub.connect(), {}};
    server.service(9);
    EXPECT_TRUE(server.events.empty());
    server.service(10);
    ASSERT_EQ(server.events.size(), 1u);
    a.service(19);
    EXPECT_TRUE(a.events.empty());
    a.service(20);
    ASSERT_EQ(a.events.size(), 1u);
    EXPECT_EQ(a.t->peer_stats(0).rtt_ms, 20.0);
    EXPECT_EQ(server.t->peer_stats(1).rtt_ms, 20.0);
    EXPECT_EQ(server.t->peer_stats(2).rtt_ms, 0.0) << "unknown peer";
    ASSERT_TRUE(a.t->send(0, Channel::unreliable, bytes(1, 0)));  // at hub time 20
    server.service(29);
    EXPECT_EQ(server.events.size(), 1u);
    server.service(30);
    ASSERT_EQ(server.events.size(), 2u);
    EXPECT_EQ(server.events[1].data, bytes(1, 0));
}

TEST(MemoryTransport, DisconnectBeforeTheConnectCompletesIsReportedAtOnce) {
    MemoryHub hub;
    End server{hub.listen(), {}}, a{hub.connect(), {}};
    a.t->disconnect(0);
    a.service(0);
    ASSERT_EQ(a.events.size(), 1u);
    EXPECT_EQ(a.events[0].type, Event::Type::disconnected);
    server.service(0);
    ASSERT_EQ(server.events.size(), 2u) << "the server saw the connect, then its end";
    EXPECT_EQ(server.events[0].type, Event::Type::connected);
    EXPECT_EQ(server.events[1].type, Event::Type::disconnected);
    a.service(1);
    EXPECT_EQ(a.events.size(), 1u) << "reported once";
}

}  // namespace
