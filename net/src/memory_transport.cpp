// The client ends of the in-memory network (memory_network.hpp), and the hub.
#include "memory_network.hpp"

namespace jetrace::net {
namespace {

using detail::Item;
using detail::ItemKind;
using detail::Side;

class MemoryClient final : public Transport {
public:
    explicit MemoryClient(std::shared_ptr<detail::MemoryNetwork> net) : net_(std::move(net)), link_(net_->next_link++) {
        detail::Link& link = net_->links[link_];
        if (net_->server_alive) {
            net_->push_to_server(net_->item(ItemKind::connect, link_));
            return;
        }
        link.client = Side::closed;
        link.server = Side::closed;
        net_->forget_if_done(link_);
        pending_.push_back(detail::event(Event::Type::disconnected, 0));
    }

    ~MemoryClient() override {
        detail::Link* link = net_->find(link_);
        if (link == nullptr) return;
        if (link->client == Side::waiting || link->client == Side::open) {
            net_->push_to_server(net_->item(ItemKind::close, link_));
        }
        link->client = Side::closed;
        link->to_client.clear();
        net_->forget_if_done(link_);
    }

    MemoryClient(const MemoryClient&) = delete;
    MemoryClient& operator=(const MemoryClient&) = delete;

    void service(std::uint64_t now_ms, std::vector<Event>& events) override {
        net_->advance(now_ms);
        for (Event& e : pending_) events.push_back(std::move(e));
        pending_.clear();
        for (detail::Link* link = net_->find(link_);
             link != nullptr && !link->to_client.empty() && link->to_client.front().due_ms <= net_->now_ms;
             link = net_->find(link_)) {
            Item it = std::move(link->to_client.front());
            link->to_client.pop_front();
            handle(*link, it, events);
        }
    }

    bool send(PeerId peer, Channel channel, std::span<const std::uint8_t> data) override {
        const detail::Link* link = net_->find(link_);
        if (peer != 0 || !detail::sendable(channel, data) || link == nullptr || link->client != Side::open) return false;
        net_->push_to_server(net_->item(ItemKind::data, link_, channel, data));
        detail::count_sent(totals_, data);
        return true;
    }

    void disconnect(PeerId peer) override {
        detail::Link* link = net_->find(link_);
        if (peer != 0 || link == nullptr) return;
        if (link->client == Side::waiting) {
            // Not connected yet: closed on the spot, reported on the next service().
            link->client = Side::closed;
            link->to_client.clear();
            pending_.push_back(detail::event(Event::Type::disconnected, 0));
            net_->push_to_server(net_->item(ItemKind::close, link_));
            net_->forget_if_done(link_);
        } else if (link->client == Side::open) {
            link->client = Side::closing;
            net_->push_to_server(net_->item(ItemKind::close, link_));
        }
    }

    void flush() override {}

    PeerStats peer_stats(PeerId peer) const override {
        PeerStats stats;
        const detail::Link* link = net_->find(link_);
        if (peer == 0 && link != nullptr && (link->client == Side::open || link->client == Side::closing)) {
            stats.rtt_ms = 2.0 * net_->config.latency_ms;
        }
        return stats;
    }

    Totals totals() const override { return totals_; }
    std::uint16_t local_port() const override { return 0; }  // no socket

private:
    void handle(detail::Link& link, const Item& it, std::vector<Event>& events) {
        switch (it.kind) {
            case ItemKind::accept:
                if (link.client != Side::waiting) break;
                link.client = Side::open;
                events.push_back(detail::event(Event::Type::connected, 0));
                break;
            case ItemKind::data:
                if (link.client != Side::open) break;
                detail::count_received(totals_, it);
                events.push_back(detail::event(Event::Type::received, 0, it.channel, it.data));
                break;
            case ItemKind::refuse:
            case ItemKind::close:
            case ItemKind::ack: {
                const bool closes = it.kind == ItemKind::ack ? link.client == Side::closing : link.client != Side::closed;
                if (!closes) break;
                link.client = Side::closed;
                link.to_client.clear();
                events.push_back(detail::event(Event::Type::disconnected, 0));
                if (it.kind == ItemKind::close) net_->push_to_server(net_->item(ItemKind::ack, link_));
                net_->forget_if_done(link_);
                break;
            }
            case ItemKind::connect: break;  // never sent to a client
        }
    }

    std::shared_ptr<detail::MemoryNetwork> net_;
    std::uint64_t link_;
    std::vector<Event> pending_;
    Totals totals_;
};

}  // namespace

MemoryHub::MemoryHub(const MemoryHubConfig& config) : net_(std::make_shared<detail::MemoryNetwork>(config)) {}

MemoryHub::~MemoryHub() = default;

std::unique_ptr<Transport> MemoryHub::listen() {
    if (net_->server_alive) return nullptr;
    return detail::make_memory_server(net_);
}

std::unique_ptr<Transport> MemoryHub::connect() { return std::make_unique<MemoryClient>(net_); }

}  // namespace jetrace::net
