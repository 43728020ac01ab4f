// condition(): a Transport decorator that degrades the sending side.
//
// Every outgoing datagram goes through a DatagramScheduler (scheduler.hpp)
// on the caller's clock of the latest service(): one flow per peer, reliable
// channel = reliable datagrams (never dropped, duplicated or reordered; the
// reliability layer is below this decorator). service() hands the due ones
// to the inner transport. A disconnect is a barrier: it follows everything
// already queued for that peer. Incoming traffic and events pass through
// unchanged.
#include "jetrace/net/scheduler.hpp"
#include "jetrace/net/transport.hpp"

#include "limits.hpp"

#include <unordered_map>
#include <utility>

namespace jetrace::net {
namespace {

// The scheduler tag of a disconnect (channels are 0 and 1).
constexpr std::uint32_t kDisconnectTag = 0xFFFFu;

class Conditioner final : public Transport {
public:
    Conditioner(std::unique_ptr<Transport> inner, const Conditions& conditions)
        : inner_(std::move(inner)), scheduler_(conditions) {}

    void service(std::uint64_t now_ms, std::vector<Event>& events) override {
        now_ms_ = now_ms;
        due_.clear();
        scheduler_.pop_due(static_cast<double>(now_ms), due_);
        for (ScheduledDatagram& d : due_) {
            const auto peer = static_cast<PeerId>(d.flow);
            if (d.tag == kDisconnectTag) {
                inner_->disconnect(peer);
            } else {
                inner_->send(peer, static_cast<Channel>(d.tag), d.data);
            }
        }
        const std::size_t first = events.size();
        inner_->service(now_ms, events);
        for (std::size_t i = first; i < events.size(); ++i) track(events[i]);
    }

    bool send(PeerId peer, Channel channel, std::span<const std::uint8_t> data) override {
        if (data.size() > detail::kMaxDatagramBytes) return false;
        if (channel != Channel::reliable && channel != Channel::unreliable) return false;
        const auto it = closing_.find(peer);
        if (it == closing_.end() || it->second) return false;
        ScheduledDatagram d;
        d.flow = peer;
        d.reliable = channel == Channel::reliable;
        d.tag = static_cast<std::uint32_t>(channel);
        d.data.assign(data.begin(), data.end());
        scheduler_.push(static_cast<double>(now_ms_), std::move(d));
        return true;  // even if dropped: the sender cannot tell
    }

    void disconnect(PeerId peer) override {
        const auto it = closing_.find(peer);
        if (it == closing_.end()) {
            inner_->disconnect(peer);  // e.g. a connection attempt still pending
            return;
        }
        if (it->second) return;
        it->second = true;
        ScheduledDatagram marker;
        marker.flow = peer;
        marker.reliable = true;
        marker.tag = kDisconnectTag;
        scheduler_.push_barrier(static_cast<double>(now_ms_), std::move(marker));
    }

    void admit(PeerId peer) override { inner_->admit(peer); }
    void flush() override { inner_->flush(); }
    PeerStats peer_stats(PeerId peer) const override { return inner_->peer_stats(peer); }
    Totals totals() const override { return inner_->totals(); }
    std::uint16_t local_port() const override { return inner_->local_port(); }

    const SchedulerStats& stats() const { return scheduler_.stats(); }

private:
    void track(const Event& event) {
        if (event.type == Event::Type::connected) {
            closing_[event.peer] = false;
        } else if (event.type == Event::Type::disconnected) {
            closing_.erase(event.peer);
            scheduler_.forget(event.peer);
        }
    }

    std::unique_ptr<Transport> inner_;
    DatagramScheduler scheduler_;
    std::uint64_t now_ms_ = 0;
    std::unordered_map<PeerId, bool> closing_;  // connected peers seen in events: closing?
    std::vector<ScheduledDatagram> due_;
};

}  // namespace

std::unique_ptr<Transport> condition(std::unique_ptr<Transport> inner, const Conditions& conditions) {
    if (!inner) return nullptr;
    return std::make_unique<Conditioner>(std::move(inner), conditions);
}

SchedulerStats conditioner_stats(const Transport& transport) {
    if (const auto* conditioner = dynamic_cast<const Conditioner*>(&transport)) return conditioner->stats();
    return {};
}

}  // namespace jetrace::net
