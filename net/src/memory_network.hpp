// The state of an in-memory network (memory_transport.hpp), shared by its
// ends: memory_server.cpp (the server end) and memory_transport.cpp (the
// client ends and the hub).
//
// Each connection is a Link: a queue of items towards its client end, its
// client side's state and its server side's state. Items towards the
// server end share one queue, so the server receives in the order the
// clients sent. A connection is a few items: connect (client to server),
// accept or refuse (back), data both ways, close (either way, behind the
// data already queued) and ack (the answer to a close). A Link is forgotten
// once both of its sides are closed; items still queued for a forgotten
// Link are skipped.
#pragma once

#include "jetrace/net/memory_transport.hpp"

#include "limits.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace jetrace::net {
namespace detail {

enum class ItemKind : std::uint8_t { connect, accept, refuse, data, close, ack };

struct Item {
    ItemKind kind = ItemKind::data;
    std::uint64_t link = 0;
    /// Handed out by the first service() at or after this hub time (unit: ms).
    std::uint64_t due_ms = 0;
    Channel channel = Channel::reliable;
    std::vector<std::uint8_t> data;
};

/// One side of a connection: connect sent or not yet handled, open,
/// disconnect called (waiting for the other side's ack), closed.
enum class Side : std::uint8_t { waiting, open, closing, closed };

struct Link {
    std::deque<Item> to_client;
    Side client = Side::waiting;
    Side server = Side::waiting;
};

struct MemoryNetwork {
    explicit MemoryNetwork(const MemoryHubConfig& c) : config(c) {}

    MemoryHubConfig config;
    /// The hub's clock: the largest now_ms given to any service() (unit: ms).
    std::uint64_t now_ms = 0;
    bool server_alive = false;
    std::deque<Item> to_server;
    std::map<std::uint64_t, Link> links;
    std::uint64_t next_link = 0;

    void advance(std::uint64_t now) { now_ms = std::max(now_ms, now); }
    Link* find(std::uint64_t id) {
        const auto it = links.find(id);
        return it == links.end() ? nullptr : &it->second;
    }
    Item item(ItemKind kind, std::uint64_t link, Channel channel = Channel::reliable,
              std::span<const std::uint8_t> data = {}) const {
        return Item{kind, link, now_ms + config.latency_ms, channel, {data.begin(), data.end()}};
    }
    /// Queues for the server end (nothing if there is none).
    void push_to_server(Item it) {
        if (server_alive) to_server.push_back(std::move(it));
    }
    /// Queues for the client end of `it.link` (nothing if that side is closed).
    void push_to_client(Item it) {
        Link* l = find(it.link);
        if (l != nullptr && l->client != Side::closed) l->to_client.push_back(std::move(it));
    }
    void forget_if_done(std::uint64_t id) {
        const Link* l = find(id);
        if (l != nullptr && l->client == Side::closed && l->server == Side::closed) links.erase(id);
    }
};

inline Event event(Event::Type type, PeerId peer, Channel channel = Channel::reliable, std::vector<std::uint8_t> data = {}) {
    Event e;
    e.type = type;
    e.peer = peer;
    e.channel = channel;
    e.data = std::move(data);
    return e;
}

inline bool sendable(Channel channel, std::span<const std::uint8_t> data) {
    return data.size() <= detail::kMaxDatagramBytes && (channel == Channel::reliable || channel == Channel::unreliable);
}

inline void count_received(Totals& totals, const Item& it) {
    totals.bytes_received += it.data.size();
    ++totals.packets_received;
}

inline void count_sent(Totals& totals, std::span<const std::uint8_t> data) {
    totals.bytes_sent += data.size();
    ++totals.packets_sent;
}

/// The server end of `net` (it must have none yet).
std::unique_ptr<Transport> make_memory_server(std::shared_ptr<MemoryNetwork> net);

}  // namespace detail

}  // namespace jetrace::net
