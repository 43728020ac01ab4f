// The ENet implementation of Transport (server: listen_enet, client: connect_enet).
//
// ENet facts this file relies on (ENet 1.3.17):
// - enet_host_service(host, &ev, 0) never waits for the socket; it returns 1
//   per event, 0 when nothing is pending and < 0 on a socket error.
// - host->totalSentData / totalReceivedData count UDP payload bytes (ENet
//   protocol header and command headers included, IP/UDP headers excluded);
//   totalSentPackets / totalReceivedPackets count UDP datagrams, each of
//   which may carry many ENet commands. They are 32-bit and ENet never resets
//   them, so they are folded into 64-bit totals on every service().
// - enet_peer_reset (run by ENet whenever a peer slot is recycled) restores
//   the default timeouts, so the configured ones are re-applied every service.
// - An UNSEQUENCED packet larger than one fragment (MTU 1392 minus headers)
//   is sent as *reliable* fragments unless ENET_PACKET_FLAG_UNRELIABLE_FRAGMENT
//   is set too; with it, large unreliable datagrams are unreliable fragments
//   (all or nothing, and dropped if a newer large one already arrived).
// - A full server silently ignores further connection attempts; the client
//   then sees its attempt time out (a `disconnected` event).
// - ENetHost::intercept sees every datagram the host receives, before ENet
//   handles it (pre_hello_gate.hpp uses it to refuse connection requests,
//   answered on the host's socket: connect_request.hpp).
// - ENET_EVENT_TYPE_DISCONNECT's data is the 32-bit data of the peer's
//   DISCONNECT command (0 on a timeout or a failed attempt).
#include "jetrace/net/transport.hpp"

#include "connect_request.hpp"
#include "limits.hpp"
#include "pre_hello_gate.hpp"

#include <enet/enet.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <system_error>
#include <unordered_map>
#include <utility>

namespace jetrace::net {
namespace {

// Process-wide enet_initialize / enet_deinitialize, reference counted.
class LibraryRef {
public:
    LibraryRef() {
        std::lock_guard lock(mutex());
        if (count() == 0 && enet_initialize() != 0) return;
        ++count();
        ok_ = true;
    }
    ~LibraryRef() {
        if (!ok_) return;
        std::lock_guard lock(mutex());
        if (--count() == 0) enet_deinitialize();
    }
    LibraryRef(const LibraryRef&) = delete;
    LibraryRef& operator=(const LibraryRef&) = delete;
    bool ok() const { return ok_; }

private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    static int& count() {
        static int n = 0;
        return n;
    }
    bool ok_ = false;
};

// Timeouts derived from one "drop a silent peer after this long" budget:
// a silent peer is pinged after `ping` ms and then dropped once the ping has
// gone unanswered for `maximum` ms (or for `minimum` ms after ENet's 32-fold
// retransmission backoff), so ping + maximum <= timeout_ms.
struct TimeoutPlan {
    enet_uint32 ping = 0;
    enet_uint32 minimum = 0;
    enet_uint32 maximum = 0;
};

TimeoutPlan plan_timeouts(std::uint32_t timeout_ms) {
    TimeoutPlan plan;
    plan.ping = std::clamp<enet_uint32>(timeout_ms / 4, 1, ENET_PEER_PING_INTERVAL);
    plan.maximum = std::max<enet_uint32>(timeout_ms - std::min(timeout_ms, plan.ping), 1);
    plan.minimum = std::max<enet_uint32>(plan.maximum / 2, 1);
    return plan;
}

void apply_timeouts(ENetPeer* peer, const TimeoutPlan& plan) {
    if (peer->timeoutMaximum != plan.maximum || peer->timeoutMinimum != plan.minimum) {
        enet_peer_timeout(peer, 0, plan.minimum, plan.maximum);
    }
    if (peer->pingInterval != plan.ping) enet_peer_ping_interval(peer, plan.ping);
}

// peer->data holds id + 1, so that nullptr means "no id assigned".
void* encode_id(PeerId id) { return reinterpret_cast<void*>(static_cast<std::uintptr_t>(id) + 1); }

bool decode_id(const ENetPeer* peer, PeerId& id) {
    const auto raw = reinterpret_cast<std::uintptr_t>(peer->data);
    if (raw == 0) return false;
    id = static_cast<PeerId>(raw - 1);
    return true;
}

std::string errno_text(int err) { return err != 0 ? std::generic_category().message(err) : std::string("unknown error"); }

class EnetTransport;
// The transport whose service() is running on this thread (ENet's intercept
// callback gets the host only).
thread_local EnetTransport* t_servicing = nullptr;
int ENET_CALLBACK intercept(ENetHost* host, ENetEvent* event);

class EnetTransport final : public Transport {
public:
    enum class Role : std::uint8_t { server, client };

    EnetTransport(Role role, TimeoutPlan plan, std::size_t max_pending_per_address = 0)
        : role_(role), plan_(plan), gate_(max_pending_per_address) {}

    ~EnetTransport() override {
        if (host_ == nullptr) return;
        if (role_ == Role::client) {
            close_client_gracefully();
        } else {
            // Tell connected clients right away instead of letting them time out.
            for (auto& [id, peer] : peers_) enet_peer_disconnect_now(peer, 0);
        }
        enet_host_destroy(host_);
    }

    EnetTransport(const EnetTransport&) = delete;
    EnetTransport& operator=(const EnetTransport&) = delete;

    bool library_ok() const { return library_.ok(); }

    // Takes ownership of `host`.
    void adopt_host(ENetHost* host) {
        host_ = host;
        host_->maximumPacketSize = detail::kMaxDatagramBytes;
        ENetAddress bound{};
        if (enet_socket_get_address(host_->socket, &bound) == 0) local_port_ = bound.port;
        if (role_ == Role::server) {
            gate_.attach(*host_);
            host_->intercept = &intercept;
        }
        configure_peers();
    }

    // ENet's intercept callback, for a datagram `host` just received: 1 drops it.
    int on_datagram(const ENetHost* host) {
        if (host != host_) return 0;
        detail::ConnectRequest request;
        switch (gate_.judge(*host_, request)) {
            case detail::PreHelloGate::Verdict::pass: return 0;
            case detail::PreHelloGate::Verdict::drop: return 1;
            case detail::PreHelloGate::Verdict::refuse:
                detail::answer_request(*host_, request, kPreHelloRefusal);
                return 1;
        }
        return 1;
    }

    // Client only: the peer of the connection attempt becomes PeerId 0.
    void adopt_server_peer(ENetPeer* peer) {
        peer->data = encode_id(0);
        apply_timeouts(peer, plan_);
        peers_[0] = peer;
    }

    void service(std::uint64_t /*now_ms: ENet reads its own clock*/, std::vector<Event>& events) override {
        for (Event& e : pending_) events.push_back(std::move(e));
        pending_.clear();
        configure_peers();
        ENetEvent ev{};
        EnetTransport* const outer = t_servicing;
        t_servicing = this;
        // Bounded so that a flood cannot keep one call busy forever.
        for (std::size_t n = 0; n < kMaxEventsPerService; ++n) {
            if (enet_host_service(host_, &ev, 0) <= 0) break;
            handle(ev, events);
        }
        t_servicing = outer;
        configure_peers();
        absorb_counters();
    }

    bool send(PeerId peer, Channel channel, std::span<const std::uint8_t> data) override {
        if (data.size() > detail::kMaxDatagramBytes) return false;
        enet_uint32 flags = 0;
        switch (channel) {
            // Without UNRELIABLE_FRAGMENT, ENet would send a datagram larger
            // than one fragment (~1.36 KB) as reliable fragments.
            case Channel::unreliable: flags = ENET_PACKET_FLAG_UNSEQUENCED | ENET_PACKET_FLAG_UNRELIABLE_FRAGMENT; break;
            case Channel::reliable: flags = ENET_PACKET_FLAG_RELIABLE; break;
            default: return false;
        }
        const auto it = peers_.find(peer);
        if (it == peers_.end() || it->second->state != ENET_PEER_STATE_CONNECTED) return false;
        ENetPacket* packet = enet_packet_create(data.data(), data.size(), flags);
        if (packet == nullptr) return false;
        if (enet_peer_send(it->second, static_cast<enet_uint8>(channel), packet) < 0) {
            if (packet->referenceCount == 0) enet_packet_destroy(packet);
            return false;
        }
        return true;
    }

    void disconnect(PeerId peer) override {
        const auto it = peers_.find(peer);
        if (it == peers_.end()) return;
        ENetPeer* p = it->second;
        enet_peer_disconnect_later(p, 0);
        // A peer that was not connected yet is reset on the spot and ENet
        // reports nothing; report it ourselves on the next service().
        if (p->state == ENET_PEER_STATE_DISCONNECTED) {
            p->data = nullptr;
            gate_.forget(*host_, *p);
            peers_.erase(it);
            Event e;
            e.type = Event::Type::disconnected;
            e.peer = peer;
            pending_.push_back(std::move(e));
        }
    }

    void admit(PeerId peer) override {
        const auto it = peers_.find(peer);
        if (it != peers_.end()) gate_.admit(*host_, *it->second);
    }

    void flush() override {
        enet_host_flush(host_);
        absorb_counters();
    }

    PeerStats peer_stats(PeerId peer) const override {
        PeerStats stats;
        const auto it = peers_.find(peer);
        // Before the handshake ENet holds a 500 ms guess, not a measurement.
        if (it == peers_.end() || (it->second->state != ENET_PEER_STATE_CONNECTED &&
                                   it->second->state != ENET_PEER_STATE_DISCONNECT_LATER)) {
            return stats;
        }
        stats.rtt_ms = static_cast<double>(it->second->roundTripTime);
        stats.rtt_variance_ms = static_cast<double>(it->second->roundTripTimeVariance);
        return stats;
    }

    Totals totals() const override {
        Totals t = totals_;
        t.bytes_sent += host_->totalSentData;
        t.bytes_received += host_->totalReceivedData;
        t.packets_sent += host_->totalSentPackets;
        t.packets_received += host_->totalReceivedPackets;
        t.connects_refused = gate_.refused();
        return t;
    }

    std::uint16_t local_port() const override { return local_port_; }

private:
    static constexpr std::size_t kMaxEventsPerService = 1u << 16;
    static constexpr auto kGracefulClose = std::chrono::milliseconds(100);

    void handle(ENetEvent& ev, std::vector<Event>& events) {
        switch (ev.type) {
            case ENET_EVENT_TYPE_CONNECT: {
                PeerId id = 0;
                if (role_ == Role::server) {
                    id = next_id_++;
                    ev.peer->data = encode_id(id);
                    peers_[id] = ev.peer;
                    gate_.forget(*host_, *ev.peer);
                } else if (!decode_id(ev.peer, id)) {
                    break;
                }
                apply_timeouts(ev.peer, plan_);
                Event e;
                e.type = Event::Type::connected;
                e.peer = id;
                events.push_back(std::move(e));
                break;
            }
            case ENET_EVENT_TYPE_DISCONNECT: {
                PeerId id = 0;
                if (decode_id(ev.peer, id) && peers_.erase(id) > 0) {
                    Event e;
                    e.type = Event::Type::disconnected;
                    e.peer = id;
                    if (ev.data <= 0xFFFFu) e.close_code = static_cast<std::uint16_t>(ev.data);
                    events.push_back(std::move(e));
                }
                ev.peer->data = nullptr;
                gate_.forget(*host_, *ev.peer);
                break;
            }
            case ENET_EVENT_TYPE_RECEIVE: {
                PeerId id = 0;
                ENetPacket* packet = ev.packet;
                if (decode_id(ev.peer, id) && peers_.count(id) > 0 && ev.channelID < kChannelCount &&
                    packet->dataLength <= detail::kMaxDatagramBytes) {
                    Event e;
                    e.type = Event::Type::received;
                    e.peer = id;
                    e.channel = static_cast<Channel>(ev.channelID);
                    if (packet->dataLength > 0) e.data.assign(packet->data, packet->data + packet->dataLength);
                    events.push_back(std::move(e));
                }
                enet_packet_destroy(packet);
                break;
            }
            case ENET_EVENT_TYPE_NONE: break;
        }
    }

    void configure_peers() {
        for (std::size_t i = 0; i < host_->peerCount; ++i) apply_timeouts(&host_->peers[i], plan_);
    }

    void absorb_counters() {
        totals_.bytes_sent += host_->totalSentData;
        totals_.bytes_received += host_->totalReceivedData;
        totals_.packets_sent += host_->totalSentPackets;
        totals_.packets_received += host_->totalReceivedPackets;
        host_->totalSentData = 0;
        host_->totalReceivedData = 0;
        host_->totalSentPackets = 0;
        host_->totalReceivedPackets = 0;
    }

    // Sends a disconnect and waits (at most kGracefulClose) for its
    // acknowledgement so that the server learns of it at once.
    void close_client_gracefully() {
        const auto it = peers_.find(0);
        if (it == peers_.end()) return;
        ENetPeer* peer = it->second;
        // _later: reliable data still queued or unacknowledged (a Goodbye)
        // goes first. enet_peer_disconnect would drop it here, and a server
        // that receives the data and the disconnect in one batch drops it too.
        enet_peer_disconnect_later(peer, 0);
        const auto deadline = std::chrono::steady_clock::now() + kGracefulClose;
        ENetEvent ev{};
        while (peer->state != ENET_PEER_STATE_DISCONNECTED) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                deadline - std::chrono::steady_clock::now());
            if (left.count() <= 0) break;
            const int r = enet_host_service(host_, &ev, static_cast<enet_uint32>(left.count()));
            if (r < 0) break;
            if (r > 0 && ev.type == ENET_EVENT_TYPE_RECEIVE) enet_packet_destroy(ev.packet);
        }
        if (peer->state != ENET_PEER_STATE_DISCONNECTED) enet_peer_reset(peer);
        peers_.erase(it);
    }

    LibraryRef library_;  // first member: outlives the host
    Role role_;
    TimeoutPlan plan_;
    detail::PreHelloGate gate_;
    ENetHost* host_ = nullptr;
    std::uint16_t local_port_ = 0;
    PeerId next_id_ = 1;
    std::unordered_map<PeerId, ENetPeer*> peers_;
    std::vector<Event> pending_;
    Totals totals_;
};

int ENET_CALLBACK intercept(ENetHost* host, ENetEvent* /*event: left as is*/) {
    return t_servicing != nullptr ? t_servicing->on_datagram(host) : 0;
}

// Resolves a dotted address or a host name into `address`.
bool resolve(const std::string& host, ENetAddress& address) {
    if (host.empty()) return false;
    if (enet_address_set_host_ip(&address, host.c_str()) == 0) return true;
    return enet_address_set_host(&address, host.c_str()) == 0;
}

}  // namespace

std::unique_ptr<Transport> listen_enet(const ServerConfig& config, std::string& error) {
    const std::string where = config.bind + ":" + std::to_string(config.port);
    if (config.max_connections == 0 || config.max_connections > ENET_PROTOCOL_MAXIMUM_PEER_ID) {
        error = "cannot listen on UDP " + where + ": max_connections must be in 1.." +
                std::to_string(ENET_PROTOCOL_MAXIMUM_PEER_ID) + " (got " + std::to_string(config.max_connections) + ")";
        return nullptr;
    }
    if (config.timeout_ms == 0) {
        error = "cannot listen on UDP " + where + ": timeout_ms must be > 0";
        return nullptr;
    }
    auto transport = std::make_unique<EnetTransport>(EnetTransport::Role::server, plan_timeouts(config.timeout_ms),
                                                     config.max_pending_per_address);
    if (!transport->library_ok()) {
        error = "cannot listen on UDP " + where + ": enet_initialize failed";
        return nullptr;
    }
    ENetAddress address{};
    address.port = config.port;
    if (config.bind == "0.0.0.0") {
        address.host = ENET_HOST_ANY;
    } else if (!resolve(config.bind, address)) {
        error = "cannot listen on UDP " + where + ": cannot resolve bind address '" + config.bind + "'";
        return nullptr;
    }
    errno = 0;
    ENetHost* host = enet_host_create(&address, config.max_connections, kChannelCount, 0, 0);
    if (host == nullptr) {
        error = "cannot bind UDP " + where + ": " + errno_text(errno);
        return nullptr;
    }
    transport->adopt_host(host);
    return transport;
}

std::unique_ptr<Transport> connect_enet(const std::string& host, std::uint16_t port, std::uint32_t timeout_ms,
                                        std::string& error) {
    const std::string where = host + ":" + std::to_string(port);
    if (port == 0) {
        error = "cannot connect to " + where + ": port must be nonzero";
        return nullptr;
    }
    if (timeout_ms == 0) {
        error = "cannot connect to " + where + ": timeout_ms must be > 0";
        return nullptr;
    }
    auto transport = std::make_unique<EnetTransport>(EnetTransport::Role::client, plan_timeouts(timeout_ms));
    if (!transport->library_ok()) {
        error = "cannot connect to " + where + ": enet_initialize failed";
        return nullptr;
    }
    ENetAddress remote{};
    if (!resolve(host, remote)) {
        error = "cannot connect to " + where + ": cannot resolve host '" + host + "'";
        return nullptr;
    }
    remote.port = port;
    // Bind an ephemeral port now (ENet would otherwise bind on the first
    // sendto), so that local_port() is known at once.
    ENetAddress local{};
    local.host = ENET_HOST_ANY;
    local.port = 0;
    errno = 0;
    ENetHost* client = enet_host_create(&local, 1, kChannelCount, 0, 0);
    if (client == nullptr) {
        error = "cannot connect to " + where + ": cannot create a UDP socket: " + errno_text(errno);
        return nullptr;
    }
    transport->adopt_host(client);
    ENetPeer* peer = enet_host_connect(client, &remote, kChannelCount, 0);
    if (peer == nullptr) {
        error = "cannot connect to " + where + ": enet_host_connect failed";
        return nullptr;
    }
    transport->adopt_server_peer(peer);
    return transport;
}

}  // namespace jetrace::net
