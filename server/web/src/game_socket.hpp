// One browser's game WebSocket, on the web transport's I/O thread: reads
// binary frames (a channel byte and one protocol message) into events, and
// writes the frames the server queued, in order. A frame that is not
// binary, is empty, names no channel or exceeds the frame cap closes this
// socket only, with kMalformedFrame.
#pragma once

#include "web_state.hpp"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <atomic>
#include <deque>
#include <memory>
#include <string>

namespace jetrace::web::detail {

class GameSocket : public std::enable_shared_from_this<GameSocket> {
public:
    GameSocket(boost::asio::ip::tcp::socket&& socket, WebState& state, std::string address);
    /// Accepts the upgrade `req` asked for, then runs until either side closes.
    void run(boost::beast::http::request<boost::beast::http::string_body> req);

    /// From the server's loop (any thread): queues a frame; false if the
    /// queue would pass its cap (the socket is then closed).
    bool queue(net::Channel channel, std::span<const std::uint8_t> data);
    /// From any thread: closes once the queued frames are written.
    void close_after_writes(std::uint16_t code);

    net::PeerId peer() const { return peer_; }
    void set_peer(net::PeerId p) { peer_ = p; }
    const std::string& address() const { return address_; }
    bool admitted = false;

private:
    void on_accept(boost::beast::error_code ec);
    void read_next();
    void on_read(boost::beast::error_code ec, std::size_t bytes);
    void push(std::string frame);
    void write_front();
    void on_write(boost::beast::error_code ec, std::size_t bytes);
    void close(std::uint16_t code);
    void finish(std::uint16_t code);
    /// Tells the server (once) that the socket is closed, with `code`.
    void report(std::uint16_t code);

    boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
    WebState* state_;
    std::string address_;
    net::PeerId peer_ = 0;
    boost::beast::flat_buffer in_;
    std::deque<std::string> out_;
    std::atomic<std::size_t> queued_bytes_{0};
    std::atomic<bool> overflowed_{false};
    bool writing_ = false;
    bool closing_ = false;
    bool finished_ = false;
    bool open_ = false;
    bool reported_ = false;
    std::uint16_t close_code_ = 0;
};

}  // namespace jetrace::web::detail
