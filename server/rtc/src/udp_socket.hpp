// The WebRTC transport's one non-blocking UDP socket (IPv4 or IPv6), and
// a remote address as a map key.
#pragma once

#include <netinet/in.h>
#include <sys/socket.h>

#include <cstdint>
#include <span>
#include <string>

namespace jetrace::rtc::detail {

struct Endpoint {
    sockaddr_storage sa{};
    socklen_t len = 0;
    /// Family, address and port bytes: equal for the same remote.
    std::string key() const;
    /// The IP alone (the rate limits' key), as bytes.
    std::string ip_key() const;
    /// For STUN's XOR-MAPPED-ADDRESS: 4 or 16 address bytes, and the port.
    bool ipv6() const { return sa.ss_family == AF_INET6; }
    std::span<const std::uint8_t> ip_bytes() const;
    std::uint16_t port() const;
};

class UdpSocket {
public:
    UdpSocket() = default;
    ~UdpSocket();
    UdpSocket(const UdpSocket&) = delete;
    UdpSocket& operator=(const UdpSocket&) = delete;

    /// Binds `ip`:`port` (0: any), non-blocking; false and `error` if not.
    bool open(const std::string& ip, std::uint16_t port, std::string& error);
    /// One datagram, or -1 when none is waiting; truncated ones are dropped
    /// (0 bytes returned).
    long receive(std::span<std::uint8_t> buffer, Endpoint& from);
    bool send(std::span<const std::uint8_t> data, const Endpoint& to);
    std::uint16_t port() const { return port_; }

private:
    int fd_ = -1;
    std::uint16_t port_ = 0;
};

}  // namespace jetrace::rtc::detail
