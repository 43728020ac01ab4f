// The viewer's HTTP side (Boost.Beast): accepts connections, serves the
// page's files, three.js's modules and /track.bin to GET and HEAD, and
// hands a request for /ws that asks for a WebSocket to WsSession. Request
// heads and bodies are size-limited; anything else gets 404 or 405.
#pragma once

#include "view_context.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include <string>

namespace jetrace::view {

class HttpServer {
public:
    HttpServer(boost::asio::io_context& io, ViewContext& ctx) : acceptor_(io), ctx_(ctx) {}
    /// Binds and listens; false with a reason.
    bool listen(const std::string& host, std::uint16_t port, std::string& error);
    /// The bound endpoint (the real port when 0 was asked for).
    boost::asio::ip::tcp::endpoint local_endpoint() const { return acceptor_.local_endpoint(); }
    /// Accepts connections until the io_context stops.
    void start() { accept_next(); }

private:
    void accept_next();

    boost::asio::ip::tcp::acceptor acceptor_;
    ViewContext& ctx_;
};

}  // namespace jetrace::view
