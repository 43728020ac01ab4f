// UdpProxy: a UDP proxy between clients and one server that degrades the
// traffic in each direction (jetrace-netsim). POSIX sockets and poll(), IPv4
// (like ENet). Each client address gets its own upstream socket, so the
// server sees as many peers as there are clients. All the decisions (delay,
// loss, duplication, reordering, rate) are a net::DatagramScheduler's, one
// per direction, one flow per client; this class only moves bytes and reads
// the clock.
#pragma once

#include "jetrace/net/link_conditions.hpp"
#include "jetrace/net/scheduler.hpp"

#include <netinet/in.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace jetrace::netsim {

struct ProxyConfig {
    /// Address to listen on for clients.
    std::string bind = "127.0.0.1";
    /// UDP port for clients; 0 lets the system choose (see local_port()).
    std::uint16_t port = 0;
    /// The server (host name or dotted IPv4 address).
    std::string forward_host;
    std::uint16_t forward_port = 0;
    /// Client -> server conditions.
    net::Conditions up;
    /// Server -> client conditions.
    net::Conditions down;
    /// A client silent for this long loses its upstream socket (unit: s).
    double idle_timeout_s = 60;
    /// Most clients served at once; datagrams from further addresses are
    /// dropped until one expires (unit: clients).
    std::size_t max_clients = 256;
};

/// What one direction did (unit: datagrams unless named otherwise).
struct DirectionCounters {
    /// Datagrams received from the sending side.
    std::uint64_t received = 0;
    /// Datagrams handed to the receiving side (copies included).
    std::uint64_t forwarded = 0;
    /// Payload bytes forwarded (unit: bytes).
    std::uint64_t forwarded_bytes = 0;
    /// The direction's scheduler: dropped, duplicated, reordered, rate-limited.
    net::SchedulerStats scheduler;
    /// Datagrams that could not be sent (socket errors, client expired).
    std::uint64_t send_failed = 0;
    /// Datagrams still queued or held (not yet due).
    std::uint64_t pending = 0;
};

struct ProxyCounters {
    DirectionCounters up;
    DirectionCounters down;
    /// Client addresses seen so far (unit: clients).
    std::uint64_t clients = 0;
    /// Clients whose session expired (unit: clients).
    std::uint64_t clients_expired = 0;
    /// Datagrams dropped because max_clients were already served.
    std::uint64_t clients_refused = 0;
};

class UdpProxy {
public:
    /// Binds the client socket and resolves the server; nullptr and `error`
    /// on failure.
    static std::unique_ptr<UdpProxy> open(const ProxyConfig& config, std::string& error);
    ~UdpProxy();
    UdpProxy(const UdpProxy&) = delete;
    UdpProxy& operator=(const UdpProxy&) = delete;

    std::uint16_t local_port() const { return local_port_; }
    /// Waits up to `max_wait_ms` for traffic (less if a datagram falls due),
    /// then reads what arrived and sends what is due. Returns false only if
    /// poll() fails for a reason other than a signal.
    bool step(int max_wait_ms);
    ProxyCounters counters() const;
    /// Shows `observer` every client -> server datagram as it arrives and as
    /// it is forwarded (peer: the client's flow id); null: none. It must
    /// outlive the proxy.
    void observe_up(net::LinkObserver* observer) { up_observer_ = observer; }
    /// Clients with an upstream socket now.
    std::size_t sessions() const { return sessions_.size(); }

private:
    struct Session {
        sockaddr_in client{};
        int fd = -1;
        double last_heard_ms = 0;
    };

    explicit UdpProxy(const ProxyConfig& config);
    double now_ms() const;
    void read_clients(double now);
    void read_server(std::uint64_t id, Session& s, double now);
    Session* session_for(const sockaddr_in& from, double now);
    void send_due(double now);
    void expire(double now);
    void close_session(std::uint64_t id);

    ProxyConfig config_;
    int listen_fd_ = -1;
    std::uint16_t local_port_ = 0;
    sockaddr_in server_{};
    net::DatagramScheduler up_;
    net::DatagramScheduler down_;
    std::map<std::uint64_t, Session> sessions_;          // by id (flow)
    std::unordered_map<std::uint64_t, std::uint64_t> by_address_;  // packed address -> id
    std::uint64_t next_id_ = 1;
    std::uint64_t start_ns_ = 0;
    ProxyCounters counters_;
    std::vector<std::uint8_t> buffer_;
    std::vector<net::ScheduledDatagram> due_;
    net::LinkObserver* up_observer_ = nullptr;
};

}  // namespace jetrace::netsim
