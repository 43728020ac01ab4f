// One page's WebSocket: sends the hello, then a frame whenever the tick it
// shows changes (at most frame_rate_hz per second; a page that reads slowly
// gets the newest frame, not a backlog), and obeys its page messages
// (replay: the timeline; drive: the keys). A malformed message closes this
// socket only, with a log line.
#pragma once

#include "playback.hpp"
#include "view_context.hpp"

#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <string>

namespace jetrace::view {

class WsSession : public std::enable_shared_from_this<WsSession> {
public:
    WsSession(boost::asio::ip::tcp::socket&& socket, ViewContext& ctx);
    ~WsSession();
    WsSession(const WsSession&) = delete;
    WsSession& operator=(const WsSession&) = delete;
    /// Accepts the upgrade `req` asked for, then runs until either side closes.
    void run(boost::beast::http::request<boost::beast::http::string_body> req);

private:
    void on_accept(boost::beast::error_code ec);
    void read_next();
    void on_read(boost::beast::error_code ec, std::size_t bytes);
    void apply(const std::string& text);
    void apply_live(const std::string& text);
    /// The frame of what this page shows now.
    std::string frame() const;
    void arm_timer();
    void on_timer(boost::beast::error_code ec);
    void send(std::string message, bool is_frame);
    void write_front();
    void on_write(boost::beast::error_code ec, std::size_t bytes);
    void close(boost::beast::websocket::close_code code, const std::string& why);
    void finish(const std::string& why);

    boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
    boost::asio::steady_timer timer_;
    ViewContext& ctx_;
    std::uint64_t id_;
    /// Replay mode only (live pages show the live session's world).
    std::optional<Playback> playback_;
    boost::beast::flat_buffer in_;
    /// Messages to write, the front one being written; at most one frame waits.
    std::deque<std::string> out_;
    bool last_is_frame_ = false;
    bool closing_ = false;
    bool finished_ = false;
    std::chrono::steady_clock::time_point last_advance_, opened_;
    std::uint64_t bytes_sent_ = 0;
};

}  // namespace jetrace::view
