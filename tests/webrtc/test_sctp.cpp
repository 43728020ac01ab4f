// SCTP over usrsctp (AF_CONN, no threads): two associations in one process
// connected through their packet queues, as a browser and the server are
// through DTLS. DCEP open and ack, ordered and unordered binary messages,
// loss on a reliable and on a maxRetransmits:0 stream under the caller's
// clock, fragmentation, stream resets, several associations at once, and
// the whole stack through real DTLS endpoints.
#include "jetrace/webrtc/dcep.hpp"
#include "jetrace/webrtc/dtls.hpp"
#include "jetrace/webrtc/sctp.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <functional>
#include <thread>

using namespace jetrace::webrtc;

namespace {

using Bytes = std::vector<std::uint8_t>;
using Drop = std::function<bool(const Bytes&)>;

struct Largest {
    std::size_t bytes = 0;
};

// Moves packets both ways until neither side has any (or `drop` eats them).
void pump(SctpAssociation& a, SctpAssociation& b, const Drop& drop = {}, Largest* largest = nullptr) {
    for (int round = 0; round < 64; ++round) {
        auto from_a = a.take_outgoing();
        auto from_b = b.take_outgoing();
        if (from_a.empty() && from_b.empty()) return;
        for (const auto& p : from_a) {
            if (largest) largest->bytes = std::max(largest->bytes, p.size());
            if (!drop || !drop(p)) b.feed(p);
        }
        for (const auto& p : from_b) {
            if (largest) largest->bytes = std::max(largest->bytes, p.size());
            if (!drop || !drop(p)) a.feed(p);
        }
    }
}

// Runs the caller's clock forward in 50 ms steps, pumping after each. Each
// step also lets 5 ms of real time pass: usrsctp's retransmission timer runs
// on the caller's clock, but when it fires a chunk is only sent again if it
// has been out longer than the smoothed RTT by the real clock
// (sctp_mark_all_for_resend), a few ms on loopback.
void run_clock(SctpAssociation& a, SctpAssociation& b, std::uint32_t ms) {
    for (std::uint32_t t = 0; t < ms; t += 50) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        SctpAssociation::advance_timers(50);
        pump(a, b);
    }
}

Bytes payload(std::size_t n, std::uint8_t seed) {
    Bytes b(n);
    for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(seed + i * 31);
    return b;
}

struct Pair {
    SctpAssociation browser{SctpSettings{}};
    SctpAssociation server{SctpSettings{}};
    Pair() { pump(browser, server); }
};

// WebRTC's {ordered: false, maxRetransmits: 0}.
const SctpSendOptions kUnreliable = [] {
    SctpSendOptions o;
    o.unordered = true;
    o.max_retransmits = 0;
    return o;
}();

}  // namespace

TEST(Sctp, ConnectsWithPacketsWithinTheMtu) {
    SctpAssociation a{SctpSettings{}};
    SctpAssociation b{SctpSettings{}};
    EXPECT_EQ(a.state(), SctpState::kConnecting) << a.error_detail();
    EXPECT_EQ(a.send(0, kPpidBinary, payload(4, 1)), SctpSendResult::kNotConnected);
    Largest largest;
    pump(a, b, {}, &largest);
    EXPECT_EQ(a.state(), SctpState::kConnected);
    EXPECT_EQ(b.state(), SctpState::kConnected);
    EXPECT_GT(largest.bytes, 0u);
    EXPECT_LE(largest.bytes, SctpSettings{}.mtu_bytes);
    EXPECT_EQ(a.send(0, kPpidBinary, Bytes{}), SctpSendResult::kEmpty);
}

TEST(Sctp, DcepOpenAckThenOrderedAndUnorderedMessages) {
    Pair p;
    ASSERT_EQ(p.server.state(), SctpState::kConnected);
    // The browser opens the unreliable channel on stream 1 and the reliable one on stream 3.
    DataChannelOpen unreliable;
    unreliable.channel_type = kChannelPartialReliableRexmitUnordered;
    unreliable.label = "unreliable";
    DataChannelOpen reliable;
    reliable.label = "reliable";
    ASSERT_EQ(p.browser.send(1, kPpidDcep, build_dcep_open(unreliable)), SctpSendResult::kSent);
    ASSERT_EQ(p.browser.send(3, kPpidDcep, build_dcep_open(reliable)), SctpSendResult::kSent);
    pump(p.browser, p.server);
    auto opens = p.server.take_messages();
    ASSERT_EQ(opens.size(), 2u);
    for (const SctpMessage& m : opens) {
        EXPECT_EQ(m.ppid, kPpidDcep);
        DataChannelOpen open;
        ASSERT_EQ(parse_dcep_open(m.data, open), DcepError::kNone);
        EXPECT_EQ(open, m.stream == 1 ? unreliable : reliable);
        ASSERT_EQ(p.server.send(m.stream, kPpidDcep, build_dcep_ack()), SctpSendResult::kSent);
    }
    pump(p.browser, p.server);
    const auto acks = p.browser.take_messages();
    ASSERT_EQ(acks.size(), 2u);
    EXPECT_TRUE(is_dcep_ack(acks[0].data) && is_dcep_ack(acks[1].data));
    // Ten messages each way on each stream: the reliable stream keeps their order.
    for (std::uint8_t i = 0; i < 10; ++i) {
        ASSERT_EQ(p.server.send(1, kPpidBinary, payload(200, i), kUnreliable), SctpSendResult::kSent);
        ASSERT_EQ(p.server.send(3, kPpidBinary, payload(300, i)), SctpSendResult::kSent);
        ASSERT_EQ(p.browser.send(1, kPpidBinary, payload(20, i), kUnreliable), SctpSendResult::kSent);
    }
    pump(p.browser, p.server);
    const auto at_browser = p.browser.take_messages();
    ASSERT_EQ(at_browser.size(), 20u);
    std::uint8_t next_reliable = 0;
    for (const SctpMessage& m : at_browser) {
        EXPECT_EQ(m.ppid, kPpidBinary);
        EXPECT_EQ(m.unordered, m.stream == 1);
        if (m.stream == 3) {
            EXPECT_EQ(m.data, payload(300, next_reliable++));
        }
    }
    EXPECT_EQ(next_reliable, 10);
    EXPECT_EQ(p.server.take_messages().size(), 10u);
}

// A lost DATA packet: on the reliable stream it comes again after the
// retransmission timeout of the caller's clock; with maxRetransmits 0 it is
// abandoned, and later messages still arrive.
TEST(Sctp, LossUnderTheCallersClock) {
    Pair p;
    bool dropped = false;
    const Drop drop_first_data = [&](const Bytes& packet) {
        // Common header 12 bytes, then the first chunk's type: 0 is DATA.
        if (dropped || packet.size() < 13 || packet[12] != 0) return false;
        dropped = true;
        return true;
    };
    ASSERT_EQ(p.server.send(3, kPpidBinary, payload(100, 7)), SctpSendResult::kSent);
    pump(p.browser, p.server, drop_first_data);
    ASSERT_TRUE(dropped);
    EXPECT_TRUE(p.browser.take_messages().empty());
    run_clock(p.browser, p.server, 3000);
    auto got = p.browser.take_messages();
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].data, payload(100, 7));

    dropped = false;
    ASSERT_EQ(p.server.send(1, kPpidBinary, payload(100, 8), kUnreliable), SctpSendResult::kSent);
    pump(p.browser, p.server, drop_first_data);
    ASSERT_TRUE(dropped);
    run_clock(p.browser, p.server, 3000);
    ASSERT_EQ(p.server.send(1, kPpidBinary, payload(100, 9), kUnreliable), SctpSendResult::kSent);
    pump(p.browser, p.server);
    got = p.browser.take_messages();
    ASSERT_EQ(got.size(), 1u);  // the abandoned message never arrives
    EXPECT_EQ(got[0].data, payload(100, 9));
}

TEST(Sctp, LargeMessagesAreFragmentedAndJoined) {
    Pair p;
    Largest largest;
    ASSERT_EQ(p.server.send(3, kPpidBinary, payload(5000, 3)), SctpSendResult::kSent);
    ASSERT_EQ(p.server.send(3, kPpidString, payload(40000, 4)), SctpSendResult::kSent);
    pump(p.browser, p.server, {}, &largest);
    run_clock(p.browser, p.server, 500);  // window updates, delayed SACKs
    const auto got = p.browser.take_messages();
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].data, payload(5000, 3));
    EXPECT_EQ(got[1].data, payload(40000, 4));
    EXPECT_EQ(got[1].ppid, kPpidString);
    EXPECT_LE(largest.bytes, SctpSettings{}.mtu_bytes);
    EXPECT_EQ(p.server.send(3, kPpidBinary, payload(SctpSettings{}.max_message_bytes + 1, 0)), SctpSendResult::kTooLarge);
}

TEST(Sctp, StreamResetReachesThePeer) {
    Pair p;
    ASSERT_EQ(p.browser.send(5, kPpidBinary, payload(10, 1)), SctpSendResult::kSent);
    pump(p.browser, p.server);
    ASSERT_TRUE(p.browser.reset_stream(5));
    pump(p.browser, p.server);
    EXPECT_EQ(p.server.take_reset_streams(), std::vector<std::uint16_t>{5});
    EXPECT_TRUE(p.browser.take_reset_streams().empty());
}

TEST(Sctp, ManyAssociationsInOneProcessStayApart) {
    std::vector<std::unique_ptr<Pair>> pairs;
    for (int i = 0; i < 4; ++i) pairs.push_back(std::make_unique<Pair>());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        ASSERT_EQ(pairs[i]->server.state(), SctpState::kConnected) << i;
        ASSERT_EQ(pairs[i]->server.send(3, kPpidBinary, payload(50, static_cast<std::uint8_t>(i))), SctpSendResult::kSent);
    }
    pairs.erase(pairs.begin() + 1);  // one goes away mid-way
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        pump(pairs[i]->browser, pairs[i]->server);
        const auto got = pairs[i]->browser.take_messages();
        ASSERT_EQ(got.size(), 1u);
        EXPECT_EQ(got[0].data, payload(50, static_cast<std::uint8_t>(i == 0 ? 0 : i + 1)));
    }
}

// usrsctp_init_nothreads: no timer and no receive thread (their work runs in
// the caller's calls); Debian's 0.9.5.0 still starts its idle iterator thread.
TEST(Sctp, UsrsctpRunsNoTimerOrReceiveThread) {
    Pair p;
    ASSERT_EQ(p.server.state(), SctpState::kConnected);
    SctpAssociation::advance_timers(100);
    // The names of the threads but this one (a new thread names itself
    // shortly after it starts: until then it has the process's name).
    const auto others = [] {
        std::vector<std::string> names;
        for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) {
            if (entry.path().filename() == std::to_string(getpid())) continue;
            std::ifstream comm(entry.path() / "comm");
            std::string name;
            std::getline(comm, name);
            names.push_back(name);
        }
        return names;
    };
    const auto only_iterator = [](const std::vector<std::string>& names) {
        return names.size() <= 1 && std::all_of(names.begin(), names.end(), [](const auto& n) { return n == "SCTP iterator"; });
    };
    std::vector<std::string> names = others();
    for (int i = 0; i < 100 && !only_iterator(names); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        names = others();
    }
    EXPECT_TRUE(only_iterator(names)) << names.size() << " other threads, the first: " << (names.empty() ? "" : names[0]);
}

TEST(Sctp, GarbagePacketsAreDropped) {
    Pair p;
    p.server.feed(payload(64, 9));
    p.server.feed(Bytes{0x13, 0x88, 0x13, 0x88});
    p.server.feed(payload(1500, 1));
    ASSERT_EQ(p.browser.send(3, kPpidBinary, payload(10, 2)), SctpSendResult::kSent);
    pump(p.browser, p.server);
    EXPECT_EQ(p.server.state(), SctpState::kConnected);
    EXPECT_EQ(p.server.take_messages().size(), 1u);
}

// The whole stack: SCTP packets in DTLS records, DCEP and a message through.
TEST(Sctp, OverDtls) {
    const auto browser_cert = DtlsContext::create(DtlsSettings{});
    const auto server_cert = DtlsContext::create(DtlsSettings{});
    ASSERT_TRUE(browser_cert && server_cert);
    DtlsEndpoint browser_dtls(*browser_cert, DtlsRole::kClient, server_cert->fingerprint());
    DtlsEndpoint server_dtls(*server_cert, DtlsRole::kServer, browser_cert->fingerprint());
    SctpAssociation browser{SctpSettings{}};
    SctpAssociation server{SctpSettings{}};
    const auto step = [](DtlsEndpoint& from_dtls, SctpAssociation& from_sctp, DtlsEndpoint& to_dtls, SctpAssociation& to_sctp) {
        if (from_dtls.handshake_done()) {
            for (const auto& packet : from_sctp.take_outgoing()) EXPECT_TRUE(from_dtls.send(packet));
        }
        bool moved = false;
        for (const auto& d : from_dtls.take_outgoing()) {
            EXPECT_LE(d.size(), 1200u);
            to_dtls.feed(d);
            moved = true;
        }
        for (const auto& packet : to_dtls.take_received()) to_sctp.feed(packet);
        return moved;
    };
    ASSERT_EQ(browser.send(1, kPpidDcep, Bytes{}), SctpSendResult::kNotConnected);
    for (int i = 0; i < 64; ++i) {
        const bool a = step(browser_dtls, browser, server_dtls, server);
        const bool b = step(server_dtls, server, browser_dtls, browser);
        if (!a && !b && browser.state() == SctpState::kConnected && server.state() == SctpState::kConnected) break;
    }
    ASSERT_EQ(server.state(), SctpState::kConnected);
    DataChannelOpen open;
    open.channel_type = kChannelPartialReliableRexmitUnordered;
    ASSERT_EQ(browser.send(1, kPpidDcep, build_dcep_open(open)), SctpSendResult::kSent);
    ASSERT_EQ(browser.send(1, kPpidBinary, payload(1000, 5), kUnreliable), SctpSendResult::kSent);
    for (int i = 0; i < 8; ++i) {
        step(browser_dtls, browser, server_dtls, server);
        step(server_dtls, server, browser_dtls, browser);
    }
    const auto got = server.take_messages();
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].ppid, kPpidDcep);
    EXPECT_EQ(got[1].data, payload(1000, 5));
}
