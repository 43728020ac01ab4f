#include "udp_socket.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace jetrace::rtc::detail {

std::string Endpoint::key() const {
    const auto b = ip_bytes();
    std::string k(b.begin(), b.end());
    const std::uint16_t p = port();
    k.push_back(static_cast<char>(p >> 8));
    k.push_back(static_cast<char>(p & 0xff));
    return k;
}

std::string Endpoint::ip_key() const {
    const auto b = ip_bytes();
    return {b.begin(), b.end()};
}

std::span<const std::uint8_t> Endpoint::ip_bytes() const {
    if (ipv6()) return {reinterpret_cast<const std::uint8_t*>(&reinterpret_cast<const sockaddr_in6&>(sa).sin6_addr), 16};
    return {reinterpret_cast<const std::uint8_t*>(&reinterpret_cast<const sockaddr_in&>(sa).sin_addr), 4};
}

std::uint16_t Endpoint::port() const {
    return ntohs(ipv6() ? reinterpret_cast<const sockaddr_in6&>(sa).sin6_port
                        : reinterpret_cast<const sockaddr_in&>(sa).sin_port);
}

UdpSocket::~UdpSocket() {
    if (fd_ >= 0) ::close(fd_);
}

bool UdpSocket::open(const std::string& ip, std::uint16_t port, std::string& error) {
    Endpoint e;
    auto& v4 = reinterpret_cast<sockaddr_in&>(e.sa);
    auto& v6 = reinterpret_cast<sockaddr_in6&>(e.sa);
    if (inet_pton(AF_INET, ip.c_str(), &v4.sin_addr) == 1) {
        v4.sin_family = AF_INET;
        v4.sin_port = htons(port);
        e.len = sizeof v4;
    } else if (inet_pton(AF_INET6, ip.c_str(), &v6.sin6_addr) == 1) {
        v6.sin6_family = AF_INET6;
        v6.sin6_port = htons(port);
        e.len = sizeof v6;
    } else {
        error = "not an IP address: " + ip;
        return false;
    }
    fd_ = ::socket(e.sa.ss_family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0 || ::bind(fd_, reinterpret_cast<const sockaddr*>(&e.sa), e.len) != 0) {
        error = "cannot bind UDP " + ip + ":" + std::to_string(port) + ": " + std::strerror(errno);
        return false;
    }
    Endpoint bound;
    bound.len = sizeof bound.sa;
    getsockname(fd_, reinterpret_cast<sockaddr*>(&bound.sa), &bound.len);
    port_ = bound.port();
    return true;
}

long UdpSocket::receive(std::span<std::uint8_t> buffer, Endpoint& from) {
    from.len = sizeof from.sa;
    const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), MSG_TRUNC,
                                 reinterpret_cast<sockaddr*>(&from.sa), &from.len);
    if (n < 0) return -1;
    if (static_cast<std::size_t>(n) > buffer.size()) return 0;
    if (from.sa.ss_family != AF_INET && from.sa.ss_family != AF_INET6) return 0;
    return static_cast<long>(n);
}

bool UdpSocket::send(std::span<const std::uint8_t> data, const Endpoint& to) {
    return ::sendto(fd_, data.data(), data.size(), 0, reinterpret_cast<const sockaddr*>(&to.sa), to.len) ==
           static_cast<ssize_t>(data.size());
}

}  // namespace jetrace::rtc::detail
