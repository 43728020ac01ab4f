// The SDP of the data-channel signalling (RFC 8866, RFC 8839 ICE, RFC 8122
// fingerprints, RFC 8841 SCTP): the browser's offer, which must carry
// exactly one data-channel section (m=application ... UDP/DTLS/SCTP
// webrtc-datachannel) and nothing else, and the server's answer: ICE-lite,
// DTLS passive, one host candidate. The offer is untrusted text: every
// refusal is a distinct SdpError. Fuzzed by fuzz/fuzz_sdp_offer.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>

namespace jetrace::webrtc {

/// The largest offer read (unit: bytes). Chromium's is about 500.
inline constexpr std::size_t kMaxOfferBytes = 16 * 1024;
/// RFC 8839 section 5.4: ice-ufrag 4..256 ice-chars, ice-pwd 22..256.
inline constexpr std::size_t kMinUfragChars = 4;
inline constexpr std::size_t kMinPwdChars = 22;
inline constexpr std::size_t kMaxIceCredentialChars = 256;
/// The longest a=mid value read and echoed in the answer (unit: chars).
inline constexpr std::size_t kMaxMidChars = 32;

using Sha256Fingerprint = std::array<std::uint8_t, 32>;

/// a=setup (RFC 4145): the offerer's DTLS role.
enum class SdpSetup : std::uint8_t { kActpass, kActive, kPassive };

struct SdpOffer {
    std::string ice_ufrag;
    std::string ice_pwd;
    Sha256Fingerprint fingerprint{};  ///< of the browser's DTLS certificate
    SdpSetup setup = SdpSetup::kActpass;
    std::string mid;                ///< "" if the section has no a=mid
    std::uint16_t sctp_port = 5000;  ///< a=sctp-port
    /// a=max-message-size (unit: bytes); RFC 8841 section 6: 64 KiB when
    /// absent, 0 for "any size".
    std::uint32_t max_message_size = 65536;
};

enum class SdpError : std::uint8_t {
    kNone = 0,
    kTooLarge,             ///< more than kMaxOfferBytes
    kMalformedLine,        ///< not "x=value", a control character, or no v=0 first
    kUnsupportedMedia,     ///< an m= section that is not the one data channel (audio, video, a second one)
    kNoDataChannel,        ///< no m=application ... UDP/DTLS/SCTP webrtc-datachannel
    kDuplicateAttribute,   ///< ice-ufrag, ice-pwd, a sha-256 fingerprint, setup, mid, sctp-port twice at one level
    kNoIceCredentials,     ///< no a=ice-ufrag or no a=ice-pwd
    kBadIceUfrag,          ///< not 4..256 ice-chars
    kBadIcePwd,            ///< not 22..256 ice-chars
    kNoFingerprint,        ///< no a=fingerprint:sha-256
    kBadFingerprint,       ///< not 32 colon-separated hex bytes
    kBadSetup,             ///< not actpass or active (this server is always the DTLS server)
    kBadMid,               ///< empty, too long, or not token characters
    kBadSctpPort,          ///< not 1..65535
    kBadMaxMessageSize,    ///< not a decimal number below 2^32
};

/// A short name of the error, for logs and HTTP error bodies ("no fingerprint").
std::string_view to_string(SdpError error);

/// Reads the browser's offer. Lines end in CRLF or LF. Session-level
/// ice-ufrag, ice-pwd, fingerprint and setup apply where the section has
/// none. Other lines (candidates, ice-options, BUNDLE) are ignored.
/// `error_line`, if given, gets the 1-based line of a line-specific error.
SdpError parse_offer(std::string_view text, SdpOffer& out, std::size_t* error_line = nullptr);

/// Bytes as SDP's fingerprint text: "AB:CD:...", upper-case hex.
std::string fingerprint_text(std::span<const std::uint8_t> digest);

/// Random bytes for the server's credentials and session id (the caller
/// chooses the source: RAND_bytes in the server, a fixed one in tests).
using RandomSource = std::function<void(std::span<std::uint8_t>)>;

struct IceCredentials {
    std::string ufrag;  ///< 8 ice-chars
    std::string pwd;    ///< 24 ice-chars
};

/// Fresh server credentials: 8 and 24 ice-chars (48 and 144 bits) from `random`.
IceCredentials make_ice_credentials(const RandomSource& random);

struct AnswerSettings {
    IceCredentials ice;
    Sha256Fingerprint fingerprint{};  ///< of the server's DTLS certificate
    std::string candidate_ip;          ///< the host candidate: an IPv4 or IPv6 literal
    std::uint16_t candidate_port = 0;  ///< the WebRTC UDP port
    std::uint16_t sctp_port = 5000;
    /// The largest message the browser may send (unit: bytes).
    std::uint32_t max_message_size = 16 * 1024;
    std::uint64_t session_id = 1;  ///< o= line; any number below 2^63
};

/// The answer to `offer` (which parse_offer() accepted): a=ice-lite, the
/// server's credentials and fingerprint, a=setup:passive, the offer's mid,
/// one host candidate and a=end-of-candidates. CRLF line ends. Asserts the
/// settings are well formed (credentials from make_ice_credentials(), an IP
/// literal, a port).
std::string write_answer(const SdpOffer& offer, const AnswerSettings& settings);

}  // namespace jetrace::webrtc
