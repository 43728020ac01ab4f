// condition() and condition_link(): Transport decorators that put network
// conditions on a transport's links (transport.hpp, link_conditions.hpp).
//
// Outgoing: every datagram goes through a DatagramScheduler (scheduler.hpp)
// on the caller's clock of the latest service(), one flow per peer;
// service() hands the due ones to the inner transport. A disconnect is a
// barrier: it follows everything already queued for that peer.
// Incoming (condition_link only): every datagram the inner transport
// receives goes through a second scheduler and is handed on as an event
// when due; a disconnection follows everything queued from that peer.
// Reliable datagrams (every one, for a stream) keep their order; they are
// lost only as Conditions::retransmit_ms says.
#include "jetrace/net/link_conditions.hpp"
#include "jetrace/net/scheduler.hpp"
#include "jetrace/net/transport.hpp"

#include "limits.hpp"

#include <optional>
#include <unordered_map>
#include <utility>

namespace jetrace::net {
namespace {

// The scheduler tag of a disconnect (channels are 0 and 1); incoming, the
// close code rides in the low 16 bits of kDisconnectTag << 16.
constexpr std::uint32_t kDisconnectTag = 0xFFFFu;

class Conditioner final : public Transport {
public:
    Conditioner(std::unique_ptr<Transport> inner, const Conditions& outgoing, std::optional<Conditions> incoming,
                Delivery delivery, LinkObserver* observer)
        : inner_(std::move(inner)), scheduler_(outgoing), delivery_(delivery), observer_(observer) {
        if (incoming) incoming_.emplace(*incoming);
    }

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
        if (!incoming_) {
            const std::size_t first = events.size();
            inner_->service(now_ms, events);
            for (std::size_t i = first; i < events.size(); ++i) track(events[i]);
            return;
        }
        inner_events_.clear();
        inner_->service(now_ms, inner_events_);
        for (Event& e : inner_events_) take(std::move(e), events);
        hand_on_due(events);
    }

    bool send(PeerId peer, Channel channel, std::span<const std::uint8_t> data) override {
        if (data.size() > detail::kMaxDatagramBytes) return false;
        if (channel != Channel::reliable && channel != Channel::unreliable) return false;
        const auto it = closing_.find(peer);
        if (it == closing_.end() || it->second) return false;
        ScheduledDatagram d;
        d.flow = peer;
        d.reliable = delivery_ == Delivery::stream || channel == Channel::reliable;
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

    /// An inner event, incoming conditioned: received datagrams and
    /// disconnections queue; connections pass at once.
    void take(Event&& e, std::vector<Event>& events) {
        track(e);
        const double now = static_cast<double>(now_ms_);
        if (e.type == Event::Type::connected) {
            events.push_back(std::move(e));
            return;
        }
        ScheduledDatagram d;
        d.flow = e.peer;
        if (e.type == Event::Type::disconnected) {
            d.reliable = true;
            d.tag = (kDisconnectTag << 16) | e.close_code;
            incoming_->push_barrier(now, std::move(d));
            return;
        }
        if (observer_) observer_->arrived(e.peer, now, e.data);
        d.reliable = delivery_ == Delivery::stream || e.channel == Channel::reliable;
        d.tag = static_cast<std::uint32_t>(e.channel);
        d.data = std::move(e.data);
        incoming_->push(now, std::move(d));
    }

    void hand_on_due(std::vector<Event>& events) {
        due_.clear();
        incoming_->pop_due(static_cast<double>(now_ms_), due_);
        for (ScheduledDatagram& d : due_) {
            Event e;
            e.peer = static_cast<PeerId>(d.flow);
            if ((d.tag >> 16) == kDisconnectTag) {
                e.type = Event::Type::disconnected;
                e.close_code = static_cast<std::uint16_t>(d.tag & 0xFFFFu);
                incoming_->forget(d.flow);
            } else {
                e.type = Event::Type::received;
                e.channel = static_cast<Channel>(d.tag);
                if (observer_) observer_->delivered(e.peer, static_cast<double>(now_ms_), d.data);
                e.data = std::move(d.data);
            }
            events.push_back(std::move(e));
        }
    }

    std::unique_ptr<Transport> inner_;
    DatagramScheduler scheduler_;
    std::optional<DatagramScheduler> incoming_;
    Delivery delivery_ = Delivery::datagrams;
    LinkObserver* observer_ = nullptr;
    std::uint64_t now_ms_ = 0;
    std::unordered_map<PeerId, bool> closing_;  // connected peers seen in events: closing?
    std::vector<ScheduledDatagram> due_;
    std::vector<Event> inner_events_;
};

}  // namespace

std::unique_ptr<Transport> condition(std::unique_ptr<Transport> inner, const Conditions& conditions) {
    if (!inner) return nullptr;
    return std::make_unique<Conditioner>(std::move(inner), conditions, std::nullopt, Delivery::datagrams, nullptr);
}

std::unique_ptr<Transport> condition_link(std::unique_ptr<Transport> inner, const LinkConditions& link,
                                          LinkObserver* observer) {
    if (!inner) return nullptr;
    return std::make_unique<Conditioner>(std::move(inner), link.outgoing, link.incoming, link.delivery, observer);
}

SchedulerStats conditioner_stats(const Transport& transport) {
    if (const auto* conditioner = dynamic_cast<const Conditioner*>(&transport)) return conditioner->stats();
    return {};
}

}  // namespace jetrace::net
