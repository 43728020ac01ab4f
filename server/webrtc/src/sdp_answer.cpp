// Writing the server's SDP answer (ICE-lite, DTLS passive, one host
// candidate), its credentials, and the names of the offer's errors.
#include "jetrace/webrtc/sdp.hpp"

#include "sdp_text.hpp"

#include <arpa/inet.h>

#include <array>
#include <cassert>

namespace jetrace::webrtc {

namespace {

constexpr std::string_view kIceAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
constexpr std::size_t kUfragChars = 8;
constexpr std::size_t kPwdChars = 24;
/// RFC 8445 section 5.1.2.1 with type preference 126 (host), local 65535, component 1.
constexpr std::uint32_t kHostPriority = 2130706431;

std::string random_ice_chars(const RandomSource& random, std::size_t n) {
    std::vector<std::uint8_t> bytes(n);
    random(bytes);
    std::string s;
    s.reserve(n);
    // 64 characters: the low 6 bits of a uniform byte pick one uniformly.
    for (const std::uint8_t b : bytes) s.push_back(kIceAlphabet[b & 63]);
    return s;
}

bool is_ipv6_literal(const std::string& ip) {
    std::array<unsigned char, 16> buf{};
    return inet_pton(AF_INET6, ip.c_str(), buf.data()) == 1;
}

bool is_ipv4_literal(const std::string& ip) {
    std::array<unsigned char, 4> buf{};
    return inet_pton(AF_INET, ip.c_str(), buf.data()) == 1;
}

}  // namespace

std::string fingerprint_text(std::span<const std::uint8_t> digest) {
    constexpr std::string_view kHex = "0123456789ABCDEF";
    std::string s;
    for (std::size_t i = 0; i < digest.size(); ++i) {
        if (i > 0) s.push_back(':');
        s.push_back(kHex[digest[i] >> 4]);
        s.push_back(kHex[digest[i] & 15]);
    }
    return s;
}

IceCredentials make_ice_credentials(const RandomSource& random) {
    IceCredentials c;
    c.ufrag = random_ice_chars(random, kUfragChars);
    c.pwd = random_ice_chars(random, kPwdChars);
    return c;
}

std::string write_answer(const SdpOffer& offer, const AnswerSettings& s) {
    assert(detail::ice_chars(s.ice.ufrag, kMinUfragChars, kMaxIceCredentialChars));
    assert(detail::ice_chars(s.ice.pwd, kMinPwdChars, kMaxIceCredentialChars));
    const bool ipv6 = is_ipv6_literal(s.candidate_ip);
    [[maybe_unused]] const bool ip_literal = ipv6 || is_ipv4_literal(s.candidate_ip);
    assert(ip_literal);
    assert(s.candidate_port != 0 && s.sctp_port != 0 && s.session_id < (std::uint64_t{1} << 63));
    const std::string port = std::to_string(s.candidate_port);
    std::string a;
    a.reserve(768);
    const auto line = [&a](std::string_view text) {
        a += text;
        a += "\r\n";
    };
    line("v=0");
    line("o=- " + std::to_string(s.session_id) + " 2 IN IP4 127.0.0.1");
    line("s=-");
    line("t=0 0");
    line("a=ice-lite");
    if (!offer.mid.empty()) line("a=group:BUNDLE " + offer.mid);
    line("m=application " + port + " UDP/DTLS/SCTP webrtc-datachannel");
    line(std::string(ipv6 ? "c=IN IP6 " : "c=IN IP4 ") + s.candidate_ip);
    if (!offer.mid.empty()) line("a=mid:" + offer.mid);
    line("a=ice-ufrag:" + s.ice.ufrag);
    line("a=ice-pwd:" + s.ice.pwd);
    line("a=fingerprint:sha-256 " + fingerprint_text(s.fingerprint));
    line("a=setup:passive");
    line("a=sctp-port:" + std::to_string(s.sctp_port));
    line("a=max-message-size:" + std::to_string(s.max_message_size));
    line("a=candidate:1 1 UDP " + std::to_string(kHostPriority) + " " + s.candidate_ip + " " + port + " typ host");
    line("a=end-of-candidates");
    return a;
}

std::string_view to_string(SdpError error) {
    switch (error) {
        case SdpError::kNone: return "ok";
        case SdpError::kTooLarge: return "offer too large";
        case SdpError::kMalformedLine: return "malformed line";
        case SdpError::kUnsupportedMedia: return "unsupported media section";
        case SdpError::kNoDataChannel: return "no data channel section";
        case SdpError::kDuplicateAttribute: return "duplicate attribute";
        case SdpError::kNoIceCredentials: return "no ICE credentials";
        case SdpError::kBadIceUfrag: return "bad ice-ufrag";
        case SdpError::kBadIcePwd: return "bad ice-pwd";
        case SdpError::kNoFingerprint: return "no sha-256 fingerprint";
        case SdpError::kBadFingerprint: return "bad fingerprint";
        case SdpError::kBadSetup: return "bad setup role";
        case SdpError::kBadMid: return "bad mid";
        case SdpError::kBadSctpPort: return "bad sctp-port";
        case SdpError::kBadMaxMessageSize: return "bad max-message-size";
    }
    return "unknown SDP error";
}

}  // namespace jetrace::webrtc
