// The SDP offer reader against real Chromium offers (fixtures/: Chromium
// 156's createOffer() for a data channel, before and after gathering), each
// refusal with its own error, and the answer written byte for byte.
#include "jetrace/webrtc/sdp.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

using namespace jetrace::webrtc;

namespace {

std::string fixture(const char* name) {
    std::ifstream in(std::string(JETRACE_WEBRTC_FIXTURES) + "/" + name, std::ios::binary);
    EXPECT_TRUE(in.good()) << name;
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `text` with the first occurrence of `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

SdpError parse(const std::string& text, std::size_t* line = nullptr) {
    SdpOffer offer;
    return parse_offer(text, offer, line);
}

// A counter as the random source: deterministic credentials.
RandomSource counting() {
    return [n = std::uint8_t{0}](std::span<std::uint8_t> out) mutable {
        for (auto& b : out) b = n++;
    };
}

constexpr Sha256Fingerprint kChromiumFingerprint = {0x92, 0x6D, 0xE6, 0x75, 0x02, 0x92, 0xDF, 0x6A, 0xC9, 0xD1, 0xCB,
                                                     0x7C, 0x66, 0x21, 0xC2, 0x56, 0xF1, 0x87, 0x6E, 0xD3, 0xC4, 0xA6,
                                                     0x0E, 0x29, 0xEA, 0x8A, 0xD5, 0x93, 0xF1, 0xAC, 0xEF, 0x02};

}  // namespace

TEST(Sdp, ChromiumOfferAfterGathering) {
    SdpOffer o;
    ASSERT_EQ(parse_offer(fixture("chromium156_offer_gathered.sdp"), o), SdpError::kNone);
    EXPECT_EQ(o.ice_ufrag, "rhrA");
    EXPECT_EQ(o.ice_pwd, "2XoTQfLVQahAf71IWq0kd5Hy");
    EXPECT_EQ(o.fingerprint, kChromiumFingerprint);
    EXPECT_EQ(o.setup, SdpSetup::kActpass);
    EXPECT_EQ(o.mid, "0");
    EXPECT_EQ(o.sctp_port, 5000);
    EXPECT_EQ(o.max_message_size, 262144u);
}

TEST(Sdp, ChromiumOfferBeforeGatheringAndWithLfEndings) {
    const std::string text = fixture("chromium156_offer.sdp");
    SdpOffer o;
    ASSERT_EQ(parse_offer(text, o), SdpError::kNone);
    EXPECT_EQ(o.ice_ufrag, "irHV");
    EXPECT_EQ(o.ice_pwd, "nW+J2pQgPoNZLDVrkJAdQv+S");
    EXPECT_EQ(fingerprint_text(o.fingerprint),
              "54:60:4D:5B:BB:BD:F4:EB:21:3D:06:CE:F5:99:59:CC:8C:19:92:A8:97:56:8A:DA:D6:CC:3F:87:81:44:68:79");
    std::string lf;
    for (const char c : text)
        if (c != '\r') lf.push_back(c);
    SdpOffer o2;
    ASSERT_EQ(parse_offer(lf, o2), SdpError::kNone);
    EXPECT_EQ(o2.fingerprint, o.fingerprint);
}

// Firefox's layout: fingerprint at the session level, credentials in the section.
TEST(Sdp, SessionLevelAttributesApply) {
    std::string text = fixture("chromium156_offer_gathered.sdp");
    const std::string fp_line =
        "a=fingerprint:sha-256 92:6D:E6:75:02:92:DF:6A:C9:D1:CB:7C:66:21:C2:56:F1:87:6E:D3:C4:A6:0E:29:EA:8A:D5:93:F1:AC:EF:02\r\n";
    text = replaced(text, fp_line, "");
    text = replaced(text, "t=0 0\r\n", "t=0 0\r\n" + fp_line + "a=fingerprint:sha-1 00:11\r\n");
    SdpOffer o;
    ASSERT_EQ(parse_offer(text, o), SdpError::kNone);
    EXPECT_EQ(o.fingerprint, kChromiumFingerprint);
    // Lower-case hex and hash name are the same fingerprint.
    ASSERT_EQ(parse_offer(replaced(text, "sha-256 92:6D:E6", "SHA-256 92:6d:e6"), o), SdpError::kNone);
    EXPECT_EQ(o.fingerprint, kChromiumFingerprint);
}

TEST(Sdp, RefusalsEachHaveTheirError) {
    const std::string good = fixture("chromium156_offer_gathered.sdp");
    const std::string fp = "a=fingerprint:sha-256 92:6D:E6:75:02:92:DF:6A:C9:D1:CB:7C:66:21:C2:56:F1:87:6E:D3:C4:A6:0E:29:EA:8A:D5:93:F1:AC:EF:02";
    const std::string m = "m=application 9 UDP/DTLS/SCTP webrtc-datachannel";
    EXPECT_EQ(parse(good + std::string(kMaxOfferBytes, 'x')), SdpError::kTooLarge);
    EXPECT_EQ(parse(""), SdpError::kMalformedLine);
    EXPECT_EQ(parse(replaced(good, "v=0", "v=1")), SdpError::kMalformedLine);
    EXPECT_EQ(parse(replaced(good, "s=-", "s -")), SdpError::kMalformedLine);
    EXPECT_EQ(parse(replaced(good, "s=-", std::string("s=\0-", 4))), SdpError::kMalformedLine);
    EXPECT_EQ(parse(replaced(good, "t=0 0\r\n", "t=0 0\r\n\r\n")), SdpError::kMalformedLine);
    EXPECT_EQ(parse(replaced(good, fp + "\r\n", "")), SdpError::kNoFingerprint);
    EXPECT_EQ(parse(replaced(good, fp, fp.substr(0, fp.size() - 3))), SdpError::kBadFingerprint);
    EXPECT_EQ(parse(replaced(good, "EF:02", "EF:0G")), SdpError::kBadFingerprint);
    EXPECT_EQ(parse(replaced(good, "EF:02", "EF-02")), SdpError::kBadFingerprint);
    EXPECT_EQ(parse(replaced(good, m + "\r\n", "")), SdpError::kNoDataChannel);
    EXPECT_EQ(parse(replaced(good, m, "m=application 9 DTLS/SCTP 5000")), SdpError::kUnsupportedMedia);
    EXPECT_EQ(parse(good + "m=audio 9 UDP/TLS/RTP/SAVPF 111\r\n"), SdpError::kUnsupportedMedia);
    EXPECT_EQ(parse(good + m + "\r\n"), SdpError::kUnsupportedMedia);
    EXPECT_EQ(parse(replaced(good, m, "m=application x UDP/DTLS/SCTP webrtc-datachannel")), SdpError::kMalformedLine);
    EXPECT_EQ(parse(replaced(good, "a=ice-ufrag:rhrA\r\n", "")), SdpError::kNoIceCredentials);
    EXPECT_EQ(parse(replaced(good, "a=ice-pwd:2XoTQfLVQahAf71IWq0kd5Hy\r\n", "")), SdpError::kNoIceCredentials);
    EXPECT_EQ(parse(replaced(good, "ice-ufrag:rhrA", "ice-ufrag:rhr")), SdpError::kBadIceUfrag);
    EXPECT_EQ(parse(replaced(good, "ice-ufrag:rhrA", "ice-ufrag:rh-A")), SdpError::kBadIceUfrag);
    EXPECT_EQ(parse(replaced(good, "ice-ufrag:rhrA", "ice-ufrag:" + std::string(257, 'a'))), SdpError::kBadIceUfrag);
    EXPECT_EQ(parse(replaced(good, "ice-pwd:2XoTQfLVQahAf71IWq0kd5Hy", "ice-pwd:2XoTQfLVQahAf71IWq0kd")), SdpError::kBadIcePwd);
    EXPECT_EQ(parse(replaced(good, "ice-pwd:2XoTQ", "ice-pwd:2X\"TQ")), SdpError::kBadIcePwd);
    EXPECT_EQ(parse(replaced(good, "a=ice-ufrag:rhrA", "a=ice-ufrag:rhrA\r\na=ice-ufrag:abcd")), SdpError::kDuplicateAttribute);
    EXPECT_EQ(parse(replaced(good, fp, fp + "\r\n" + fp)), SdpError::kDuplicateAttribute);
    EXPECT_EQ(parse(replaced(good, "setup:actpass", "setup:passive")), SdpError::kBadSetup);
    EXPECT_EQ(parse(replaced(good, "setup:actpass", "setup:holdconn")), SdpError::kBadSetup);
    EXPECT_EQ(parse(replaced(good, "a=mid:0", "a=mid:")), SdpError::kBadMid);
    EXPECT_EQ(parse(replaced(good, "a=mid:0", "a=mid:0 1")), SdpError::kBadMid);
    EXPECT_EQ(parse(replaced(good, "a=mid:0", "a=mid:" + std::string(kMaxMidChars + 1, 'm'))), SdpError::kBadMid);
    EXPECT_EQ(parse(replaced(good, "sctp-port:5000", "sctp-port:0")), SdpError::kBadSctpPort);
    EXPECT_EQ(parse(replaced(good, "sctp-port:5000", "sctp-port:65536")), SdpError::kBadSctpPort);
    EXPECT_EQ(parse(replaced(good, "max-message-size:262144", "max-message-size:4294967296")), SdpError::kBadMaxMessageSize);
    EXPECT_EQ(parse(replaced(good, "max-message-size:262144", "max-message-size:-1")), SdpError::kBadMaxMessageSize);
}

TEST(Sdp, ErrorLineNamesTheLine) {
    const std::string good = fixture("chromium156_offer_gathered.sdp");
    std::size_t line = 99;
    EXPECT_EQ(parse(replaced(good, "setup:actpass", "setup:passive"), &line), SdpError::kBadSetup);
    EXPECT_EQ(line, 16u);  // v o s t group extmap msid m c candidate candidate ufrag pwd options fingerprint, setup
    EXPECT_EQ(parse(good, &line), SdpError::kNone);
    EXPECT_EQ(line, 0u);
    EXPECT_EQ(to_string(SdpError::kNoFingerprint), "no sha-256 fingerprint");
}

TEST(Sdp, IceCredentialsFromTheRandomSource) {
    const IceCredentials a = make_ice_credentials(counting());
    EXPECT_EQ(a.ufrag, "ABCDEFGH");
    EXPECT_EQ(a.pwd, "IJKLMNOPQRSTUVWXYZabcdef");
    const IceCredentials b = make_ice_credentials([](std::span<std::uint8_t> out) {
        for (auto& v : out) v = 0xFF;  // the last of the 64 ice-chars
    });
    EXPECT_EQ(b.ufrag, "////////");
    EXPECT_EQ(b.pwd.size(), 24u);
}

TEST(Sdp, AnswerToChromiumOffer) {
    SdpOffer o;
    ASSERT_EQ(parse_offer(fixture("chromium156_offer_gathered.sdp"), o), SdpError::kNone);
    AnswerSettings s;
    s.ice = make_ice_credentials(counting());
    for (std::size_t i = 0; i < s.fingerprint.size(); ++i) s.fingerprint[i] = static_cast<std::uint8_t>(i * 8);
    s.candidate_ip = "192.0.2.7";
    s.candidate_port = 7779;
    s.session_id = 4242;
    const std::string expected =
        "v=0\r\no=- 4242 2 IN IP4 127.0.0.1\r\ns=-\r\nt=0 0\r\na=ice-lite\r\na=group:BUNDLE 0\r\n"
        "m=application 7779 UDP/DTLS/SCTP webrtc-datachannel\r\nc=IN IP4 192.0.2.7\r\na=mid:0\r\n"
        "a=ice-ufrag:ABCDEFGH\r\na=ice-pwd:IJKLMNOPQRSTUVWXYZabcdef\r\n"
        "a=fingerprint:sha-256 00:08:10:18:20:28:30:38:40:48:50:58:60:68:70:78:80:88:90:98:A0:A8:B0:B8:C0:C8:D0:D8:E0:E8:F0:F8\r\n"
        "a=setup:passive\r\na=sctp-port:5000\r\na=max-message-size:16384\r\n"
        "a=candidate:1 1 UDP 2130706431 192.0.2.7 7779 typ host\r\na=end-of-candidates\r\n";
    EXPECT_EQ(write_answer(o, s), expected);
    // IPv6, and an offer without a mid: no BUNDLE group, no a=mid.
    s.candidate_ip = "2001:db8::7";
    o.mid.clear();
    const std::string v6 = write_answer(o, s);
    EXPECT_NE(v6.find("c=IN IP6 2001:db8::7\r\n"), std::string::npos);
    EXPECT_NE(v6.find("a=candidate:1 1 UDP 2130706431 2001:db8::7 7779 typ host\r\n"), std::string::npos);
    EXPECT_EQ(v6.find("BUNDLE"), std::string::npos);
    EXPECT_EQ(v6.find("a=mid"), std::string::npos);
}
