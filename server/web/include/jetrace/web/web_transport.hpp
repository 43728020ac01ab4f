// The server's WebSocket transport (Boost.Beast): browsers race through it
// exactly as native clients race over ENet. One TCP port serves the game
// page's files (a fixed table held in memory: no path from a request
// reaches the file system) and upgrades GET /play to a WebSocket that
// carries the protocol's messages, one per binary frame: a channel byte
// (0 unreliable, 1 reliable) and the message (docs/PROTOCOL.md, "Transport:
// WebSocket"; docs/BROWSER.md).
//
// The sockets live on one I/O thread of their own; the server's loop only
// swaps events out in service() and hands frames over in send(), so a slow
// or stalled page never delays a tick. Each socket has a bounded send
// queue: a socket over it is closed with kSendQueueFull.
#pragma once

#include "jetrace/net/transport.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace jetrace::web {

/// A file the web port serves.
struct WebFile {
    std::string content_type;
    std::string bytes;
    /// The same bytes gzip-compressed, served to a request that accepts
    /// gzip ("": served as they are).
    std::string gzipped;
};
/// Request path ("/", "/app.js", "/three/build/three.module.js") to file.
using WebSite = std::map<std::string, WebFile>;

/// What a signalling handler answers (POST /rtc).
struct SignalReply {
    int status = 200;
    std::string content_type;
    std::string body;
};
/// The WebRTC signalling (server/rtc): the posted offer, the client's IP and
/// the web port's local IP in; the reply out. Called on the web I/O thread.
using SignalHandler =
    std::function<SignalReply(std::string_view offer, const std::string& address, const std::string& local_ip)>;

struct WebConfig {
    /// Address to bind ("127.0.0.1": loopback only).
    std::string bind = "127.0.0.1";
    /// TCP port; 0 lets the system choose (see listen_web's port).
    std::uint16_t port = 8080;
    /// Origins a page may come from besides the server's own
    /// (scheme://host[:port] of the Host header); a request without an
    /// Origin (no browser) is let in.
    std::vector<std::string> origins;
    /// Game sockets open at once (unit: sockets).
    std::size_t max_sockets = 256;
    /// Game sockets one IP address may hold before the server admits them
    /// (net::Transport::admit on a Hello); an upgrade beyond it is answered
    /// 503 with Retry-After. 0: no cap (unit: sockets).
    std::size_t max_pending_per_address = 4;
    /// Largest frame a page may send (unit: bytes).
    std::size_t max_frame_bytes = 4096;
    /// Bytes queued to one socket and not yet written; over it the socket is
    /// closed with kSendQueueFull (unit: bytes).
    std::size_t max_queued_bytes = 256 * 1024;
    /// A socket that sends nothing, not even a pong, this long is closed
    /// (unit: ms).
    std::uint32_t timeout_ms = 5000;
    /// TLS: a PEM certificate chain and its PEM private key; with them every
    /// connection is HTTPS and WSS, without them plain HTTP and WS.
    std::string cert_file;
    std::string key_file;
    /// POST /rtc (the WebRTC data channel's offer, Content-Type
    /// application/sdp), from an allowed Origin; unset: 404.
    SignalHandler rtc_signal;
};

/// Validates a WebConfig: "" or what is wrong.
std::string validate(const WebConfig& config);

/// The lowest peer id of a WebSocket (ENet's peers stay far below it).
inline constexpr net::PeerId kWebPeerBase = 0x40000000u;

/// WebSocket close codes of the transport itself (proto::CloseCode).
inline constexpr std::uint16_t kMalformedFrame = 4001;
inline constexpr std::uint16_t kSendQueueFull = 4003;

/// A listening web port: nullptr and `error` if it cannot bind or read
/// the TLS files; `port` gets the bound port.
std::unique_ptr<net::Transport> listen_web(const WebConfig& config, WebSite site, std::uint16_t& port,
                                           std::string& error);

/// Counters of a transport made by listen_web (zeros for any other).
struct WebStats {
    /// Sockets closed because their send queue overflowed.
    std::uint64_t send_queue_drops = 0;
    /// Sockets closed for a malformed frame (text, empty, bad channel, too big).
    std::uint64_t malformed_drops = 0;
    /// Upgrades refused: a foreign Origin, the socket cap, the pre-Hello cap.
    std::uint64_t origin_refusals = 0;
    std::uint64_t full_refusals = 0;
    std::uint64_t pre_hello_refusals = 0;
    /// Game sockets open now.
    std::uint64_t open_sockets = 0;
};
WebStats web_stats(const net::Transport& transport);

}  // namespace jetrace::web
