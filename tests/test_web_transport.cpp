// The WebSocket transport of jetrace-server --web (server/web) against
// hostile clients on 127.0.0.1 while an honest 4-bot race runs over ENet
// beside it: a foreign Origin, text frames, a frame naming no channel, an
// oversized frame, junk messages, half-open sockets and 1,000 upgrades from
// one address. Each is refused (HTTP 403, 503) or closed with its close
// code (4001 malformed frame, 1009 too big), and the race
// is untouched: every car stepped by exactly its own bot's inputs. And a
// socket whose reader stalls is closed at its send-queue cap (4003), not
// waited for.
#include "support/live_race.hpp"
#include "support/log_capture.hpp"
#include "support/test_seed.hpp"

#include "jetrace/net/mux_transport.hpp"
#include "jetrace/web/web_transport.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <gtest/gtest.h>

#include <random>
#include <thread>

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using jetrace::test::LiveRace;
using jetrace::test::LiveRaceOptions;

/// A WebSocket client that does what a test says, blocking.
struct WsClient {
    asio::io_context io;
    websocket::stream<tcp::socket> ws{io};

    /// Connects and asks for /play from `origin` ("": no Origin header).
    bool open(std::uint16_t port, const std::string& origin) {
        beast::error_code ec;
        ws.next_layer().connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), ec);
        if (ec) return false;
        ws.set_option(websocket::stream_base::decorator([origin](websocket::request_type& req) {
            if (!origin.empty()) req.set(http::field::origin, origin);
        }));
        ws.handshake("127.0.0.1:" + std::to_string(port), "/play", ec);
        return !ec;
    }

    /// Reads until the server closes; its close code (-1: the socket ended
    /// without a close frame or did not end within `seconds`).
    int close_code(double seconds = 10) {
        beast::get_lowest_layer(ws).non_blocking(false);
        ws.set_option(websocket::stream_base::timeout{std::chrono::seconds(5),
                                                        std::chrono::milliseconds(static_cast<int>(seconds * 1000)),
                                                        false});
        for (;;) {
            beast::flat_buffer b;
            beast::error_code ec;
            ws.read(b, ec);
            if (ec == websocket::error::closed) return ws.reason().code;
            if (ec) return -1;
        }
    }

    void send_binary(const std::vector<std::uint8_t>& bytes) {
        ws.binary(true);
        beast::error_code ec;
        ws.write(asio::buffer(bytes), ec);
    }
    void send_text(const std::string& text) {
        ws.text(true);
        beast::error_code ec;
        ws.write(asio::buffer(text), ec);
    }
};

/// The server's transport in these tests: ENet plus a web port on
/// 127.0.0.1 (its port in `*web_port`), no page files.
std::function<std::unique_ptr<jetrace::net::Transport>(std::unique_ptr<jetrace::net::Transport>)> with_web(
    std::uint16_t* web_port, jetrace::web::WebConfig c = {}) {
    return [web_port, c](std::unique_ptr<jetrace::net::Transport> enet) mutable -> std::unique_ptr<jetrace::net::Transport> {
        c.bind = "127.0.0.1";
        c.port = 0;
        std::string error;
        auto web = jetrace::web::listen_web(c, {}, *web_port, error);
        EXPECT_TRUE(web) << error;
        if (!web) return nullptr;
        return jetrace::net::combine(std::move(enet), std::move(web), jetrace::web::kWebPeerBase);
    };
}

/// Asks for the upgrade by hand over `socket` and returns the HTTP status
/// of the answer (101: upgraded; Beast's client does not keep the status of
/// a declined upgrade); 0 if none.
int upgrade_status(tcp::socket& socket, std::uint16_t port, const std::string& origin) {
    beast::error_code ec;
    socket.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), ec);
    if (ec) return 0;
    http::request<http::empty_body> req{http::verb::get, "/play", 11};
    req.set(http::field::host, "127.0.0.1:" + std::to_string(port));
    req.set(http::field::connection, "Upgrade");
    req.set(http::field::upgrade, "websocket");
    req.set(http::field::sec_websocket_version, "13");
    req.set(http::field::sec_websocket_key, "dGhlIHNhbXBsZSBub25jZQ==");
    if (!origin.empty()) req.set(http::field::origin, origin);
    http::write(socket, req, ec);
    if (ec) return 0;
    beast::flat_buffer b;
    http::response_parser<http::string_body> res;
    res.skip(false);
    http::read_header(socket, b, res, ec);
    return ec ? 0 : static_cast<int>(res.get().result_int());
}

struct Outcomes {
    int foreign_origin_status = 0;
    int text_close = 0, bad_channel_close = 0, oversized_close = 0, junk_close = 0;
    int flood_accepted = 0, flood_refused = 0;
};

// Every attack on one web port, one after the other (blocking).
void attack(std::uint16_t port, std::uint64_t seed, Outcomes& out) {
    {
        asio::io_context io;
        tcp::socket s(io);
        out.foreign_origin_status = upgrade_status(s, port, "http://evil.example");
    }
    {
        WsClient c;
        ASSERT_TRUE(c.open(port, "http://127.0.0.1:" + std::to_string(port)));
        c.send_text("{\"type\":\"hello\"}");
        out.text_close = c.close_code();
    }
    {
        WsClient c;
        ASSERT_TRUE(c.open(port, ""));
        c.send_binary({7, 1, 2, 3});
        out.bad_channel_close = c.close_code();
    }
    {
        WsClient c;
        ASSERT_TRUE(c.open(port, ""));
        c.send_binary(std::vector<std::uint8_t>(5000, 1));
        out.oversized_close = c.close_code();
    }
    {
        // A message that does not decode: the server's Goodbye (malformed),
        // then a normal close.
        WsClient c;
        ASSERT_TRUE(c.open(port, ""));
        std::mt19937_64 rng(seed);
        std::vector<std::uint8_t> junk(2 + rng() % 200);
        for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
        junk[0] = 1;
        c.send_binary(junk);
        out.junk_close = c.close_code();
    }
    // Half-open: TCP connections with half a request, held open.
    asio::io_context io;
    std::vector<std::unique_ptr<tcp::socket>> half_open;
    for (int i = 0; i < 50; ++i) {
        auto s = std::make_unique<tcp::socket>(io);
        beast::error_code ec;
        s->connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), ec);
        if (!ec) asio::write(*s, asio::buffer(std::string("GET /play HTTP/1.1\r\nHost: x\r\n")), ec);
        half_open.push_back(std::move(s));
    }
    // 1,000 upgrades from one address, each kept open: the pre-Hello cap
    // lets 4 wait for their Hello, the rest are answered 503.
    std::vector<std::unique_ptr<tcp::socket>> flood;
    for (int i = 0; i < 1000; ++i) {
        auto s = std::make_unique<tcp::socket>(io);
        const int status = upgrade_status(*s, port, "");
        if (status == 101) ++out.flood_accepted;
        else if (status == 503) ++out.flood_refused;
        flood.push_back(std::move(s));
    }
}

TEST(WebTransport, HostileSocketsAreRefusedOrClosedAndTheRaceIsUntouched) {
    const std::uint64_t seed = jetrace::test::test_seed(61);
    jetrace::test::LogCapture log;
    std::uint16_t web_port = 0;
    LiveRaceOptions o;
    o.bots = 4;
    o.max_players = 5;
    jetrace::web::WebConfig wc;
    wc.max_pending_per_address = 4;
    o.server_wrap = with_web(&web_port, wc);
    LiveRace race(o);
    ASSERT_NE(web_port, 0);
    Outcomes out;
    std::thread attacker([&] { attack(web_port, seed, out); });
    const bool ended = race.run();
    attacker.join();
    ASSERT_TRUE(ended);

    EXPECT_EQ(out.foreign_origin_status, 403);
    EXPECT_EQ(out.text_close, jetrace::web::kMalformedFrame);
    EXPECT_EQ(out.bad_channel_close, jetrace::web::kMalformedFrame);
    // Beast itself closes a socket whose frame passes the cap: 1009, too big.
    EXPECT_EQ(out.oversized_close, static_cast<int>(websocket::close_code::too_big));
    EXPECT_EQ(out.junk_close, 1000) << "a junk message is answered by the server's Goodbye and a normal close";
    EXPECT_TRUE(log.has_line("malformed")) << log.text();
    EXPECT_EQ(out.flood_accepted, 4);
    EXPECT_EQ(out.flood_refused, 996);
    ASSERT_EQ(race.ends.size(), 1u);
    EXPECT_EQ(race.replay_hash(), race.ends.front().state_hash);
    race.expect_cars_moved_by_their_own_bots();
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(race.finished(i)) << "bot " << i;
}

TEST(WebTransport, AStalledReaderIsClosedAtItsSendQueueCap) {
    jetrace::web::WebConfig c;
    c.bind = "127.0.0.1";
    c.port = 0;
    c.max_queued_bytes = 64 * 1024;
    c.max_frame_bytes = 4096;
    std::uint16_t port = 0;
    std::string error;
    auto web = jetrace::web::listen_web(c, {}, port, error);
    ASSERT_TRUE(web) << error;
    WsClient client;
    ASSERT_TRUE(client.open(port, ""));
    std::vector<jetrace::net::Event> events;
    jetrace::net::PeerId peer = 0;
    for (int i = 0; i < 500 && peer == 0; ++i) {
        web->service(0, events);
        for (const auto& e : events) if (e.type == jetrace::net::Event::Type::connected) peer = e.peer;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_GE(peer, jetrace::web::kWebPeerBase);
    // The client reads nothing: the kernel's buffers fill, then the queue.
    const std::vector<std::uint8_t> chunk(60000, 0x5a);
    int sent = 0;
    while (sent < 100000 && web->send(peer, jetrace::net::Channel::unreliable, chunk)) ++sent;
    ASSERT_LT(sent, 100000) << "the queue never filled";
    bool closed = false;
    std::uint16_t code = 0;
    for (int i = 0; i < 2000 && !closed; ++i) {
        events.clear();
        web->service(0, events);
        for (const auto& e : events) {
            if (e.type == jetrace::net::Event::Type::disconnected && e.peer == peer) {
                closed = true;
                code = e.close_code;
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_TRUE(closed);
    EXPECT_EQ(code, jetrace::web::kSendQueueFull);
    EXPECT_EQ(jetrace::web::web_stats(*web).send_queue_drops, 1u);
}

}  // namespace
