// A client transport whose connection can be cut, for the reconnect tests:
// sever() destroys the ENet connection without a Goodbye (the server sees a
// disconnect at once, as when a game crashes) and reports `disconnected` to
// its owner.
#pragma once

#include "jetrace/net/transport.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace jetrace::test {

class Severable final : public net::Transport {
public:
    explicit Severable(std::unique_ptr<net::Transport> inner) : inner_(std::move(inner)) {}
    void sever() {
        if (!inner_) return;
        last_totals_ = inner_->totals();
        inner_.reset();
    }
    bool severed() const { return !inner_; }
    void service(std::uint64_t now_ms, std::vector<net::Event>& events) override {
        if (inner_) return inner_->service(now_ms, events);
        if (!announced_) events.push_back({net::Event::Type::disconnected, 0, net::Channel::reliable, {}});
        announced_ = true;
    }
    bool send(net::PeerId p, net::Channel c, std::span<const std::uint8_t> d) override {
        return inner_ && inner_->send(p, c, d);
    }
    void disconnect(net::PeerId p) override {
        if (inner_) inner_->disconnect(p);
    }
    void flush() override {
        if (inner_) inner_->flush();
    }
    net::PeerStats peer_stats(net::PeerId p) const override {
        return inner_ ? inner_->peer_stats(p) : net::PeerStats{};
    }
    net::Totals totals() const override { return inner_ ? inner_->totals() : last_totals_; }
    std::uint16_t local_port() const override { return inner_ ? inner_->local_port() : 0; }

private:
    std::unique_ptr<net::Transport> inner_;
    net::Totals last_totals_;
    bool announced_ = false;
};

}  // namespace jetrace::test
