// What the web transport's I/O thread and the server's loop share: the
// events for service(), the open game sockets by peer id, the pre-Hello
// counts per address and the counters. Everything below `mutex` is behind
// it; the functions take it.
#pragma once

#include "jetrace/web/web_transport.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ssl/context.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace jetrace::web::detail {

class GameSocket;

struct WebState {
    WebState(WebConfig c, WebSite s) : config(std::move(c)), site(std::move(s)) {}

    const WebConfig config;
    const WebSite site;
    boost::asio::io_context io;
    /// TLS (WebConfig::cert_file): every connection is HTTPS / WSS; null: plain.
    std::unique_ptr<boost::asio::ssl::context> tls;

    std::mutex mutex;
    std::vector<net::Event> events;
    std::map<net::PeerId, std::shared_ptr<GameSocket>> sockets;
    /// Sockets of each address the server has not admitted yet.
    std::map<std::string, std::size_t> pending;
    net::PeerId next_peer = kWebPeerBase;
    /// Upgrades reserved whose handshake has not finished.
    std::size_t handshaking = 0;
    net::Totals totals;
    WebStats stats;

    /// Whether the upgrade from `address` may open a socket (the caps): if
    /// so, it counts as a socket and as one of the address's pending ones
    /// from now (its handshake included); else the refusal is counted.
    enum class Admission { open, full, pre_hello_cap };
    Admission reserve(const std::string& address);
    /// A reserved socket's handshake failed.
    void abandoned(const std::string& address);
    /// A reserved socket opened (connected event) / an open one closed
    /// (disconnected event with `close_code`).
    void opened(const std::shared_ptr<GameSocket>& s);
    void closed(const GameSocket& s, std::uint16_t close_code);
    /// The server admitted the peer: it leaves its address's pending count.
    void admit(net::PeerId peer);
    void received(net::PeerId peer, net::Channel channel, std::vector<std::uint8_t> data);
};

}  // namespace jetrace::web::detail
