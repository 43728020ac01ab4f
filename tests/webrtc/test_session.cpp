// DataChannelSession against a browser made of the same blocks (a DTLS
// client with its own certificate, an SCTP association, DCEP opens as
// Chromium sends them): channels open and are acknowledged, messages go
// both ways with each channel's ordering and PPID, empty messages, data on
// a stream with no channel dropped, a closed channel reset both ways, and a
// browser with another certificate refused.
#include "jetrace/webrtc/session.hpp"

#include <gtest/gtest.h>

using namespace jetrace::webrtc;

namespace {

using Bytes = std::vector<std::uint8_t>;

// The browser's side: DTLS client, SCTP, and what it received.
struct Browser {
    std::unique_ptr<DtlsContext> context = DtlsContext::create(DtlsSettings{});
    std::unique_ptr<DtlsEndpoint> dtls;
    SctpAssociation sctp{SctpSettings{}};
    std::vector<SctpMessage> received;

    explicit Browser(const Sha256Fingerprint& server) {
        dtls = std::make_unique<DtlsEndpoint>(*context, DtlsRole::kClient, server);
    }
    SdpOffer offer() const {
        SdpOffer o;
        o.fingerprint = context->fingerprint();
        return o;
    }
};

// Datagrams both ways until none move.
void pump(Browser& b, DataChannelSession& s) {
    for (int round = 0; round < 64; ++round) {
        if (b.dtls->handshake_done()) {
            for (const auto& packet : b.sctp.take_outgoing()) b.dtls->send(packet);
        }
        const auto to_server = b.dtls->take_outgoing();
        const auto to_browser = s.take_outgoing();
        if (to_server.empty() && to_browser.empty()) return;
        for (const auto& d : to_server) s.feed(d);
        for (const auto& d : to_browser) b.dtls->feed(d);
        for (const auto& packet : b.dtls->take_received()) b.sctp.feed(packet);
        for (auto& m : b.sctp.take_messages()) b.received.push_back(std::move(m));
    }
}

struct Fixture {
    std::unique_ptr<DtlsContext> server_context = DtlsContext::create(DtlsSettings{});
    Browser browser{server_context->fingerprint()};
    DataChannelSession session{*server_context, browser.offer()};

    // Chromium's two channels: unreliable unordered on stream 0, reliable on 2.
    void open_channels() {
        pump(browser, session);
        ASSERT_EQ(session.state(), SessionState::kOpen) << session.error_detail();
        DataChannelOpen unreliable;
        unreliable.channel_type = kChannelPartialReliableRexmitUnordered;
        unreliable.priority = 256;
        unreliable.label = "unreliable";
        DataChannelOpen reliable;
        reliable.priority = 256;
        reliable.label = "reliable";
        ASSERT_EQ(browser.sctp.send(0, kPpidDcep, build_dcep_open(unreliable)), SctpSendResult::kSent);
        ASSERT_EQ(browser.sctp.send(2, kPpidDcep, build_dcep_open(reliable)), SctpSendResult::kSent);
        pump(browser, session);
    }
};

Bytes bytes(std::string_view s) { return Bytes(s.begin(), s.end()); }

}  // namespace

TEST(Session, OpensAndAcknowledgesChannels) {
    Fixture f;
    f.open_channels();
    EXPECT_EQ(f.session.take_opened(), (std::vector<std::uint16_t>{0, 2}));
    EXPECT_EQ(f.session.find_channel("unreliable"), 0);
    EXPECT_EQ(f.session.find_channel("reliable"), 2);
    EXPECT_FALSE(f.session.find_channel("other").has_value());
    ASSERT_NE(f.session.channel(0), nullptr);
    EXPECT_TRUE(f.session.channel(0)->unordered());
    ASSERT_EQ(f.browser.received.size(), 2u);
    for (const auto& m : f.browser.received) {
        EXPECT_EQ(m.ppid, kPpidDcep);
        EXPECT_TRUE(is_dcep_ack(m.data));
        EXPECT_FALSE(m.unordered);  // DCEP is reliable and ordered
    }
}

TEST(Session, MessagesBothWaysWithEachChannelsReliability) {
    Fixture f;
    f.open_channels();
    f.browser.received.clear();
    SctpSendOptions unreliable;
    unreliable.unordered = true;
    unreliable.max_retransmits = 0;
    ASSERT_EQ(f.browser.sctp.send(0, kPpidBinary, bytes("input"), unreliable), SctpSendResult::kSent);
    ASSERT_EQ(f.browser.sctp.send(2, kPpidString, bytes("hello")), SctpSendResult::kSent);
    const std::uint8_t zero = 0;
    ASSERT_EQ(f.browser.sctp.send(2, kPpidBinaryEmpty, {&zero, 1}), SctpSendResult::kSent);
    ASSERT_EQ(f.browser.sctp.send(4, kPpidBinary, bytes("no channel")), SctpSendResult::kSent);
    pump(f.browser, f.session);
    const auto got = f.session.take_messages();
    ASSERT_EQ(got.size(), 3u);  // stream 4 has no channel: dropped
    EXPECT_EQ(got[0].stream, 0);
    EXPECT_TRUE(got[0].binary);
    EXPECT_EQ(got[0].data, bytes("input"));
    EXPECT_EQ(got[1].stream, 2);
    EXPECT_FALSE(got[1].binary);
    EXPECT_EQ(got[1].data, bytes("hello"));
    EXPECT_TRUE(got[2].binary);
    EXPECT_TRUE(got[2].data.empty());

    ASSERT_EQ(f.session.send(0, bytes("snapshot")), SctpSendResult::kSent);
    ASSERT_EQ(f.session.send(2, bytes("results")), SctpSendResult::kSent);
    ASSERT_EQ(f.session.send(2, Bytes{}), SctpSendResult::kSent);
    ASSERT_EQ(f.session.send(2, bytes("text"), false), SctpSendResult::kSent);
    EXPECT_EQ(f.session.send(4, bytes("x")), SctpSendResult::kNotConnected);
    pump(f.browser, f.session);
    ASSERT_EQ(f.browser.received.size(), 4u);
    EXPECT_EQ(f.browser.received[3].ppid, kPpidString);
    EXPECT_EQ(f.browser.received[3].data, bytes("text"));
    EXPECT_EQ(f.browser.received[0].stream, 0);
    EXPECT_TRUE(f.browser.received[0].unordered);
    EXPECT_EQ(f.browser.received[0].ppid, kPpidBinary);
    EXPECT_EQ(f.browser.received[0].data, bytes("snapshot"));
    EXPECT_FALSE(f.browser.received[1].unordered);
    EXPECT_EQ(f.browser.received[1].data, bytes("results"));
    EXPECT_EQ(f.browser.received[2].ppid, kPpidBinaryEmpty);
    EXPECT_EQ(f.browser.received[2].data, Bytes{0});
}

TEST(Session, ClosedChannelIsResetBothWays) {
    Fixture f;
    f.open_channels();
    (void)f.session.take_opened();
    ASSERT_TRUE(f.browser.sctp.reset_stream(0));
    pump(f.browser, f.session);
    EXPECT_EQ(f.session.take_closed(), std::vector<std::uint16_t>{0});
    EXPECT_EQ(f.session.channel(0), nullptr);
    EXPECT_NE(f.session.channel(2), nullptr);
    EXPECT_EQ(f.browser.sctp.take_reset_streams(), std::vector<std::uint16_t>{0});
    EXPECT_EQ(f.session.send(0, bytes("x")), SctpSendResult::kNotConnected);
    EXPECT_EQ(f.session.state(), SessionState::kOpen);
}

TEST(Session, BrowserWithAnotherCertificateIsRefused) {
    const auto server_context = DtlsContext::create(DtlsSettings{});
    Browser browser(server_context->fingerprint());
    SdpOffer offer = browser.offer();
    offer.fingerprint[0] ^= 0x80;  // the offer named another certificate
    DataChannelSession session(*server_context, offer);
    EXPECT_EQ(session.state(), SessionState::kConnecting);
    pump(browser, session);
    EXPECT_EQ(session.state(), SessionState::kFailed);
    EXPECT_FALSE(session.error_detail().empty());
    EXPECT_TRUE(session.take_messages().empty());
}
