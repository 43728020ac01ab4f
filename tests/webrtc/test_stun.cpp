// STUN for ICE-lite against RFC 5769's test vectors (section 2.1: a request
// with MESSAGE-INTEGRITY and FINGERPRINT; 2.2 and 2.3: responses with an
// IPv4 and an IPv6 XOR-MAPPED-ADDRESS), and the server's own messages read
// back; tampering and truncation refused with the right error.
#include "jetrace/webrtc/stun.hpp"

#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <vector>

using namespace jetrace::webrtc;

namespace {

using Bytes = std::vector<std::uint8_t>;

// RFC 5769 section 2.1: username "evtj:h6vY", password "VOkJxbRl1RmTxUk/WvJxBt".
const Bytes kSampleRequest = {
    0x00, 0x01, 0x00, 0x58, 0x21, 0x12, 0xa4, 0x42, 0xb7, 0xe7, 0xa7, 0x01, 0xbc, 0x34, 0xd6, 0x86,
    0xfa, 0x87, 0xdf, 0xae, 0x80, 0x22, 0x00, 0x10, 0x53, 0x54, 0x55, 0x4e, 0x20, 0x74, 0x65, 0x73,
    0x74, 0x20, 0x63, 0x6c, 0x69, 0x65, 0x6e, 0x74, 0x00, 0x24, 0x00, 0x04, 0x6e, 0x00, 0x01, 0xff,
    0x80, 0x29, 0x00, 0x08, 0x93, 0x2f, 0xf9, 0xb1, 0x51, 0x26, 0x3b, 0x36, 0x00, 0x06, 0x00, 0x09,
    0x65, 0x76, 0x74, 0x6a, 0x3a, 0x68, 0x36, 0x76, 0x59, 0x20, 0x20, 0x20, 0x00, 0x08, 0x00, 0x14,
    0x9a, 0xea, 0xa7, 0x0c, 0xbf, 0xd8, 0xcb, 0x56, 0x78, 0x1e, 0xf2, 0xb5, 0xb2, 0xd3, 0xf2, 0x49,
    0xc1, 0xb5, 0x71, 0xa2, 0x80, 0x28, 0x00, 0x04, 0xe5, 0x7a, 0x3b, 0xcf};
// Sections 2.2 and 2.3: the responses, password as above, SOFTWARE "test vector".
const Bytes kSampleIpv4Response = {
    0x01, 0x01, 0x00, 0x3c, 0x21, 0x12, 0xa4, 0x42, 0xb7, 0xe7, 0xa7, 0x01, 0xbc, 0x34, 0xd6, 0x86,
    0xfa, 0x87, 0xdf, 0xae, 0x80, 0x22, 0x00, 0x0b, 0x74, 0x65, 0x73, 0x74, 0x20, 0x76, 0x65, 0x63,
    0x74, 0x6f, 0x72, 0x20, 0x00, 0x20, 0x00, 0x08, 0x00, 0x01, 0xa1, 0x47, 0xe1, 0x12, 0xa6, 0x43,
    0x00, 0x08, 0x00, 0x14, 0x2b, 0x91, 0xf5, 0x99, 0xfd, 0x9e, 0x90, 0xc3, 0x8c, 0x74, 0x89, 0xf9,
    0x2a, 0xf9, 0xba, 0x53, 0xf0, 0x6b, 0xe7, 0xd7, 0x80, 0x28, 0x00, 0x04, 0xc0, 0x7d, 0x4c, 0x96};
const Bytes kSampleIpv6Response = {
    0x01, 0x01, 0x00, 0x48, 0x21, 0x12, 0xa4, 0x42, 0xb7, 0xe7, 0xa7, 0x01, 0xbc, 0x34, 0xd6, 0x86,
    0xfa, 0x87, 0xdf, 0xae, 0x80, 0x22, 0x00, 0x0b, 0x74, 0x65, 0x73, 0x74, 0x20, 0x76, 0x65, 0x63,
    0x74, 0x6f, 0x72, 0x20, 0x00, 0x20, 0x00, 0x14, 0x00, 0x02, 0xa1, 0x47, 0x01, 0x13, 0xa9, 0xfa,
    0xa5, 0xd3, 0xf1, 0x79, 0xbc, 0x25, 0xf4, 0xb5, 0xbe, 0xd2, 0xb9, 0xd9, 0x00, 0x08, 0x00, 0x14,
    0xa3, 0x82, 0x95, 0x4e, 0x4b, 0xe6, 0x7b, 0xf1, 0x17, 0x84, 0xc9, 0x7c, 0x82, 0x92, 0xc2, 0x75,
    0xbf, 0xe3, 0xed, 0x41, 0x80, 0x28, 0x00, 0x04, 0xc8, 0xfb, 0x0b, 0x4c};
constexpr std::string_view kPassword = "VOkJxbRl1RmTxUk/WvJxBt";
constexpr StunTransactionId kTid = {0xb7, 0xe7, 0xa7, 0x01, 0xbc, 0x34, 0xd6, 0x86, 0xfa, 0x87, 0xdf, 0xae};
const StunAddress kIpv4 = StunAddress::v4({192, 0, 2, 1}, 32853);
const StunAddress kIpv6 = StunAddress::v6(
    {0x20, 0x01, 0x0d, 0xb8, 0x12, 0x34, 0x56, 0x78, 0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77}, 32853);

// Chromium 156's first connectivity check to webrtc_echo_peer (captured with
// JETRACE_ECHO_DUMP): USERNAME "y/LGz4cG:mrDx", GOOG-NETWORK-INFO (0xc057),
// ICE-CONTROLLING, PRIORITY, MESSAGE-INTEGRITY with the server's ice-pwd
// "okBt490qyXa+IszcsoSaoLjm", FINGERPRINT; no USE-CANDIDATE yet.
const Bytes kChromiumRequest = {
    0x00, 0x01, 0x00, 0x50, 0x21, 0x12, 0xa4, 0x42, 0x2f, 0x4d, 0x6a, 0x30, 0x48, 0x72, 0x47, 0x65,
    0x6c, 0x38, 0x61, 0x54, 0x00, 0x06, 0x00, 0x0d, 0x79, 0x2f, 0x4c, 0x47, 0x7a, 0x34, 0x63, 0x47,
    0x3a, 0x6d, 0x72, 0x44, 0x78, 0x00, 0x00, 0x00, 0xc0, 0x57, 0x00, 0x04, 0x00, 0x00, 0x03, 0xe7,
    0x80, 0x2a, 0x00, 0x08, 0x66, 0x82, 0xcd, 0x25, 0x77, 0x21, 0x04, 0xdc, 0x00, 0x24, 0x00, 0x04,
    0x6e, 0x00, 0x1e, 0xff, 0x00, 0x08, 0x00, 0x14, 0xf6, 0x0c, 0x9c, 0x65, 0xda, 0x33, 0x28, 0x70,
    0xde, 0x79, 0x8b, 0xd8, 0xa4, 0x42, 0xc4, 0x0c, 0x5e, 0x1a, 0x45, 0x65, 0x80, 0x28, 0x00, 0x04,
    0x65, 0xe1, 0x36, 0xdd};

// The vector up to (not including) MESSAGE-INTEGRITY: 24 + 8 bytes from its end.
Bytes before_integrity(const Bytes& v) { return Bytes(v.begin(), v.end() - 32); }

}  // namespace

TEST(Stun, Rfc5769RequestParsesAndVerifies) {
    ASSERT_TRUE(is_stun(kSampleRequest));
    StunMessage m;
    ASSERT_EQ(parse_binding_request(kSampleRequest, m), StunError::kNone);
    EXPECT_EQ(m.transaction_id, kTid);
    EXPECT_EQ(m.username, "evtj:h6vY");
    EXPECT_EQ(m.software, "STUN test client");
    EXPECT_EQ(m.priority, 0x6e0001ffu);
    EXPECT_EQ(m.ice_controlled, 0x932ff9b151263b36u);
    EXPECT_FALSE(m.ice_controlling.has_value());
    EXPECT_FALSE(m.use_candidate);
    EXPECT_TRUE(m.has_fingerprint);
    EXPECT_EQ(m.integrity_offset, kSampleRequest.size() - 32);
    EXPECT_TRUE(integrity_valid(kSampleRequest, m, kPassword));
    EXPECT_FALSE(integrity_valid(kSampleRequest, m, "VOkJxbRl1RmTxUk/WvJxBu"));
    EXPECT_FALSE(integrity_valid(kSampleRequest, m, ""));
    std::string_view receiver, sender;
    ASSERT_TRUE(split_ice_username(*m.username, receiver, sender));
    EXPECT_EQ(receiver, "evtj");
    EXPECT_EQ(sender, "h6vY");
}

TEST(Stun, ChromiumConnectivityCheck) {
    StunMessage m;
    ASSERT_EQ(parse_binding_request(kChromiumRequest, m), StunError::kNone);
    EXPECT_EQ(m.username, "y/LGz4cG:mrDx");
    EXPECT_EQ(m.priority, 0x6e001effu);
    EXPECT_EQ(m.ice_controlling, 0x6682cd25772104dcu);
    EXPECT_FALSE(m.ice_controlled.has_value());
    EXPECT_FALSE(m.use_candidate);
    EXPECT_TRUE(integrity_valid(kChromiumRequest, m, "okBt490qyXa+IszcsoSaoLjm"));
    EXPECT_FALSE(integrity_valid(kChromiumRequest, m, "okBt490qyXa+IszcsoSaoLjn"));
    Bytes rebuilt = before_integrity(kChromiumRequest);
    append_integrity_and_fingerprint(rebuilt, "okBt490qyXa+IszcsoSaoLjm");
    EXPECT_EQ(rebuilt, kChromiumRequest);
}

// The HMAC and CRC written here are the RFC's, byte for byte.
TEST(Stun, IntegrityAndFingerprintMatchRfc5769Bytes) {
    for (const Bytes* v : {&kSampleRequest, &kSampleIpv4Response, &kSampleIpv6Response}) {
        Bytes rebuilt = before_integrity(*v);
        append_integrity_and_fingerprint(rebuilt, kPassword);
        EXPECT_EQ(rebuilt, *v);
    }
}

// The HMAC also agrees with OpenSSL's HMAC over the message as RFC 8489
// section 14.5 describes it, computed here independently.
TEST(Stun, IntegrityIsHmacSha1WithAdjustedLength) {
    Bytes prefix = before_integrity(kSampleRequest);
    const std::size_t with_integrity = prefix.size() + 24 - 20;
    prefix[2] = static_cast<std::uint8_t>(with_integrity >> 8);
    prefix[3] = static_cast<std::uint8_t>(with_integrity);
    unsigned char mac[20];
    unsigned int size = 0;
    HMAC(EVP_sha1(), kPassword.data(), static_cast<int>(kPassword.size()), prefix.data(), prefix.size(), mac, &size);
    ASSERT_EQ(size, 20u);
    EXPECT_TRUE(std::equal(mac, mac + 20, kSampleRequest.end() - 28));
}

TEST(Stun, Rfc5769ResponsesDecodeXorMappedAddress) {
    StunMessage m;
    ASSERT_EQ(parse_stun(kSampleIpv4Response, m), StunError::kNone);
    EXPECT_EQ(m.type, kStunBindingSuccess);
    EXPECT_EQ(m.software, "test vector");
    EXPECT_EQ(m.xor_mapped_address, kIpv4);
    EXPECT_TRUE(integrity_valid(kSampleIpv4Response, m, kPassword));
    ASSERT_EQ(parse_stun(kSampleIpv6Response, m), StunError::kNone);
    EXPECT_EQ(m.xor_mapped_address, kIpv6);
    EXPECT_TRUE(integrity_valid(kSampleIpv6Response, m, kPassword));
    EXPECT_EQ(parse_binding_request(kSampleIpv6Response, m), StunError::kNotBindingRequest);
}

// build_binding_success() writes the RFC's XOR-MAPPED-ADDRESS bytes, and what
// it writes reads back with a valid integrity and fingerprint.
TEST(Stun, BindingSuccessReadsBack) {
    for (const auto& [address, vector] : {std::pair{kIpv4, &kSampleIpv4Response}, std::pair{kIpv6, &kSampleIpv6Response}}) {
        const Bytes out = build_binding_success(kTid, address, kPassword);
        ASSERT_TRUE(is_stun(out));
        StunMessage m;
        ASSERT_EQ(parse_stun(out, m), StunError::kNone);
        EXPECT_EQ(m.type, kStunBindingSuccess);
        EXPECT_EQ(m.transaction_id, kTid);
        EXPECT_EQ(m.xor_mapped_address, address);
        EXPECT_TRUE(m.has_fingerprint);
        EXPECT_TRUE(integrity_valid(out, m, kPassword));
        // Header, then XOR-MAPPED-ADDRESS as in the RFC (after its 16-byte SOFTWARE).
        const std::size_t attr_bytes = address.ipv6 ? 24 : 12;
        EXPECT_TRUE(std::equal(out.begin() + 20, out.begin() + 20 + attr_bytes, vector->begin() + 36));
        EXPECT_EQ(out.size(), 20 + attr_bytes + 24 + 8);
    }
    // With SOFTWARE the message differs from the RFC's only in its padding
    // (zeros here, spaces there), so everything but the checksums matches.
    const Bytes with_software = build_binding_success(kTid, kIpv4, kPassword, "test vector");
    ASSERT_EQ(with_software.size(), kSampleIpv4Response.size());
    Bytes expected = kSampleIpv4Response;
    expected[35] = 0;
    EXPECT_TRUE(std::equal(with_software.begin(), with_software.end() - 32, expected.begin()));
}

TEST(Stun, BrowserStyleRequestRoundTrips) {
    BindingRequestFields f;
    f.transaction_id = kTid;
    f.username = "srvUfrag1:rhrA";
    f.priority = 2113937151;
    f.ice_controlling = 0x0123456789abcdefULL;
    const std::string pwd = "0123456789abcdefghijkl";
    const Bytes req = build_binding_request(f, pwd);
    StunMessage m;
    ASSERT_EQ(parse_binding_request(req, m), StunError::kNone);
    EXPECT_EQ(m.username, f.username);
    EXPECT_EQ(m.priority, f.priority);
    EXPECT_EQ(m.ice_controlling, f.ice_controlling);
    EXPECT_TRUE(m.use_candidate);
    EXPECT_TRUE(integrity_valid(req, m, pwd));
    EXPECT_FALSE(integrity_valid(req, m, kPassword));
}

// Any one byte changed after the header's type is caught: by the cookie,
// the length, the structure, the fingerprint or the integrity.
TEST(Stun, EveryTamperedByteIsRefused) {
    for (std::size_t i = 2; i < kSampleRequest.size(); ++i) {
        Bytes bad = kSampleRequest;
        bad[i] ^= 0x40;
        StunMessage m;
        const StunError e = parse_binding_request(bad, m);
        const bool refused = e != StunError::kNone || !integrity_valid(bad, m, kPassword);
        EXPECT_TRUE(refused) << "byte " << i;
    }
}

TEST(Stun, TruncationAndStructureErrors) {
    StunMessage m;
    for (std::size_t n = 0; n < kSampleRequest.size(); ++n) {
        const Bytes cut(kSampleRequest.begin(), kSampleRequest.begin() + static_cast<std::ptrdiff_t>(n));
        EXPECT_NE(parse_stun(cut, m), StunError::kNone) << n;
    }
    Bytes dtls = kSampleRequest;
    dtls[0] = 22;  // a DTLS handshake record
    EXPECT_FALSE(is_stun(dtls));
    EXPECT_EQ(parse_stun(dtls, m), StunError::kNotStun);
    // The length field says 4 bytes fewer than the datagram has.
    Bytes longer = kSampleRequest;
    longer.insert(longer.end(), {0, 0, 0, 0});
    EXPECT_EQ(parse_stun(longer, m), StunError::kLengthMismatch);
    // An attribute after FINGERPRINT (length field fixed up).
    longer[3] = static_cast<std::uint8_t>(longer.size() - 20);
    longer[longer.size() - 4] = 0x80;  // type 0x8000, empty: comprehension-optional
    EXPECT_EQ(parse_stun(longer, m), StunError::kAfterFingerprint);
    // No integrity, no fingerprint.
    BindingRequestFields f;
    f.username = "a:b";
    Bytes req = build_binding_request(f, kPassword);
    Bytes no_fp(req.begin(), req.end() - 8);
    no_fp[3] = static_cast<std::uint8_t>(no_fp.size() - 20);
    EXPECT_EQ(parse_binding_request(no_fp, m), StunError::kNoFingerprint);
    Bytes no_mi(req.begin(), req.end() - 32);
    no_mi[3] = static_cast<std::uint8_t>(no_mi.size() - 20);
    EXPECT_EQ(parse_binding_request(no_mi, m), StunError::kNoIntegrity);
}

TEST(Stun, UnknownRequiredAttributeAndOversizedUsername) {
    Bytes m = {0x00, 0x01, 0x00, 0x04, 0x21, 0x12, 0xa4, 0x42, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 0x7f, 0x00, 0x00, 0x00};
    StunMessage out;
    EXPECT_EQ(parse_stun(m, out), StunError::kUnknownRequiredAttribute);
    m[20] = 0xc0;  // 0xc000: comprehension-optional, skipped
    EXPECT_EQ(parse_stun(m, out), StunError::kNone);
    BindingRequestFields f;
    f.username = std::string(kStunMaxUsernameBytes, 'u');
    EXPECT_EQ(parse_binding_request(build_binding_request(f, kPassword), out), StunError::kNone);
    Bytes big = build_binding_request(f, kPassword);
    // USERNAME's length field + 3 (same padded size): 516 bytes is too long.
    big[22] = 0x02;
    big[23] = 0x04;
    EXPECT_EQ(parse_stun(big, out), StunError::kUsernameTooLong);
    std::string_view a, b;
    EXPECT_FALSE(split_ice_username("nocolon", a, b));
    EXPECT_FALSE(split_ice_username(":x", a, b));
    EXPECT_FALSE(split_ice_username("x:", a, b));
}
