// One browser's game WebSocket, on the web transport's I/O thread: reads
// binary frames (a channel byte and one protocol message,
// net::read_ws_frame) into events, and writes the frames the server
// queued, in order. A frame that is not binary, is empty or names no
// channel closes this socket only, with kMalformedFrame (one over the frame
// cap: Beast closes it with 1009). Over plain TCP or TLS (--web-cert).
#pragma once

#include "web_state.hpp"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>

#include <memory>
#include <span>
#include <string>

namespace jetrace::web::detail {

using PlainStream = boost::beast::tcp_stream;
using TlsStream = boost::beast::ssl_stream<boost::beast::tcp_stream>;
using Request = boost::beast::http::request<boost::beast::http::string_body>;

class GameSocket : public std::enable_shared_from_this<GameSocket> {
public:
    virtual ~GameSocket() = default;
    GameSocket(const GameSocket&) = delete;
    GameSocket& operator=(const GameSocket&) = delete;

    /// From the server's loop (any thread): queues a frame; false if the
    /// queue would pass its cap (the socket is then closed).
    virtual bool queue(net::Channel channel, std::span<const std::uint8_t> data) = 0;
    /// From any thread: closes once the queued frames are written.
    virtual void close_after_writes(std::uint16_t code) = 0;

    net::PeerId peer() const { return peer_; }
    void set_peer(net::PeerId p) { peer_ = p; }
    const std::string& address() const { return address_; }
    /// The server accepted its Hello (under WebState::mutex).
    bool admitted = false;

protected:
    GameSocket(WebState& state, std::string address) : state_(&state), address_(std::move(address)) {}

    WebState* state_;
    std::string address_;
    net::PeerId peer_ = 0;
};

/// Accepts the upgrade `req` asked for on `stream` (its handshake reserved
/// with WebState::reserve), then runs the socket until either side closes.
void open_game_socket(PlainStream&& stream, WebState& state, std::string address, Request req);
void open_game_socket(TlsStream&& stream, WebState& state, std::string address, Request req);

}  // namespace jetrace::web::detail
