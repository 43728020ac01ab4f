// The skeleton of a test decorator over a real transport: every call goes to
// the wrapped one, so a decorator overrides only the calls it changes (a
// client that cheats on send(), say).
#pragma once

#include "jetrace/net/transport.hpp"

#include <cassert>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace jetrace::test {

class ForwardingTransport : public net::Transport {
public:
    explicit ForwardingTransport(std::unique_ptr<net::Transport> inner) : inner_(std::move(inner)) {
        assert(inner_ != nullptr);
    }
    void service(std::uint64_t now_ms, std::vector<net::Event>& events) override { inner_->service(now_ms, events); }
    bool send(net::PeerId peer, net::Channel channel, std::span<const std::uint8_t> data) override {
        return inner_->send(peer, channel, data);
    }
    void disconnect(net::PeerId peer) override { inner_->disconnect(peer); }
    void admit(net::PeerId peer) override { inner_->admit(peer); }
    void flush() override { inner_->flush(); }
    net::PeerStats peer_stats(net::PeerId peer) const override { return inner_->peer_stats(peer); }
    net::Totals totals() const override { return inner_->totals(); }
    std::uint16_t local_port() const override { return inner_->local_port(); }

protected:
    net::Transport& inner() { return *inner_; }

private:
    std::unique_ptr<net::Transport> inner_;
};

}  // namespace jetrace::test
