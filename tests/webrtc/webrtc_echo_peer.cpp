// A minimal data-channel server from jetrace::webrtc's blocks, for the
// browser interop test (webrtc_browser_echo.mjs): reads the browser's offer
// on stdin, prints its answer then "END" on stdout, and on one UDP port
// answers STUN checks (ICE-lite) and runs a DataChannelSession (DTLS, SCTP,
// DCEP) that echoes every message on its channel, with the channel's
// reliability. Exits after SECONDS, printing counts on stderr. With LOSS
// (0..1), once the channels are open that share of the datagrams each way
// is dropped (a fixed pseudo-random sequence).
// Usage: webrtc_echo_peer SECONDS [LOSS] < offer.sdp
#include "jetrace/webrtc/sdp.hpp"
#include "jetrace/webrtc/session.hpp"
#include "jetrace/webrtc/stun.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <openssl/rand.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <iterator>
#include <optional>
#include <random>

using namespace jetrace::webrtc;

namespace {

struct Peer {
    int fd = -1;
    sockaddr_in remote{};
    bool have_remote = false;
    IceCredentials ice;
    SdpOffer offer;
    std::unique_ptr<DtlsContext> context;
    std::unique_ptr<DataChannelSession> session;
    int stun_checks = 0, echoed = 0, dropped = 0;
    double loss = 0;
    std::minstd_rand random{33};
};

// With JETRACE_ECHO_DUMP set: what the browser sent, as hex on stderr (test vectors).
void dump(const char* what, std::span<const std::uint8_t> d) {
    if (std::getenv("JETRACE_ECHO_DUMP") == nullptr) return;
    std::fprintf(stderr, "%s:", what);
    for (const std::uint8_t b : d) std::fprintf(stderr, " %02x", b);
    std::fprintf(stderr, "\n");
}

// True if this datagram is to be lost (only once the channels are open).
bool lose(Peer& p) {
    if (p.loss <= 0 || !p.session || p.session->state() != SessionState::kOpen) return false;
    const bool lost = std::uniform_real_distribution<double>(0, 1)(p.random) < p.loss;
    p.dropped += lost ? 1 : 0;
    return lost;
}

void send_to_remote(Peer& p, const std::vector<std::uint8_t>& d) {
    if (!p.have_remote || lose(p)) return;
    sendto(p.fd, d.data(), d.size(), 0, reinterpret_cast<const sockaddr*>(&p.remote), sizeof p.remote);
}

void on_stun(Peer& p, std::span<const std::uint8_t> d, const sockaddr_in& from) {
    StunMessage m;
    if (parse_binding_request(d, m) != StunError::kNone) return;
    std::string_view ours, theirs;
    if (!split_ice_username(*m.username, ours, theirs) || ours != p.ice.ufrag || theirs != p.offer.ice_ufrag) return;
    if (!integrity_valid(d, m, p.ice.pwd)) return;
    if (p.stun_checks++ == 0) {
        std::fprintf(stderr, "server ice-ufrag %s ice-pwd %s\n", p.ice.ufrag.c_str(), p.ice.pwd.c_str());
        dump("first binding request", d);
    }
    p.remote = from;
    p.have_remote = true;
    std::array<std::uint8_t, 4> ip{};
    std::memcpy(ip.data(), &from.sin_addr, 4);
    send_to_remote(p, build_binding_success(m.transaction_id, StunAddress::v4(ip, ntohs(from.sin_port)), p.ice.pwd));
}

// Echoes what arrived, and sends what is due.
void pump(Peer& p) {
    for (const std::uint16_t stream : p.session->take_opened()) {
        const DataChannelOpen* open = p.session->channel(stream);
        std::fprintf(stderr, "open stream %u type 0x%02x label %s\n", stream, open->channel_type, open->label.c_str());
    }
    for (const ChannelMessage& m : p.session->take_messages())
        if (p.session->send(m.stream, m.data, m.binary) == SctpSendResult::kSent) ++p.echoed;
    for (const auto& d : p.session->take_outgoing()) send_to_remote(p, d);
}

int open_socket() {
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return -1;
    return fd;
}

std::uint16_t local_port(int fd) {
    sockaddr_in a{};
    socklen_t n = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
    return ntohs(a.sin_port);
}

}  // namespace

int main(int argc, char** argv) {
    const double seconds = argc > 1 ? std::atof(argv[1]) : 20.0;
    const double loss = argc > 2 ? std::atof(argv[2]) : 0.0;
    const std::string text{std::istreambuf_iterator<char>(std::cin), {}};
    Peer p;
    p.loss = loss;
    std::size_t line = 0;
    if (const SdpError e = parse_offer(text, p.offer, &line); e != SdpError::kNone) {
        std::fprintf(stderr, "offer refused: %s (line %zu)\n", std::string(to_string(e)).c_str(), line);
        return 2;
    }
    p.fd = open_socket();
    p.context = DtlsContext::create(DtlsSettings{});
    if (p.fd < 0 || !p.context) return 3;
    const RandomSource random = [](std::span<std::uint8_t> out) { RAND_bytes(out.data(), static_cast<int>(out.size())); };
    AnswerSettings s;
    s.ice = p.ice = make_ice_credentials(random);
    s.fingerprint = p.context->fingerprint();
    s.candidate_ip = "127.0.0.1";
    s.candidate_port = local_port(p.fd);
    std::cout << write_answer(p.offer, s) << "END" << std::endl;
    p.session = std::make_unique<DataChannelSession>(*p.context, p.offer);
    const auto start = std::chrono::steady_clock::now();
    auto last = start;
    std::vector<std::uint8_t> buf(2048);
    while (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds)) {
        pollfd pfd{p.fd, POLLIN, 0};
        if (poll(&pfd, 1, 5) > 0) {
            sockaddr_in from{};
            socklen_t n = sizeof from;
            const ssize_t got = recvfrom(p.fd, buf.data(), buf.size(), 0, reinterpret_cast<sockaddr*>(&from), &n);
            const std::span<const std::uint8_t> d(buf.data(), got > 0 ? static_cast<std::size_t>(got) : 0);
            if (is_stun(d)) {
                on_stun(p, d, from);
            } else if (is_dtls(d) && p.have_remote && !lose(p)) {
                p.session->feed(d);
            }
        }
        const auto now = std::chrono::steady_clock::now();
        const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now - last).count();
        if (ms > 0) {
            SctpAssociation::advance_timers(static_cast<std::uint32_t>(ms));
            last = now;
        }
        p.session->handle_timeout();
        pump(p);
    }
    std::fprintf(stderr, "stun_checks=%d session=%d echoed=%d dropped=%d %s\n", p.stun_checks,
                 static_cast<int>(p.session->state()), p.echoed, p.dropped, p.session->error_detail().c_str());
    return 0;
}
