// jetrace::rtc's WebRTC transport on a real UDP port, against a "browser"
// made of jetrace::webrtc's blocks (STUN check, DTLS client, SCTP, DCEP
// opens as Chromium sends them): the channels open into a connected event,
// messages go both ways on their net::Channel, an unreliable message too
// large for one datagram goes whole on the reliable channel, bad offers get
// 400 with the reason, 100 half-finished handshakes from one address leave
// an honest browser from another address able to connect while the
// flooder is answered 503 beyond its cap, and STUN floods are rate-limited.
#include "jetrace/rtc/rtc_transport.hpp"
#include "jetrace/webrtc/dcep.hpp"
#include "jetrace/webrtc/dtls.hpp"
#include "jetrace/webrtc/sctp.hpp"
#include "jetrace/webrtc/sdp.hpp"
#include "jetrace/webrtc/stun.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <sstream>
#include <thread>

using namespace jetrace;
using namespace jetrace::webrtc;

namespace {

using Bytes = std::vector<std::uint8_t>;

const std::string kOffer = "v=0\r\no=- 1 2 IN IP4 127.0.0.1\r\ns=-\r\nt=0 0\r\na=group:BUNDLE 0\r\n"
                           "m=application 9 UDP/DTLS/SCTP webrtc-datachannel\r\nc=IN IP4 0.0.0.0\r\n"
                           "a=ice-ufrag:brws\r\na=ice-pwd:abcdefghijklmnopqrstuvwx\r\n"
                           "a=fingerprint:sha-256 FP\r\na=setup:actpass\r\na=mid:0\r\na=sctp-port:5000\r\n";

std::string offer_with(const Sha256Fingerprint& fp) {
    std::string o = kOffer;
    o.replace(o.find("FP"), 2, fingerprint_text(fp));
    return o;
}

std::string answer_line(const std::string& answer, const std::string& key) {
    const auto at = answer.find(key);
    if (at == std::string::npos) return {};
    const auto end = answer.find("\r\n", at);
    return answer.substr(at + key.size(), end - at - key.size());
}

// A browser on its own UDP socket bound to `ip`.
struct Browser {
    std::unique_ptr<DtlsContext> context = DtlsContext::create(DtlsSettings{});
    std::unique_ptr<DtlsEndpoint> dtls;
    std::unique_ptr<SctpAssociation> sctp;
    int fd = -1;
    sockaddr_in server{};
    std::string server_ufrag, server_pwd;
    std::vector<SctpMessage> received;
    bool opened = false;

    explicit Browser(const char* ip) {
        fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        inet_pton(AF_INET, ip, &a.sin_addr);
        EXPECT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    }
    ~Browser() { close(fd); }

    // Reads the answer, sends a STUN check, starts DTLS as the client.
    void start(const std::string& answer, const Sha256Fingerprint& server_fp) {
        server_ufrag = answer_line(answer, "a=ice-ufrag:");
        server_pwd = answer_line(answer, "a=ice-pwd:");
        const std::string cand = answer_line(answer, "a=candidate:");
        server.sin_family = AF_INET;
        inet_pton(AF_INET, "127.0.0.1", &server.sin_addr);
        std::istringstream words(cand);  // foundation component UDP priority ip port typ host
        std::string w, port;
        for (int i = 0; i < 5 && words >> w; ++i) port = w;
        words >> port;
        server.sin_port = htons(static_cast<std::uint16_t>(std::stoi(port)));
        BindingRequestFields f;
        f.username = server_ufrag + ":brws";
        f.priority = 1;
        f.transaction_id[0] = 7;
        put(build_binding_request(f, server_pwd));
        dtls = std::make_unique<DtlsEndpoint>(*context, DtlsRole::kClient, server_fp);
        sctp = std::make_unique<SctpAssociation>(SctpSettings{});
    }
    void put(const Bytes& d) { sendto(fd, d.data(), d.size(), 0, reinterpret_cast<sockaddr*>(&server), sizeof server); }

    // Moves datagrams; opens both channels once SCTP is up.
    void pump() {
        Bytes buf(2048);
        for (;;) {
            const ssize_t n = recv(fd, buf.data(), buf.size(), 0);
            if (n <= 0) break;
            const std::span<const std::uint8_t> d(buf.data(), static_cast<std::size_t>(n));
            if (is_dtls(d)) dtls->feed(d);
        }
        dtls->handle_timeout();
        for (const auto& p : dtls->take_received()) sctp->feed(p);
        for (auto& m : sctp->take_messages()) received.push_back(std::move(m));
        if (!opened && sctp->state() == SctpState::kConnected) {
            opened = true;
            DataChannelOpen u;
            u.channel_type = kChannelPartialReliableRexmitUnordered;
            u.label = "unreliable";
            DataChannelOpen r;
            r.label = "reliable";
            sctp->send(0, kPpidDcep, build_dcep_open(u));
            sctp->send(2, kPpidDcep, build_dcep_open(r));
        }
        if (dtls->handshake_done()) {
            for (const auto& p : sctp->take_outgoing()) dtls->send(p);
        }
        for (const auto& d : dtls->take_outgoing()) put(d);
    }
};

struct Fixture {
    std::shared_ptr<rtc::RtcSignal> signal;
    std::unique_ptr<net::Transport> t;
    std::uint64_t now = 1;
    std::vector<net::Event> events;

    Fixture() {
        rtc::RtcConfig c;
        std::string error;
        t = rtc::listen_rtc(c, signal, error);
        EXPECT_TRUE(t) << error;
    }
    // Runs the server and the browsers for `ms`, until `done`.
    template <class Done>
    bool run(std::vector<Browser*> browsers, int ms, Done done) {
        for (int i = 0; i < ms; ++i) {
            t->service(now++, events);
            for (Browser* b : browsers) b->pump();
            SctpAssociation::advance_timers(1);
            if (done()) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return false;
    }
    int count(net::Event::Type type) const {
        return static_cast<int>(std::count_if(events.begin(), events.end(), [&](const net::Event& e) { return e.type == type; }));
    }
};

Sha256Fingerprint fingerprint_in(const std::string& answer) {
    const std::string text = answer_line(answer, "a=fingerprint:sha-256 ");
    Sha256Fingerprint fp{};
    for (std::size_t i = 0; i < fp.size(); ++i) fp[i] = static_cast<std::uint8_t>(std::stoi(text.substr(i * 3, 2), nullptr, 16));
    return fp;
}

// Connects `b` (posting from `address`); the connected event's peer.
net::PeerId connect(Fixture& f, Browser& b, const std::string& address) {
    const rtc::RtcReply r = f.signal->offer(offer_with(b.context->fingerprint()), address, "127.0.0.1");
    EXPECT_EQ(r.status, 200) << r.body;
    if (r.status != 200) return 0;
    b.start(r.body, fingerprint_in(r.body));
    EXPECT_TRUE(f.run({&b}, 5000, [&] { return f.count(net::Event::Type::connected) > 0; }));
    for (const auto& e : f.events)
        if (e.type == net::Event::Type::connected) return e.peer;
    return 0;
}

}  // namespace

TEST(RtcTransport, ConnectsAndCarriesBothChannels) {
    Fixture f;
    Browser b("127.0.0.1");
    const net::PeerId peer = connect(f, b, "127.0.0.1");
    ASSERT_GE(peer, rtc::kRtcPeerBase);
    const Bytes hello{1, 2, 3};
    b.sctp->send(2, kPpidBinary, hello);
    b.sctp->send(0, kPpidBinary, Bytes{9}, SctpSendOptions{true, 0u, std::nullopt});
    ASSERT_TRUE(f.run({&b}, 2000, [&] { return f.count(net::Event::Type::received) >= 2; }));
    for (const auto& e : f.events) {
        if (e.type != net::Event::Type::received) continue;
        EXPECT_EQ(e.channel, e.data == hello ? net::Channel::reliable : net::Channel::unreliable);
    }
    EXPECT_TRUE(f.t->send(peer, net::Channel::unreliable, Bytes(rtc::kMaxUnreliableBytes, 5)));
    // Too large for one datagram: whole, on the reliable channel (stream 2).
    EXPECT_TRUE(f.t->send(peer, net::Channel::unreliable, Bytes(rtc::kMaxUnreliableBytes + 1, 7)));
    EXPECT_TRUE(f.t->send(peer, net::Channel::reliable, Bytes(6144 + 64, 6)));  // a TrackChunk
    EXPECT_FALSE(f.t->send(peer, net::Channel::reliable, Bytes(rtc::kMaxReliableBytes + 1, 6)));
    const auto binary = [&] {
        return std::count_if(b.received.begin(), b.received.end(), [](const auto& m) { return m.ppid == kPpidBinary; });
    };
    ASSERT_TRUE(f.run({&b}, 2000, [&] { return binary() >= 3; }));
    for (const auto& m : b.received) {
        if (m.ppid != kPpidBinary) continue;
        EXPECT_EQ(m.stream, m.data.size() == rtc::kMaxUnreliableBytes ? 0 : 2) << m.data.size() << " bytes";
    }
    EXPECT_EQ(rtc::rtc_stats(*f.t).unreliable_sent_reliably, 1u);
    f.t->disconnect(peer);
    ASSERT_TRUE(f.run({&b}, 3000, [&] { return f.count(net::Event::Type::disconnected) == 1; }));
}

// Junk on the UDP port, from another address and from the browser's own
// (DTLS-looking records that are no records of its session, truncated STUN),
// is dropped: the session goes on.
TEST(RtcTransport, JunkDatagramsLeaveTheSessionAlone) {
    Fixture f;
    Browser b("127.0.0.1");
    const net::PeerId peer = connect(f, b, "127.0.0.1");
    ASSERT_GE(peer, rtc::kRtcPeerBase);
    Browser other("127.0.0.1");
    other.server = b.server;
    std::uint32_t x = 33;
    for (int i = 0; i < 2000; ++i) {
        Bytes junk(1 + (x % 1400));
        for (auto& byte : junk) byte = static_cast<std::uint8_t>((x = x * 1664525u + 1013904223u) >> 24);
        if (i % 3 == 0) junk[0] = static_cast<std::uint8_t>(20 + i % 44);  // DTLS-looking
        if (i % 3 == 1 && junk.size() >= 20) {                             // STUN-looking
            junk[0] = 0;
            junk[4] = 0x21, junk[5] = 0x12, junk[6] = 0xA4, junk[7] = 0x42;
        }
        (i % 2 == 0 ? other : b).put(junk);
        if (i % 100 == 0) f.t->service(f.now++, f.events);
    }
    b.sctp->send(2, kPpidBinary, Bytes{4, 2});
    ASSERT_TRUE(f.run({&b}, 3000, [&] { return f.count(net::Event::Type::received) > 0; }));
    EXPECT_EQ(f.count(net::Event::Type::disconnected), 0);
}

TEST(RtcTransport, RefusesBadOffers) {
    Fixture f;
    const auto reply = [&](const std::string& sdp) { return f.signal->offer(sdp, "10.0.0.1", "127.0.0.1"); };
    EXPECT_EQ(reply(std::string(20000, 'a')).status, 400);
    EXPECT_NE(reply(std::string(20000, 'a')).body.find("too large"), std::string::npos);
    EXPECT_EQ(reply("hello\r\n").status, 400);
    std::string no_fp = kOffer;
    no_fp.erase(no_fp.find("a=fingerprint"), no_fp.find("a=setup") - no_fp.find("a=fingerprint"));
    const auto r = reply(no_fp);
    EXPECT_EQ(r.status, 400);
    EXPECT_NE(r.body.find("no sha-256 fingerprint"), std::string::npos) << r.body;
    EXPECT_EQ(rtc::rtc_stats(*f.t).offers_refused_bad, 4u);
}

TEST(RtcTransport, HalfFinishedHandshakesDoNotLockOutOthers) {
    Fixture f;
    Browser flooder_cert("127.0.0.1");
    int answered = 0, busy = 0;
    for (int i = 0; i < 100; ++i) {
        const auto r = f.signal->offer(offer_with(flooder_cert.context->fingerprint()), "127.0.0.5", "127.0.0.1");
        answered += r.status == 200 ? 1 : 0;
        busy += r.status == 503 ? 1 : 0;
    }
    EXPECT_EQ(answered, 4);  // RtcConfig::max_pending_per_address
    EXPECT_EQ(busy, 96);
    Browser honest("127.0.0.1");
    EXPECT_GE(connect(f, honest, "127.0.0.1"), rtc::kRtcPeerBase);
    // The flood's pending sessions expire (no ICE): the address may try again.
    f.now += 11000;
    f.run({}, 2, [] { return false; });
    EXPECT_EQ(rtc::rtc_stats(*f.t).pending_expired, 4u);
    EXPECT_EQ(f.signal->offer(offer_with(flooder_cert.context->fingerprint()), "127.0.0.5", "127.0.0.1").status, 200);
}

TEST(RtcTransport, RateLimitsStunPerAddress) {
    Fixture f;
    BindingRequestFields fields;
    fields.username = "nobody:brws";
    const Bytes check = build_binding_request(fields, "abcdefghijklmnopqrstuvwx");
    Browser b("127.0.0.1");
    b.server.sin_family = AF_INET;
    inet_pton(AF_INET, "127.0.0.1", &b.server.sin_addr);
    b.server.sin_port = htons(f.t->local_port());
    for (int i = 0; i < 300; ++i) b.put(check);
    f.t->service(f.now, f.events);
    EXPECT_GE(rtc::rtc_stats(*f.t).rate_limited, 150u);
}
