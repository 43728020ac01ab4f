// condition(): a Transport decorator that degrades the sending side.
//
// Every outgoing datagram is queued with a release time (caller's clock of the
// latest service() + latency + uniform jitter) and handed to the inner
// transport by service() once due, in (release time, arrival) order.
// Reliable datagrams are never dropped, duplicated or reordered: each peer's
// reliable release times never decrease. Unreliable datagrams may be dropped,
// duplicated (the copy draws its own jitter) or held back until the next
// unreliable datagram to the same peer has been queued (then released right
// after it). Incoming traffic and events pass through unchanged.
//
// Every random choice comes from a seeded std::mt19937_64 with a fixed
// mapping to [0, 1), and the same number of draws is taken per datagram, so a
// given sequence of calls always produces the same outcome.
#include "jetrace/net/transport.hpp"

#include "limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <unordered_map>
#include <utility>

namespace jetrace::net {
namespace {

double clamp_fraction(double p) { return std::isfinite(p) ? std::clamp(p, 0.0, 1.0) : 0.0; }
double clamp_ms(double ms) { return std::isfinite(ms) ? std::max(ms, 0.0) : 0.0; }

class Conditioner final : public Transport {
public:
    Conditioner(std::unique_ptr<Transport> inner, const Conditions& conditions)
        : inner_(std::move(inner)), rng_(conditions.seed) {
        conditions_.latency_ms = clamp_ms(conditions.latency_ms);
        conditions_.jitter_ms = clamp_ms(conditions.jitter_ms);
        conditions_.loss = clamp_fraction(conditions.loss);
        conditions_.duplicate = clamp_fraction(conditions.duplicate);
        conditions_.reorder = clamp_fraction(conditions.reorder);
        conditions_.seed = conditions.seed;
    }

    void service(std::uint64_t now_ms, std::vector<Event>& events) override {
        now_ms_ = now_ms;
        release_overdue_held();
        release_due();
        const std::size_t first = events.size();
        inner_->service(now_ms, events);
        for (std::size_t i = first; i < events.size(); ++i) track(events[i]);
    }

    bool send(PeerId peer, Channel channel, std::span<const std::uint8_t> data) override {
        if (data.size() > detail::kMaxDatagramBytes) return false;
        if (channel != Channel::reliable && channel != Channel::unreliable) return false;
        const auto it = peers_.find(peer);
        if (it == peers_.end() || it->second.closing) return false;
        PeerState& state = it->second;
        const double now = static_cast<double>(now_ms_);
        const double base = now + conditions_.latency_ms;

        Item item;
        item.peer = peer;
        item.channel = channel;
        item.sent_at = now;
        item.data.assign(data.begin(), data.end());

        if (channel == Channel::reliable) {
            item.release = std::max(base + uniform() * conditions_.jitter_ms, state.last_reliable);
            state.last_reliable = item.release;
            enqueue(std::move(item));
            return true;
        }

        const double u_loss = uniform();
        const double u_duplicate = uniform();
        const double u_reorder = uniform();
        const double jitter = uniform() * conditions_.jitter_ms;
        const double copy_jitter = uniform() * conditions_.jitter_ms;
        if (u_loss < conditions_.loss) {
            ++stats_.dropped;
            return true;  // the sender cannot tell
        }
        item.release = base + jitter;
        std::optional<Item> copy;
        if (u_duplicate < conditions_.duplicate) {
            ++stats_.duplicated;
            copy = item;
            copy->release = base + copy_jitter;
        }
        if (state.held) {
            // The held datagram goes right behind this one.
            Item held = std::move(*state.held);
            state.held.reset();
            held.release = std::max(held.release, item.release);
            enqueue(std::move(item));
            if (copy) enqueue(std::move(*copy));
            ++stats_.reordered;
            enqueue(std::move(held));
        } else if (u_reorder < conditions_.reorder) {
            state.held = std::move(item);
            if (copy) enqueue(std::move(*copy));
        } else {
            enqueue(std::move(item));
            if (copy) enqueue(std::move(*copy));
        }
        return true;
    }

    void disconnect(PeerId peer) override {
        const auto it = peers_.find(peer);
        if (it == peers_.end()) {
            inner_->disconnect(peer);  // e.g. a connection attempt still pending
            return;
        }
        PeerState& state = it->second;
        if (state.closing) return;
        state.closing = true;
        if (state.held) {
            enqueue(std::move(*state.held));
            state.held.reset();
        }
        // The disconnect follows everything already queued for this peer.
        Item marker;
        marker.peer = peer;
        marker.disconnect = true;
        marker.sent_at = static_cast<double>(now_ms_);
        marker.release = std::max(marker.sent_at + conditions_.latency_ms, state.last_reliable);
        for (const Item& queued : queue_) {
            if (queued.peer == peer) marker.release = std::max(marker.release, queued.release);
        }
        enqueue(std::move(marker));
    }

    void flush() override { inner_->flush(); }
    PeerStats peer_stats(PeerId peer) const override { return inner_->peer_stats(peer); }
    Totals totals() const override { return inner_->totals(); }
    std::uint16_t local_port() const override { return inner_->local_port(); }

    ConditionerStats stats() const { return stats_; }

private:
    // A held datagram with no successor is let go alone after this long (unit: ms).
    static constexpr double kMaxHoldMs = 100.0;

    struct Item {
        double release = 0;
        double sent_at = 0;
        std::uint64_t seq = 0;
        PeerId peer = 0;
        Channel channel = Channel::unreliable;
        bool disconnect = false;
        std::vector<std::uint8_t> data;
    };

    struct PeerState {
        double last_reliable = -std::numeric_limits<double>::infinity();
        bool closing = false;
        std::optional<Item> held;
    };

    // Heap order: the earliest release (then the earliest queued) on top.
    static bool later(const Item& a, const Item& b) {
        if (a.release != b.release) return a.release > b.release;
        return a.seq > b.seq;
    }

    double uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

    void enqueue(Item item) {
        item.seq = next_seq_++;
        if (item.release > item.sent_at) ++stats_.delayed;
        queue_.push_back(std::move(item));
        std::push_heap(queue_.begin(), queue_.end(), later);
    }

    void release_due() {
        const double now = static_cast<double>(now_ms_);
        while (!queue_.empty() && queue_.front().release <= now) {
            std::pop_heap(queue_.begin(), queue_.end(), later);
            Item item = std::move(queue_.back());
            queue_.pop_back();
            if (item.disconnect) {
                inner_->disconnect(item.peer);
            } else {
                inner_->send(item.peer, item.channel, item.data);
            }
        }
    }

    void release_overdue_held() {
        const double now = static_cast<double>(now_ms_);
        for (auto& [peer, state] : peers_) {
            if (state.held && now >= state.held->release + kMaxHoldMs) {
                enqueue(std::move(*state.held));
                state.held.reset();
            }
        }
    }

    void track(const Event& event) {
        if (event.type == Event::Type::connected) {
            peers_[event.peer] = PeerState{};
        } else if (event.type == Event::Type::disconnected) {
            peers_.erase(event.peer);
            const auto removed = std::erase_if(queue_, [&](const Item& item) { return item.peer == event.peer; });
            if (removed > 0) std::make_heap(queue_.begin(), queue_.end(), later);
        }
    }

    std::unique_ptr<Transport> inner_;
    Conditions conditions_;
    std::mt19937_64 rng_;
    std::uint64_t now_ms_ = 0;
    std::uint64_t next_seq_ = 0;
    std::vector<Item> queue_;  // a heap ordered by later()
    std::unordered_map<PeerId, PeerState> peers_;  // connected peers seen in events
    ConditionerStats stats_;
};

}  // namespace

std::unique_ptr<Transport> condition(std::unique_ptr<Transport> inner, const Conditions& conditions) {
    if (!inner) return nullptr;
    return std::make_unique<Conditioner>(std::move(inner), conditions);
}

ConditionerStats conditioner_stats(const Transport& transport) {
    if (const auto* conditioner = dynamic_cast<const Conditioner*>(&transport)) return conditioner->stats();
    return {};
}

}  // namespace jetrace::net
