// net::combine nested as jetrace-server --web nests it (ENet, WebSocket,
// WebRTC): each peer's transport is named by the part that holds it, and
// each part's totals are found by that name.
#include "jetrace/net/mux_transport.hpp"

#include <gtest/gtest.h>

#include <memory>

using namespace jetrace;

namespace {

// A transport that only has totals (bytes_sent = `n`).
struct Counted final : net::Transport {
    explicit Counted(std::uint64_t n) { t.bytes_sent = n; }
    void service(std::uint64_t, std::vector<net::Event>&) override {}
    bool send(net::PeerId, net::Channel, std::span<const std::uint8_t>) override { return true; }
    void disconnect(net::PeerId) override {}
    void flush() override {}
    net::PeerStats peer_stats(net::PeerId) const override { return {}; }
    net::Totals totals() const override { return t; }
    std::uint16_t local_port() const override { return 0; }
    net::Totals t;
};

}  // namespace

// jetrace-server's transport with --web: ENet, WebSocket and WebRTC, nested.
TEST(MuxTransport, NestedCombineNamesEachPart) {
    auto both = net::combine(std::make_unique<Counted>(1), std::make_unique<Counted>(2), 0x40000000u);
    auto all = net::combine(std::move(both), std::make_unique<Counted>(4), 0x60000000u, "webrtc");
    EXPECT_EQ(net::transport_of(*all, 5), "enet");
    EXPECT_EQ(net::transport_of(*all, 0x40000001u), "websocket");
    EXPECT_EQ(net::transport_of(*all, 0x60000000u + 3), "webrtc");
    EXPECT_EQ(net::part_totals(*all, "enet").bytes_sent, 1u);
    EXPECT_EQ(net::part_totals(*all, "websocket").bytes_sent, 2u);
    EXPECT_EQ(net::part_totals(*all, "webrtc").bytes_sent, 4u);
    EXPECT_EQ(all->totals().bytes_sent, 7u);
}
