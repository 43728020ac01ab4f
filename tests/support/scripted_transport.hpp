// A net::Transport with no network: the test scripts the events service()
// hands out (connects, drops, datagrams) and reads back, in order, what was
// sent and disconnected. Tests that need more (checks on every datagram,
// stamped times) set its clock or its on_send hook instead of writing
// another fake.
#pragma once

#include "jetrace/net/transport.hpp"

#include <algorithm>
#include <cstdint>
#include <deque>
#include <functional>
#include <iterator>
#include <span>
#include <utility>
#include <vector>

namespace jetrace::test {

class ScriptedTransport : public net::Transport {
public:
    /// One call the transport received: a datagram sent or a disconnect.
    struct Record {
        enum class Kind : std::uint8_t { sent, disconnect };
        Kind kind = Kind::sent;
        /// The test's clock at the call (0 without a clock) (unit: ms).
        std::uint64_t at_ms = 0;
        net::PeerId peer = 0;
        /// Channel::reliable for a disconnect.
        net::Channel channel = net::Channel::reliable;
        std::vector<std::uint8_t> data;
    };

    /// `clock` (unit: ms), if given, stamps every record: the caller's clock
    /// at the call, which service()'s argument would lag for sends a
    /// decorator releases before it services its inner transport.
    explicit ScriptedTransport(const std::uint64_t* clock = nullptr) : clock_(clock) {}

    /// Called with every datagram before it is recorded.
    std::function<void(const Record&)> on_send;

    // The script: what the next service() hands out, in this order.
    void connect(net::PeerId peer = 0) { script(net::Event::Type::connected, peer, net::Channel::reliable, {}); }
    /// `close_code`: what the disconnect carries (net::Event::close_code).
    void drop(net::PeerId peer = 0, std::uint16_t close_code = 0) {
        script(net::Event::Type::disconnected, peer, net::Channel::reliable, {});
        pending_.back().close_code = close_code;
    }
    void deliver(net::PeerId peer, net::Channel channel, std::vector<std::uint8_t> data) {
        script(net::Event::Type::received, peer, channel, std::move(data));
    }

    // What happened.
    const std::vector<Record>& log() const { return log_; }
    /// The datagrams only, in the order they were sent.
    std::vector<Record> sent() const {
        std::vector<Record> out;
        std::copy_if(log_.begin(), log_.end(), std::back_inserter(out),
                     [](const Record& r) { return r.kind == Record::Kind::sent; });
        return out;
    }
    bool disconnected() const {
        return std::any_of(log_.begin(), log_.end(),
                           [](const Record& r) { return r.kind == Record::Kind::disconnect; });
    }

    void service(std::uint64_t /*now_ms*/, std::vector<net::Event>& events) override {
        for (; !pending_.empty(); pending_.pop_front()) events.push_back(std::move(pending_.front()));
    }
    bool send(net::PeerId peer, net::Channel channel, std::span<const std::uint8_t> data) override {
        Record r{Record::Kind::sent, now(), peer, channel, {data.begin(), data.end()}};
        if (on_send) on_send(r);
        log_.push_back(std::move(r));
        return true;
    }
    void disconnect(net::PeerId peer) override {
        log_.push_back({Record::Kind::disconnect, now(), peer, net::Channel::reliable, {}});
    }
    void flush() override {}
    net::PeerStats peer_stats(net::PeerId) const override { return {}; }
    net::Totals totals() const override { return {}; }
    std::uint16_t local_port() const override { return 0; }

private:
    void script(net::Event::Type type, net::PeerId peer, net::Channel channel, std::vector<std::uint8_t> data) {
        pending_.push_back({type, peer, channel, std::move(data)});
    }
    std::uint64_t now() const { return clock_ != nullptr ? *clock_ : 0; }

    const std::uint64_t* clock_;
    std::deque<net::Event> pending_;
    std::vector<Record> log_;
};

}  // namespace jetrace::test
