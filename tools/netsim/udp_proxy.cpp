// UdpProxy: sockets, sessions and the two schedulers (see udp_proxy.hpp).
#include "udp_proxy.hpp"

#include <spdlog/spdlog.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>

namespace jetrace::netsim {
namespace {

constexpr std::size_t kMaxDatagramBytes = 65536;
// Datagrams read from one socket per step, so one busy peer cannot starve the rest.
constexpr int kMaxReadsPerSocket = 256;

std::string text(const sockaddr_in& a) {
    char host[INET_ADDRSTRLEN] = {};
    ::inet_ntop(AF_INET, &a.sin_addr, host, sizeof host);
    return std::string(host) + ":" + std::to_string(ntohs(a.sin_port));
}

std::uint64_t pack(const sockaddr_in& a) {
    return (std::uint64_t{a.sin_addr.s_addr} << 16) | std::uint64_t{a.sin_port};
}

bool resolve(const std::string& host, std::uint16_t port, sockaddr_in& out, std::string& error) {
    addrinfo hints{};
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* found = nullptr;
    const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &found);
    if (rc != 0 || found == nullptr) {
        error = "cannot resolve '" + host + "': " + ::gai_strerror(rc);
        return false;
    }
    std::memcpy(&out, found->ai_addr, sizeof out);
    out.sin_port = htons(port);
    ::freeaddrinfo(found);
    return true;
}

std::uint64_t steady_ns() {
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
            .count());
}

// Socket buffers asked for (unit: bytes): a proxy descheduled for a moment
// on a busy machine should queue, not drop, what arrives meanwhile. Beyond
// net.core.rmem_max only with CAP_NET_ADMIN (SO_RCVBUFFORCE); best effort.
constexpr int kSocketBufferBytes = 4 << 20;

int udp_socket(std::string& error) {
    const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        error = std::string("cannot create a UDP socket: ") + std::strerror(errno);
        return fd;
    }
    const int bytes = kSocketBufferBytes;
    if (::setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &bytes, sizeof bytes) != 0)
        ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &bytes, sizeof bytes);
    if (::setsockopt(fd, SOL_SOCKET, SO_SNDBUFFORCE, &bytes, sizeof bytes) != 0)
        ::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &bytes, sizeof bytes);
    return fd;
}

}  // namespace

UdpProxy::UdpProxy(const ProxyConfig& config)
    : config_(config), up_(config.up), down_(config.down), buffer_(kMaxDatagramBytes) {
    start_ns_ = steady_ns();
}

UdpProxy::~UdpProxy() {
    for (auto& [id, s] : sessions_) ::close(s.fd);
    if (listen_fd_ >= 0) ::close(listen_fd_);
}

std::unique_ptr<UdpProxy> UdpProxy::open(const ProxyConfig& config, std::string& error) {
    std::unique_ptr<UdpProxy> p(new UdpProxy(config));
    const std::string where = config.bind + ":" + std::to_string(config.port);
    if (!resolve(config.forward_host, config.forward_port, p->server_, error)) return nullptr;
    sockaddr_in local{};
    if (!resolve(config.bind, config.port, local, error)) return nullptr;
    p->listen_fd_ = udp_socket(error);
    if (p->listen_fd_ < 0) return nullptr;
    if (::bind(p->listen_fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
        error = "cannot bind UDP " + where + ": " + std::strerror(errno);
        return nullptr;
    }
    socklen_t len = sizeof local;
    ::getsockname(p->listen_fd_, reinterpret_cast<sockaddr*>(&local), &len);
    p->local_port_ = ntohs(local.sin_port);
    return p;
}

double UdpProxy::now_ms() const {
    return static_cast<double>(steady_ns() - start_ns_) / 1e6;
}

bool UdpProxy::step(int max_wait_ms) {
    double now = now_ms();
    const double due = std::min(up_.next_due_ms(), down_.next_due_ms());
    int wait = std::max(0, max_wait_ms);
    if (due < now + wait) wait = std::max(0, static_cast<int>(std::ceil(due - now)));

    std::vector<pollfd> fds;
    std::vector<std::uint64_t> ids;
    fds.push_back({listen_fd_, POLLIN, 0});
    for (const auto& [id, s] : sessions_) {
        fds.push_back({s.fd, POLLIN, 0});
        ids.push_back(id);
    }
    const int ready = ::poll(fds.data(), fds.size(), wait);
    if (ready < 0 && errno != EINTR) {
        spdlog::error("poll failed: {}", std::strerror(errno));
        return false;
    }
    now = now_ms();
    if (ready > 0) {
        if (fds[0].revents != 0) read_clients(now);
        for (std::size_t i = 1; i < fds.size(); ++i) {
            if (fds[i].revents == 0) continue;
            const auto it = sessions_.find(ids[i - 1]);
            if (it != sessions_.end()) read_server(it->first, it->second, now);
        }
    }
    send_due(now_ms());
    expire(now);
    return true;
}

UdpProxy::Session* UdpProxy::session_for(const sockaddr_in& from, double now) {
    const auto known = by_address_.find(pack(from));
    if (known != by_address_.end()) return &sessions_.at(known->second);
    if (sessions_.size() >= config_.max_clients) {
        if (counters_.clients_refused++ == 0) {
            spdlog::warn("{} clients already: datagrams from {} (and further new clients) are dropped",
                         config_.max_clients, text(from));
        }
        return nullptr;
    }
    std::string error;
    Session s;
    s.client = from;
    s.fd = udp_socket(error);
    if (s.fd < 0) {
        spdlog::error("client {}: {}", text(from), error);
        return nullptr;
    }
    if (::connect(s.fd, reinterpret_cast<const sockaddr*>(&server_), sizeof server_) != 0) {
        spdlog::error("client {}: cannot reach {}: {}", text(from), text(server_), std::strerror(errno));
        ::close(s.fd);
        return nullptr;
    }
    sockaddr_in upstream{};
    socklen_t len = sizeof upstream;
    ::getsockname(s.fd, reinterpret_cast<sockaddr*>(&upstream), &len);
    s.last_heard_ms = now;
    const std::uint64_t id = next_id_++;
    spdlog::info("client {} -> {} via {}", text(from), text(server_), text(upstream));
    ++counters_.clients;
    by_address_[pack(from)] = id;
    return &sessions_.emplace(id, s).first->second;
}

void UdpProxy::read_clients(double now) {
    for (int i = 0; i < kMaxReadsPerSocket; ++i) {
        sockaddr_in from{};
        socklen_t len = sizeof from;
        const ssize_t n =
            ::recvfrom(listen_fd_, buffer_.data(), buffer_.size(), 0, reinterpret_cast<sockaddr*>(&from), &len);
        if (n < 0) break;  // EAGAIN: nothing more (or a transient error)
        if (len != sizeof from || from.sin_family != AF_INET) continue;
        ++counters_.up.received;
        Session* s = session_for(from, now);
        if (s == nullptr) continue;
        s->last_heard_ms = now;
        net::ScheduledDatagram d;
        d.flow = by_address_.at(pack(from));
        d.data.assign(buffer_.begin(), buffer_.begin() + n);
        if (up_observer_) up_observer_->arrived(static_cast<net::PeerId>(d.flow), now, d.data);
        up_.push(now, std::move(d));
    }
}

void UdpProxy::read_server(std::uint64_t id, Session& s, double now) {
    for (int i = 0; i < kMaxReadsPerSocket; ++i) {
        const ssize_t n = ::recv(s.fd, buffer_.data(), buffer_.size(), 0);
        if (n < 0) break;  // EAGAIN, or ECONNREFUSED from an ICMP error: the server is not there (yet)
        ++counters_.down.received;
        net::ScheduledDatagram d;
        d.flow = id;
        d.data.assign(buffer_.begin(), buffer_.begin() + n);
        down_.push(now, std::move(d));
    }
}

void UdpProxy::send_due(double now) {
    due_.clear();
    up_.pop_due(now, due_);
    for (const auto& d : due_) {
        const auto it = sessions_.find(d.flow);
        if (it != sessions_.end() && ::send(it->second.fd, d.data.data(), d.data.size(), 0) >= 0) {
            if (up_observer_) up_observer_->delivered(static_cast<net::PeerId>(d.flow), now, d.data);
            ++counters_.up.forwarded;
            counters_.up.forwarded_bytes += d.data.size();
        } else {
            ++counters_.up.send_failed;
        }
    }
    due_.clear();
    down_.pop_due(now, due_);
    for (const auto& d : due_) {
        const auto it = sessions_.find(d.flow);
        if (it != sessions_.end() &&
            ::sendto(listen_fd_, d.data.data(), d.data.size(), 0, reinterpret_cast<const sockaddr*>(&it->second.client),
                     sizeof it->second.client) >= 0) {
            ++counters_.down.forwarded;
            counters_.down.forwarded_bytes += d.data.size();
        } else {
            ++counters_.down.send_failed;
        }
    }
}

void UdpProxy::expire(double now) {
    const double limit_ms = config_.idle_timeout_s * 1000.0;
    std::vector<std::uint64_t> idle;
    for (const auto& [id, s] : sessions_) {
        if (now - s.last_heard_ms > limit_ms) idle.push_back(id);
    }
    for (const std::uint64_t id : idle) close_session(id);
}

void UdpProxy::close_session(std::uint64_t id) {
    const auto it = sessions_.find(id);
    if (it == sessions_.end()) return;
    spdlog::info("client {} silent for {:.0f} s: session closed", text(it->second.client), config_.idle_timeout_s);
    ::close(it->second.fd);
    by_address_.erase(pack(it->second.client));
    sessions_.erase(it);
    up_.forget(id);
    down_.forget(id);
    ++counters_.clients_expired;
}

ProxyCounters UdpProxy::counters() const {
    ProxyCounters c = counters_;
    const auto fill = [](DirectionCounters& d, const net::DatagramScheduler& scheduler) {
        d.pending = scheduler.pending();
        d.scheduler = scheduler.stats();
    };
    fill(c.up, up_);
    fill(c.down, down_);
    return c;
}

}  // namespace jetrace::netsim
