// DCEP (RFC 8832): DATA_CHANNEL_OPEN read from hand-computed bytes (what
// createDataChannel("unreliable", {ordered: false, maxRetransmits: 0}) and
// a reliable channel with a protocol send; Chromium 156 sent the first and
// kChromiumReliableOpen byte for byte to webrtc_echo_peer), written back
// byte for byte, and every malformed form refused with its error.
#include "jetrace/webrtc/dcep.hpp"

#include <gtest/gtest.h>

using namespace jetrace::webrtc;

namespace {

using Bytes = std::vector<std::uint8_t>;

// Type 3, channel type 0x81 (rexmit, unordered), priority 256, 0
// retransmissions, label "unreliable" (10 bytes), no protocol.
const Bytes kUnreliableOpen = {0x03, 0x81, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0a, 0x00, 0x00,
                               'u',  'n',  'r',  'e',  'l',  'i',  'a',  'b',  'l',  'e'};
// Chromium 156's createDataChannel("reliable"): reliable ordered, priority 256.
const Bytes kChromiumReliableOpen = {0x03, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00,
                                     'r',  'e',  'l',  'i',  'a',  'b',  'l',  'e'};
// Type 3, reliable ordered, priority 512, label "rel", protocol "jr1".
const Bytes kReliableOpen = {0x03, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x03, 0x00, 0x03,
                             'r',  'e',  'l',  'j',  'r',  '1'};

}  // namespace

TEST(Dcep, ReadsUnreliableUnorderedOpen) {
    DataChannelOpen o;
    ASSERT_EQ(parse_dcep_open(kUnreliableOpen, o), DcepError::kNone);
    EXPECT_EQ(o.channel_type, kChannelPartialReliableRexmitUnordered);
    EXPECT_TRUE(o.unordered());
    EXPECT_TRUE(o.partial());
    EXPECT_EQ(o.priority, 256);
    EXPECT_EQ(o.reliability, 0u);
    EXPECT_EQ(o.label, "unreliable");
    EXPECT_EQ(o.protocol, "");
    EXPECT_EQ(build_dcep_open(o), kUnreliableOpen);
}

TEST(Dcep, ReadsReliableOpenWithProtocol) {
    DataChannelOpen o;
    ASSERT_EQ(parse_dcep_open(kReliableOpen, o), DcepError::kNone);
    EXPECT_EQ(o.channel_type, kChannelReliable);
    EXPECT_FALSE(o.unordered());
    EXPECT_FALSE(o.partial());
    EXPECT_EQ(o.priority, 512);
    EXPECT_EQ(o.label, "rel");
    EXPECT_EQ(o.protocol, "jr1");
    EXPECT_EQ(build_dcep_open(o), kReliableOpen);
}

TEST(Dcep, ReadsChromiumReliableOpen) {
    DataChannelOpen o;
    ASSERT_EQ(parse_dcep_open(kChromiumReliableOpen, o), DcepError::kNone);
    EXPECT_EQ(o.channel_type, kChannelReliable);
    EXPECT_EQ(o.priority, 256);
    EXPECT_EQ(o.label, "reliable");
    EXPECT_EQ(build_dcep_open(o), kChromiumReliableOpen);
}

TEST(Dcep, AckIsOneByte) {
    EXPECT_EQ(build_dcep_ack(), Bytes{0x02});
    EXPECT_TRUE(is_dcep_ack(build_dcep_ack()));
    EXPECT_FALSE(is_dcep_ack(Bytes{0x02, 0x00}));
    EXPECT_FALSE(is_dcep_ack(Bytes{}));
    DataChannelOpen o;
    EXPECT_EQ(parse_dcep_open(build_dcep_ack(), o), DcepError::kNotOpen);
}

TEST(Dcep, MalformedOpensRefused) {
    DataChannelOpen o;
    EXPECT_EQ(parse_dcep_open(Bytes{}, o), DcepError::kEmpty);
    for (std::size_t n = 1; n < kDcepOpenHeaderBytes; ++n)
        EXPECT_EQ(parse_dcep_open(std::span(kUnreliableOpen).first(n), o), DcepError::kTooShort) << n;
    for (std::size_t n = kDcepOpenHeaderBytes; n < kUnreliableOpen.size(); ++n)
        EXPECT_EQ(parse_dcep_open(std::span(kUnreliableOpen).first(n), o), DcepError::kLengthMismatch) << n;
    Bytes longer = kUnreliableOpen;
    longer.push_back('!');
    EXPECT_EQ(parse_dcep_open(longer, o), DcepError::kLengthMismatch);
    Bytes huge = kReliableOpen;
    huge[8] = 0xff;  // label length 0xff03: past the end
    EXPECT_EQ(parse_dcep_open(huge, o), DcepError::kLengthMismatch);
    huge[8] = 0x00;
    huge[10] = 0xff;
    huge[11] = 0xff;
    EXPECT_EQ(parse_dcep_open(huge, o), DcepError::kLengthMismatch);
    for (const int t : {0x03, 0x7f, 0x80 | 0x03, 0xff}) {
        Bytes bad = kReliableOpen;
        bad[1] = static_cast<std::uint8_t>(t);
        EXPECT_EQ(parse_dcep_open(bad, o), DcepError::kBadChannelType) << t;
    }
    Bytes other = kReliableOpen;
    other[0] = 0x04;
    EXPECT_EQ(parse_dcep_open(other, o), DcepError::kNotOpen);
    EXPECT_EQ(o, DataChannelOpen{});  // nothing left from a refused message
}
