#include "jetrace/net/mux_transport.hpp"

#include <cassert>

namespace jetrace::net {
namespace {

class MuxTransport final : public Transport {
public:
    MuxTransport(std::unique_ptr<Transport> first, std::unique_ptr<Transport> second, PeerId base, std::string name)
        : first_(std::move(first)), second_(std::move(second)), base_(base), name_(std::move(name)) {
        assert(first_ && second_ && base_ > 0);
    }

    void service(std::uint64_t now_ms, std::vector<Event>& events) override {
        first_->service(now_ms, events);
        second_->service(now_ms, events);
    }
    bool send(PeerId peer, Channel channel, std::span<const std::uint8_t> data) override {
        return part(peer).send(peer, channel, data);
    }
    void disconnect(PeerId peer) override { part(peer).disconnect(peer); }
    void admit(PeerId peer) override { part(peer).admit(peer); }
    void flush() override {
        first_->flush();
        second_->flush();
    }
    PeerStats peer_stats(PeerId peer) const override { return part(peer).peer_stats(peer); }
    Totals totals() const override {
        Totals a = first_->totals();
        const Totals b = second_->totals();
        a.bytes_sent += b.bytes_sent;
        a.bytes_received += b.bytes_received;
        a.packets_sent += b.packets_sent;
        a.packets_received += b.packets_received;
        a.connects_refused += b.connects_refused;
        return a;
    }
    std::uint16_t local_port() const override { return first_->local_port(); }

    bool second(PeerId peer) const { return peer >= base_; }
    const Transport& part(int index) const { return index == 0 ? *first_ : *second_; }
    const std::string& name() const { return name_; }

private:
    Transport& part(PeerId peer) { return second(peer) ? *second_ : *first_; }
    const Transport& part(PeerId peer) const { return second(peer) ? *second_ : *first_; }

    std::unique_ptr<Transport> first_, second_;
    PeerId base_;
    std::string name_;
};

}  // namespace

std::unique_ptr<Transport> combine(std::unique_ptr<Transport> first, std::unique_ptr<Transport> second,
                                   PeerId second_base, std::string second_name) {
    return std::make_unique<MuxTransport>(std::move(first), std::move(second), second_base, std::move(second_name));
}

std::string transport_of(const Transport& transport, PeerId peer) {
    const auto* mux = dynamic_cast<const MuxTransport*>(&transport);
    if (mux == nullptr) return "enet";
    return mux->second(peer) ? mux->name() : transport_of(mux->part(0), peer);
}

Totals part_totals(const Transport& transport, const std::string& name) {
    const auto* mux = dynamic_cast<const MuxTransport*>(&transport);
    if (mux == nullptr) return name == "enet" ? transport.totals() : Totals{};
    return mux->name() == name ? mux->part(1).totals() : part_totals(mux->part(0), name);
}

}  // namespace jetrace::net
