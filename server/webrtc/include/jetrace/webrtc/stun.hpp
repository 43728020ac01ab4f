// STUN (RFC 8489) as an ICE-lite server needs it (RFC 8445 section 2.5):
// read a browser's connectivity check (a Binding request with USERNAME,
// MESSAGE-INTEGRITY and FINGERPRINT), and answer it with a Binding success
// response carrying XOR-MAPPED-ADDRESS, MESSAGE-INTEGRITY and FINGERPRINT.
// Every reader takes untrusted bytes: it never reads out of bounds and says
// what is wrong with a StunError. Fuzzed by fuzz/fuzz_stun.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace jetrace::webrtc {

inline constexpr std::uint32_t kStunMagicCookie = 0x2112A442;
/// Message type, message length, magic cookie, transaction id (unit: bytes).
inline constexpr std::size_t kStunHeaderBytes = 20;
/// RFC 8489 section 14.3: USERNAME is shorter than 514 bytes.
inline constexpr std::size_t kStunMaxUsernameBytes = 513;

inline constexpr std::uint16_t kStunBindingRequest = 0x0001;
inline constexpr std::uint16_t kStunBindingSuccess = 0x0101;

// The attributes read or written here (RFC 8489 section 18.3, RFC 8445 section 16.1).
inline constexpr std::uint16_t kStunAttrMappedAddress = 0x0001;
inline constexpr std::uint16_t kStunAttrUsername = 0x0006;
inline constexpr std::uint16_t kStunAttrMessageIntegrity = 0x0008;
inline constexpr std::uint16_t kStunAttrXorMappedAddress = 0x0020;
inline constexpr std::uint16_t kStunAttrPriority = 0x0024;
inline constexpr std::uint16_t kStunAttrUseCandidate = 0x0025;
inline constexpr std::uint16_t kStunAttrSoftware = 0x8022;
inline constexpr std::uint16_t kStunAttrFingerprint = 0x8028;
inline constexpr std::uint16_t kStunAttrIceControlled = 0x8029;
inline constexpr std::uint16_t kStunAttrIceControlling = 0x802A;

using StunTransactionId = std::array<std::uint8_t, 12>;

enum class StunError : std::uint8_t {
    kNone = 0,
    kNotStun,                   ///< is_stun() is false: short, first bits, cookie or length not a multiple of 4
    kLengthMismatch,            ///< the header's length is not the datagram's
    kTruncatedAttribute,        ///< an attribute runs past the end of the message
    kBadAttribute,              ///< a known attribute's value has the wrong size or content
    kUnknownRequiredAttribute,  ///< a comprehension-required attribute (type < 0x8000) not known here
    kAfterFingerprint,          ///< an attribute after FINGERPRINT, which must be the last
    kBadFingerprint,            ///< FINGERPRINT is not the CRC-32 of the message
    kNotBindingRequest,         ///< a STUN message, but no Binding request
    kNoUsername,
    kUsernameTooLong,
    kNoIntegrity,
    kNoFingerprint,
    kBadIntegrity,  ///< MESSAGE-INTEGRITY is not the HMAC of the message with the key
};

/// A short name of the error, for logs ("bad fingerprint").
std::string_view to_string(StunError error);

/// A transport address (XOR-MAPPED-ADDRESS): IPv4 in ip[0..4), or IPv6.
struct StunAddress {
    bool ipv6 = false;
    std::array<std::uint8_t, 16> ip{};
    std::uint16_t port = 0;

    static StunAddress v4(std::array<std::uint8_t, 4> ip4, std::uint16_t port);
    static StunAddress v6(const std::array<std::uint8_t, 16>& ip6, std::uint16_t port);
    bool operator==(const StunAddress&) const = default;
};

/// What parse_stun() read. Attributes after MESSAGE-INTEGRITY other than
/// FINGERPRINT are ignored, as RFC 8489 section 14.5 says.
struct StunMessage {
    std::uint16_t type = 0;  ///< method and class: kStunBindingRequest, kStunBindingSuccess...
    StunTransactionId transaction_id{};
    std::optional<std::string> username;
    std::optional<std::uint32_t> priority;
    bool use_candidate = false;
    std::optional<std::uint64_t> ice_controlling;  ///< tie-breaker
    std::optional<std::uint64_t> ice_controlled;   ///< tie-breaker
    std::optional<StunAddress> xor_mapped_address;
    std::optional<std::string> software;
    /// Where MESSAGE-INTEGRITY starts in the message (unit: bytes), if present.
    std::optional<std::size_t> integrity_offset;
    /// FINGERPRINT was present (and parse_stun() found it right).
    bool has_fingerprint = false;
};

/// RFC 7983's demultiplexing test for a datagram on the shared UDP port:
/// first byte 0..3, at least a header, the magic cookie, a length that is a
/// multiple of 4. False for DTLS (first byte 20..63) and anything else.
bool is_stun(std::span<const std::uint8_t> datagram);

/// Reads a STUN message's structure and, if present, checks its FINGERPRINT.
/// MESSAGE-INTEGRITY needs the key: integrity_valid().
StunError parse_stun(std::span<const std::uint8_t> bytes, StunMessage& out);

/// parse_stun(), then what an ICE connectivity check must have: a Binding
/// request with USERNAME, MESSAGE-INTEGRITY and FINGERPRINT (RFC 8445 section 7.2.2).
StunError parse_binding_request(std::span<const std::uint8_t> bytes, StunMessage& out);

/// True if `message` (parsed into `parsed` from these bytes) has a
/// MESSAGE-INTEGRITY that is HMAC-SHA1 with `key` (ICE: the receiver's
/// ice-pwd) over the message up to it, its length field counting up to the
/// end of MESSAGE-INTEGRITY. Compared in constant time; false for an empty key.
bool integrity_valid(std::span<const std::uint8_t> message, const StunMessage& parsed, std::string_view key);

/// ICE's USERNAME "receiver-ufrag:sender-ufrag" split at its first colon;
/// false if there is none or either side is empty.
bool split_ice_username(std::string_view username, std::string_view& receiver_ufrag, std::string_view& sender_ufrag);

/// Appends MESSAGE-INTEGRITY (HMAC-SHA1 with `key`, not empty: asserted)
/// and FINGERPRINT to a complete message (header and attributes) and sets
/// its length field.
void append_integrity_and_fingerprint(std::vector<std::uint8_t>& message, std::string_view key);

/// A Binding success response to the request `transaction_id`: SOFTWARE if
/// not empty, XOR-MAPPED-ADDRESS `mapped` (where the request came from),
/// MESSAGE-INTEGRITY with `key` (the server's ice-pwd), FINGERPRINT.
std::vector<std::uint8_t> build_binding_success(const StunTransactionId& transaction_id, const StunAddress& mapped,
                                                std::string_view key, std::string_view software = {});

/// What a browser sends: a connectivity check from the controlling agent.
struct BindingRequestFields {
    StunTransactionId transaction_id{};
    std::string username;  ///< "receiver-ufrag:sender-ufrag"
    std::uint32_t priority = 0;
    std::uint64_t ice_controlling = 0;  ///< tie-breaker
    bool use_candidate = true;
};

/// A Binding request as a browser sends it (USERNAME, PRIORITY,
/// ICE-CONTROLLING, USE-CANDIDATE, MESSAGE-INTEGRITY with `key`, the
/// receiver's ice-pwd, and FINGERPRINT): for tests and seed corpora.
std::vector<std::uint8_t> build_binding_request(const BindingRequestFields& fields, std::string_view key);

}  // namespace jetrace::webrtc
