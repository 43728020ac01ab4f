// Availability: one UDP socket that opens ENet connections and never says
// Hello must not lock everybody out. A flooder bound to 127.0.0.2 (the whole
// 127.0.0.0/8 is loopback on Linux) keeps every connection it can open
// silent, re-opens each as the server drops it, and keeps fresh connection
// requests going, until the race is over (at most 30 s of real time);
// meanwhile an honest bot from 127.0.0.1 joins within its join window and
// finishes its race. Without the server's pre-Hello cap
// (net::ServerConfig::max_pending_per_address) the flooder holds every peer
// slot and the bot never gets in.
#include "support/live_race.hpp"
#include "support/log_capture.hpp"

#include <enet/enet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

using namespace jetrace;
using Clock = std::chrono::steady_clock;

// One ENet host (one UDP socket) that opens as many connections to the
// server as it has peers, never sends a byte on them, re-opens every one
// that ends, and replaces a request unanswered for kRetryMs with a fresh one.
class Flooder {
public:
    static constexpr std::uint64_t kRetryMs = 200;

    Flooder(const char* from, std::uint16_t port, std::size_t peers) : started_(peers, Clock::time_point{}) {
        if (enet_initialize() != 0) return;
        initialized_ = true;
        ENetAddress local{};
        if (enet_address_set_host_ip(&local, from) != 0) return;
        local.port = 0;
        host_ = enet_host_create(&local, peers, 2, 0, 0);
        if (host_ == nullptr) return;
        enet_address_set_host_ip(&server_, "127.0.0.1");
        server_.port = port;
    }
    ~Flooder() {
        if (host_ != nullptr) enet_host_destroy(host_);
        if (initialized_) enet_deinitialize();
    }
    Flooder(const Flooder&) = delete;
    Flooder& operator=(const Flooder&) = delete;

    bool ok() const { return host_ != nullptr; }

    void service() {
        ENetEvent ev{};
        while (enet_host_service(host_, &ev, 0) > 0) {
            if (ev.type == ENET_EVENT_TYPE_CONNECT) {
                ++connects;
                ev.peer->data = this;  // marks it connected
            } else if (ev.type == ENET_EVENT_TYPE_DISCONNECT) {
                if (ev.peer->data != nullptr) ++dropped;
                ev.peer->data = nullptr;
            } else if (ev.type == ENET_EVENT_TYPE_RECEIVE) {
                enet_packet_destroy(ev.packet);
            }
        }
        const auto now = Clock::now();
        std::size_t open = 0;
        for (std::size_t i = 0; i < host_->peerCount; ++i) {
            ENetPeer& p = host_->peers[i];
            if (p.state == ENET_PEER_STATE_CONNECTED) ++open;
            const bool stale = p.state == ENET_PEER_STATE_CONNECTING && now - started_[i] > std::chrono::milliseconds(kRetryMs);
            if (stale) enet_peer_reset(&p);
            if (p.state != ENET_PEER_STATE_DISCONNECTED) continue;
            if (enet_host_connect(host_, &server_, 2, 0) == nullptr) break;
            started_[i] = now;
            ++requests;
        }
        most_open = std::max(most_open, open);
        enet_host_flush(host_);
    }

    /// Connections the server accepted, and dropped after they said nothing.
    std::uint64_t connects = 0;
    std::uint64_t dropped = 0;
    /// Connection requests started (unit: requests).
    std::uint64_t requests = 0;
    /// Most connections up at once.
    std::size_t most_open = 0;

private:
    bool initialized_ = false;
    ENetHost* host_ = nullptr;
    ENetAddress server_{};
    std::vector<Clock::time_point> started_;
};

std::size_t lines_with(const std::string& text, const std::string& part) {
    std::istringstream in(text);
    std::size_t n = 0;
    for (std::string line; std::getline(in, line);) n += line.find(part) != std::string::npos ? 1 : 0;
    return n;
}

// Services `transports` (appending their events) every millisecond until
// `done()` or `max_ms` of real time; false on timeout.
bool pump(const std::vector<std::pair<net::Transport*, std::vector<net::Event>*>>& transports,
          const std::function<bool()>& done, int max_ms) {
    const auto deadline = Clock::now() + std::chrono::milliseconds(max_ms);
    while (!done()) {
        if (Clock::now() > deadline) return false;
        for (auto& [t, events] : transports) {
            t->service(0, *events);
            t->flush();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return true;
}

std::size_t count(const std::vector<net::Event>& events, net::Event::Type type) {
    return static_cast<std::size_t>(
        std::count_if(events.begin(), events.end(), [type](const net::Event& e) { return e.type == type; }));
}

// The cap at the transport: with 1, a second connection from the same
// address (another port) gets no slot until the first is admitted: its
// request is answered at once with an ENet disconnect carrying
// kPreHelloRefusal, long before ENet's first resend (0.5 s) or timeout.
// Once the first is admitted, a new one gets in.
TEST(Availability, TransportRefusesAnAddressAtItsCapUntilAdmit) {
    net::ServerConfig cfg;
    cfg.bind = "127.0.0.1";
    cfg.max_connections = 8;
    cfg.max_pending_per_address = 1;
    std::string error;
    auto server = net::listen_enet(cfg, error);
    ASSERT_TRUE(server) << error;
    auto a = net::connect_enet("127.0.0.1", server->local_port(), 5000, error);
    ASSERT_TRUE(a) << error;
    std::vector<net::Event> se, ae, be, ce;
    using Ev = net::Event::Type;
    ASSERT_TRUE(pump({{server.get(), &se}, {a.get(), &ae}}, [&] { return count(se, Ev::connected) == 1; }, 2000));
    const net::PeerId first = se.front().peer;
    auto b = net::connect_enet("127.0.0.1", server->local_port(), 5000, error);
    ASSERT_TRUE(b) << error;
    const auto asked = Clock::now();
    ASSERT_TRUE(pump({{server.get(), &se}, {a.get(), &ae}, {b.get(), &be}},
                     [&] { return count(be, Ev::disconnected) == 1; }, 3000));
    EXPECT_LT(Clock::now() - asked, std::chrono::milliseconds(400)) << "the refusal was not answered";
    EXPECT_EQ(be.back().close_code, net::kPreHelloRefusal);
    EXPECT_EQ(count(be, Ev::connected), 0u);
    EXPECT_EQ(count(se, Ev::connected), 1u);
    EXPECT_GE(server->totals().connects_refused, 1u);
    server->admit(first);
    auto c = net::connect_enet("127.0.0.1", server->local_port(), 5000, error);
    ASSERT_TRUE(c) << error;
    EXPECT_TRUE(pump({{server.get(), &se}, {a.get(), &ae}, {c.get(), &ce}},
                     [&] { return count(se, Ev::connected) == 2 && count(ce, Ev::connected) == 1; }, 2000));
    EXPECT_EQ(count(ae, Ev::disconnected) + count(ce, Ev::disconnected) + count(se, Ev::disconnected), 0u);
}

// An attempt nobody answers (no server on the port) times out with no code:
// the client tells a dead server from the cap's refusal by the code alone.
TEST(Availability, AnUnansweredAttemptEndsWithoutACode) {
    std::uint16_t port = 0;
    {
        net::ServerConfig cfg;
        cfg.bind = "127.0.0.1";
        std::string error;
        auto gone = net::listen_enet(cfg, error);
        ASSERT_TRUE(gone) << error;
        port = gone->local_port();
    }
    std::string error;
    auto c = net::connect_enet("127.0.0.1", port, 400, error);
    ASSERT_TRUE(c) << error;
    std::vector<net::Event> ce;
    ASSERT_TRUE(pump({{c.get(), &ce}}, [&] { return count(ce, net::Event::Type::disconnected) == 1; }, 3000));
    EXPECT_EQ(ce.back().close_code, 0u);
}

TEST(Availability, OneSocketWithoutHellosLocksNobodyOut) {
    constexpr std::size_t kCap = 2;
    constexpr double kFloodSeconds = 30;
    test::LogCapture log(spdlog::level::warn);
    test::LiveRaceOptions o = test::lobby_options();
    o.max_players = 2;
    o.min_players = 1;
    o.spare_connections = 16;  // as jetrace-server: max_players + max_observers (8) + 8 peer slots
    o.max_pending_per_address = kCap;
    test::LiveRace race(o);
    ASSERT_TRUE(race.ok()) << race.error;
    const std::size_t slots = static_cast<std::size_t>(o.max_players) + o.spare_connections;
    // Far more peers than the server has slots, so that one is always waiting to take a free slot.
    Flooder flood("127.0.0.2", race.port, 4 * slots);
    ASSERT_TRUE(flood.ok()) << "cannot bind an ENet host to 127.0.0.2";

    const auto start = Clock::now();
    auto elapsed_s = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    // The flood first takes what it can, then the bot comes.
    while (elapsed_s() < 2) {
        race.step();
        flood.service();
    }
    client::ClientConfig cc;
    cc.name = "honest";
    cc.join_window_s = 20;  // virtual seconds, several times ENet's connect timeout
    race.add_bot(cc);
    const std::uint64_t bot_joined_at_us = race.now_us();
    std::uint64_t welcomed_after_us = 0;
    // The flood goes on until the race is over and it has been refused and
    // dropped as often as the checks below ask, or for kFloodSeconds.
    auto flood_did_its_work = [&] {
        return race.server().done() && flood.connects >= 2 * kCap && flood.dropped >= kCap && flood.requests > 1000;
    };
    while (elapsed_s() < kFloodSeconds && !flood_did_its_work()) {
        race.step();
        flood.service();
        if (welcomed_after_us == 0 && race.bot(0).client->slot() >= 0) welcomed_after_us = race.now_us() - bot_joined_at_us;
    }
    std::printf("flood: %.1f s, %llu requests, %llu connects, %llu dropped\n", elapsed_s(),
                static_cast<unsigned long long>(flood.requests), static_cast<unsigned long long>(flood.connects),
                static_cast<unsigned long long>(flood.dropped));

    EXPECT_GT(welcomed_after_us, 0u) << "the honest bot never got a slot";
    EXPECT_LE(welcomed_after_us, 20'000'000u) << "the honest bot got in after its join window";
    EXPECT_TRUE(race.server().done()) << "the race did not end within the flood";
    ASSERT_EQ(race.ends.size(), 1u);
    EXPECT_TRUE(race.finished(0)) << "the honest bot did not finish its race";
    // The flood was real: it kept connections up, the server kept dropping them.
    EXPECT_GE(flood.connects, 2 * kCap);
    EXPECT_GE(flood.dropped, kCap);
    EXPECT_GT(flood.requests, 1000u);
    // It never held more than the cap, was refused, and the log says so once.
    EXPECT_LE(flood.most_open, kCap);
    EXPECT_GT(race.server().refused_pre_hello(), 0u);
    EXPECT_EQ(lines_with(log.text(), "pre-Hello cap: refusing connection requests from 127.0.0.2"), 1u) << log.text();
    EXPECT_EQ(lines_with(log.text(), "refusing connection requests from 127.0.0.1"), 0u);
}

}  // namespace
