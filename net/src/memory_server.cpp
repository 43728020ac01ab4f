// The server end of the in-memory network (memory_network.hpp).
#include "memory_network.hpp"

namespace jetrace::net {
namespace {

using detail::Item;
using detail::ItemKind;
using detail::Side;

class MemoryServer final : public Transport {
public:
    explicit MemoryServer(std::shared_ptr<detail::MemoryNetwork> net) : net_(std::move(net)) {
        net_->server_alive = true;
    }

    ~MemoryServer() override {
        std::vector<std::uint64_t> ids;
        for (auto& [id, link] : net_->links) {
            if (link.server == Side::closed) continue;
            net_->push_to_client(net_->item(link.server == Side::waiting ? ItemKind::refuse : ItemKind::close, id));
            link.server = Side::closed;
            ids.push_back(id);
        }
        for (std::uint64_t id : ids) net_->forget_if_done(id);
        net_->server_alive = false;
        net_->to_server.clear();
    }

    MemoryServer(const MemoryServer&) = delete;
    MemoryServer& operator=(const MemoryServer&) = delete;

    void service(std::uint64_t now_ms, std::vector<Event>& events) override {
        net_->advance(now_ms);
        while (!net_->to_server.empty() && net_->to_server.front().due_ms <= net_->now_ms) {
            Item it = std::move(net_->to_server.front());
            net_->to_server.pop_front();
            handle(it, events);
        }
    }

    bool send(PeerId peer, Channel channel, std::span<const std::uint8_t> data) override {
        if (!detail::sendable(channel, data)) return false;
        const auto it = peers_.find(peer);
        if (it == peers_.end() || net_->find(it->second)->server != Side::open) return false;
        net_->push_to_client(net_->item(ItemKind::data, it->second, channel, data));
        detail::count_sent(totals_, data);
        return true;
    }

    void disconnect(PeerId peer) override {
        const auto it = peers_.find(peer);
        if (it == peers_.end()) return;
        detail::Link& link = *net_->find(it->second);
        if (link.server != Side::open) return;
        link.server = Side::closing;
        net_->push_to_client(net_->item(ItemKind::close, it->second));
    }

    void flush() override {}

    PeerStats peer_stats(PeerId peer) const override {
        PeerStats stats;
        if (peers_.count(peer) > 0) stats.rtt_ms = 2.0 * net_->config.latency_ms;
        return stats;
    }

    Totals totals() const override { return totals_; }
    std::uint16_t local_port() const override { return 0; }  // no socket

private:
    void handle(const Item& it, std::vector<Event>& events) {
        detail::Link* link = net_->find(it.link);
        if (link == nullptr) return;
        switch (it.kind) {
            case ItemKind::connect: accept(it.link, *link, events); break;
            case ItemKind::data:
                if (link->server != Side::open) break;
                detail::count_received(totals_, it);
                events.push_back(detail::event(Event::Type::received, ids_.at(it.link), it.channel, it.data));
                break;
            case ItemKind::close:
            case ItemKind::ack: {
                const bool closes = link->server == Side::closing || (it.kind == ItemKind::close && link->server == Side::open);
                if (!closes) break;
                const PeerId peer = ids_.at(it.link);
                events.push_back(detail::event(Event::Type::disconnected, peer));
                link->server = Side::closed;
                peers_.erase(peer);
                ids_.erase(it.link);
                if (it.kind == ItemKind::close) net_->push_to_client(net_->item(ItemKind::ack, it.link));
                net_->forget_if_done(it.link);
                break;
            }
            case ItemKind::accept:
            case ItemKind::refuse: break;  // never sent to the server
        }
    }

    void accept(std::uint64_t id, detail::Link& link, std::vector<Event>& events) {
        if (link.server != Side::waiting) return;
        if (peers_.size() >= net_->config.max_connections) {
            link.server = Side::closed;
            net_->push_to_client(net_->item(ItemKind::refuse, id));
            net_->forget_if_done(id);
            return;
        }
        const PeerId peer = next_id_++;
        peers_[peer] = id;
        ids_[id] = peer;
        link.server = Side::open;
        events.push_back(detail::event(Event::Type::connected, peer));
        net_->push_to_client(net_->item(ItemKind::accept, id));
    }

    std::shared_ptr<detail::MemoryNetwork> net_;
    std::map<PeerId, std::uint64_t> peers_;  // open or closing connections: peer -> link
    std::map<std::uint64_t, PeerId> ids_;    // link -> peer
    PeerId next_id_ = 1;
    Totals totals_;
};

}  // namespace

namespace detail {

std::unique_ptr<Transport> make_memory_server(std::shared_ptr<MemoryNetwork> net) {
    return std::make_unique<MemoryServer>(std::move(net));
}

}  // namespace detail
}  // namespace jetrace::net
