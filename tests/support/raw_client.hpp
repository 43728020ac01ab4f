// A client that speaks raw bytes to a live server: it sends whatever a test
// crafts (a hand-made Hello, junk, messages out of order) and remembers what
// the server answered.
#pragma once

#include "jetrace/net/transport.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace jetrace::test {

/// The server's answer to a Hello: Welcome or Refuse (monostate: none yet).
using Answer = std::variant<std::monostate, proto::Welcome, proto::Refuse>;

/// The reason of a Refuse answer, or what came instead.
inline std::string refusal(const Answer& a) {
    if (const auto* r = std::get_if<proto::Refuse>(&a)) return r->reason;
    return a.index() == 1 ? "(welcomed)" : "(no answer)";
}

class RawClient {
public:
    /// Over `transport`, a connection to the server (null: none, see `error`).
    explicit RawClient(std::unique_ptr<net::Transport> transport, std::string connect_error = {})
        : error(std::move(connect_error)), transport_(std::move(transport)) {}

    bool ok() const { return transport_ != nullptr; }

    /// Handles the connection's events at `now_ms` (the caller's clock), then flushes.
    void service(std::uint64_t now_ms) {
        if (!transport_) return;
        events_.clear();
        transport_->service(now_ms, events_);
        for (const net::Event& e : events_) {
            if (e.type == net::Event::Type::connected) {
                connected = true;
                if (greeting_) send(*greeting_);
            }
            if (e.type == net::Event::Type::disconnected) disconnected = true;
            if (e.type != net::Event::Type::received) continue;
            proto::Message m;
            std::string why;
            if (!proto::decode(e.data, m, why)) continue;
            if (const auto* w = std::get_if<proto::Welcome>(&m)) welcome = *w;
            if (const auto* r = std::get_if<proto::Refuse>(&m)) {
                refused = true;
                refuse = r->reason;
            }
            if (const auto* g = std::get_if<proto::Goodbye>(&m)) goodbye = g->reason;
            if (const auto* s = std::get_if<proto::Snapshot>(&m)) {
                ++snapshots;
                if (s->phase == proto::RacePhase::countdown || s->phase == proto::RacePhase::racing)
                    server_tick = s->server_tick;
            }
        }
        transport_->flush();
    }
    bool send(std::span<const std::uint8_t> bytes, net::Channel channel = net::Channel::reliable) {
        return transport_ && transport_->send(0, channel, bytes);
    }
    bool send(const proto::Message& m, net::Channel channel = net::Channel::reliable) {
        return send(proto::encode(m), channel);
    }
    /// Sends `m` as soon as the connection is up (within the service() that sees it).
    void send_on_connect(proto::Message m) { greeting_ = std::move(m); }
    /// Says Goodbye and closes the connection.
    void leave(const std::string& reason) {
        if (!transport_) return;
        send(proto::Goodbye{reason});
        transport_->disconnect(0);
        transport_->flush();
    }
    /// Stops answering (never serviced again), like a machine that vanished.
    void vanish() { vanished = true; }

    /// The Welcome or Refuse received (a Welcome first).
    Answer answer() const {
        if (welcome) return *welcome;
        if (refused) return proto::Refuse{refuse};
        return {};
    }

    std::string error;
    bool connected = false;
    bool disconnected = false;
    bool vanished = false;
    std::optional<proto::Welcome> welcome;
    bool refused = false;
    std::string refuse;
    std::string goodbye;
    std::uint64_t snapshots = 0;
    /// Newest server tick of a countdown or racing snapshot.
    std::uint32_t server_tick = 0;

private:
    std::unique_ptr<net::Transport> transport_;
    std::vector<net::Event> events_;
    std::optional<proto::Message> greeting_;
};

}  // namespace jetrace::test
