// The WebAssembly client's transport: one browser WebSocket to
// jetrace-server's /play, opened and fed by the page's JavaScript
// (client_source.js) through the Module.jetraceSocket hooks. Each binary
// frame is a channel byte and one protocol message (docs/PROTOCOL.md,
// "WebSocket"). The browser gives no round trip, so peer_stats() is empty
// (RaceClient measures one in ticks: ClientStats::tick_round_trip_ms).
#pragma once

#include "jetrace/net/transport.hpp"

#include <cstdint>
#include <vector>

namespace jetrace::webclient {

class SocketTransport final : public net::Transport {
public:
    /// Asks the page to open socket `id`.
    explicit SocketTransport(int id);
    /// Asks the page to close the socket, if it is still open.
    ~SocketTransport() override;
    SocketTransport(const SocketTransport&) = delete;
    SocketTransport& operator=(const SocketTransport&) = delete;

    /// The socket of `id` (nullptr: closed and forgotten).
    static SocketTransport* find(int id);

    /// From the page: the socket opened, a frame arrived, it closed (with
    /// the WebSocket close code; 3000-4999 become Event::close_code).
    void opened();
    void frame(const std::uint8_t* data, std::size_t size);
    void closed(int code);

    void service(std::uint64_t now_ms, std::vector<net::Event>& events) override;
    bool send(net::PeerId peer, net::Channel channel, std::span<const std::uint8_t> data) override;
    void disconnect(net::PeerId peer) override;
    void flush() override {}
    net::PeerStats peer_stats(net::PeerId) const override { return {}; }
    net::Totals totals() const override { return totals_; }
    std::uint16_t local_port() const override { return 0; }

private:
    int id_;
    bool open_ = false;
    bool closed_ = false;
    std::vector<net::Event> pending_;
    net::Totals totals_;
};

}  // namespace jetrace::webclient
