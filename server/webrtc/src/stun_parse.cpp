// Reading STUN messages (RFC 8489): the header, the attributes this server
// needs, FINGERPRINT and MESSAGE-INTEGRITY.
#include "jetrace/webrtc/stun.hpp"

#include "byte_io.hpp"
#include "stun_hash.hpp"

#include <openssl/crypto.h>

namespace jetrace::webrtc {

using detail::load_u16;
using detail::load_u32;
using detail::load_u64;

namespace {

constexpr std::size_t kAttrHeaderBytes = 4;
constexpr std::size_t kIntegrityBytes = 20;
constexpr std::size_t kFingerprintBytes = 4;

std::size_t padded(std::size_t n) { return (n + 3) & ~std::size_t{3}; }

// Comprehension-required attributes (type < 0x8000) a Binding message may
// carry that this server reads or may skip (RFC 8489 section 18.3, RFC 8445).
bool known_required(std::uint16_t type) {
    switch (type) {
        case kStunAttrMappedAddress:
        case kStunAttrUsername:
        case kStunAttrMessageIntegrity:
        case 0x0009:  // ERROR-CODE
        case 0x000A:  // UNKNOWN-ATTRIBUTES
        case 0x0014:  // REALM
        case 0x0015:  // NONCE
        case 0x001C:  // MESSAGE-INTEGRITY-SHA256
        case 0x001D:  // PASSWORD-ALGORITHM
        case 0x001E:  // USERHASH
        case kStunAttrXorMappedAddress:
        case kStunAttrPriority:
        case kStunAttrUseCandidate:
            return true;
        default:
            return false;
    }
}

StunError read_xor_address(std::span<const std::uint8_t> v, const StunTransactionId& tid, StunAddress& out) {
    if (v.size() < 4) return StunError::kBadAttribute;
    const std::uint8_t family = v[1];
    const std::size_t ip_bytes = family == 0x01 ? 4 : family == 0x02 ? 16 : 0;
    if (ip_bytes == 0 || v.size() != 4 + ip_bytes) return StunError::kBadAttribute;
    out = StunAddress{};
    out.ipv6 = family == 0x02;
    out.port = static_cast<std::uint16_t>(load_u16(v, 2) ^ (kStunMagicCookie >> 16));
    // The address is XORed with the cookie, then (IPv6) the transaction id.
    std::array<std::uint8_t, 16> mask{};
    for (std::size_t i = 0; i < 4; ++i) mask[i] = static_cast<std::uint8_t>(kStunMagicCookie >> (24 - 8 * i));
    for (std::size_t i = 0; i < tid.size(); ++i) mask[4 + i] = tid[i];
    for (std::size_t i = 0; i < ip_bytes; ++i) out.ip[i] = static_cast<std::uint8_t>(v[4 + i] ^ mask[i]);
    return StunError::kNone;
}

// One attribute before MESSAGE-INTEGRITY.
StunError read_attribute(std::uint16_t type, std::span<const std::uint8_t> v, StunMessage& out) {
    switch (type) {
        case kStunAttrUsername:
            if (v.size() > kStunMaxUsernameBytes) return StunError::kUsernameTooLong;
            out.username.emplace(v.begin(), v.end());
            return StunError::kNone;
        case kStunAttrSoftware:
            out.software.emplace(v.begin(), v.end());
            return StunError::kNone;
        case kStunAttrPriority:
            if (v.size() != 4) return StunError::kBadAttribute;
            out.priority = load_u32(v, 0);
            return StunError::kNone;
        case kStunAttrUseCandidate:
            if (!v.empty()) return StunError::kBadAttribute;
            out.use_candidate = true;
            return StunError::kNone;
        case kStunAttrIceControlling:
        case kStunAttrIceControlled:
            if (v.size() != 8) return StunError::kBadAttribute;
            (type == kStunAttrIceControlling ? out.ice_controlling : out.ice_controlled) = load_u64(v, 0);
            return StunError::kNone;
        case kStunAttrXorMappedAddress: {
            StunAddress a;
            const StunError e = read_xor_address(v, out.transaction_id, a);
            if (e == StunError::kNone) out.xor_mapped_address = a;
            return e;
        }
        default:
            return type < 0x8000 && !known_required(type) ? StunError::kUnknownRequiredAttribute : StunError::kNone;
    }
}

}  // namespace

bool is_stun(std::span<const std::uint8_t> d) {
    return d.size() >= kStunHeaderBytes && d[0] <= 3 && load_u32(d, 4) == kStunMagicCookie && (load_u16(d, 2) & 3) == 0;
}

StunError parse_stun(std::span<const std::uint8_t> bytes, StunMessage& out) {
    out = StunMessage{};
    if (!is_stun(bytes)) return StunError::kNotStun;
    if (load_u16(bytes, 2) != bytes.size() - kStunHeaderBytes) return StunError::kLengthMismatch;
    out.type = load_u16(bytes, 0);
    for (std::size_t i = 0; i < out.transaction_id.size(); ++i) out.transaction_id[i] = bytes[8 + i];
    std::size_t at = kStunHeaderBytes;
    while (at < bytes.size()) {
        if (out.has_fingerprint) return StunError::kAfterFingerprint;
        if (bytes.size() - at < kAttrHeaderBytes) return StunError::kTruncatedAttribute;
        const std::uint16_t type = load_u16(bytes, at);
        const std::size_t length = load_u16(bytes, at + 2);
        if (bytes.size() - at - kAttrHeaderBytes < padded(length)) return StunError::kTruncatedAttribute;
        const auto value = bytes.subspan(at + kAttrHeaderBytes, length);
        if (type == kStunAttrFingerprint) {
            if (length != kFingerprintBytes) return StunError::kBadAttribute;
            const auto length_field = static_cast<std::uint16_t>(at + kAttrHeaderBytes + kFingerprintBytes - kStunHeaderBytes);
            if (load_u32(value, 0) != detail::stun_fingerprint(bytes.first(at), length_field)) return StunError::kBadFingerprint;
            out.has_fingerprint = true;
        } else if (type == kStunAttrMessageIntegrity && !out.integrity_offset) {
            if (length != kIntegrityBytes) return StunError::kBadAttribute;
            out.integrity_offset = at;
        } else if (!out.integrity_offset) {
            // Attributes after MESSAGE-INTEGRITY, but FINGERPRINT, are ignored.
            const StunError e = read_attribute(type, value, out);
            if (e != StunError::kNone) return e;
        }
        at += kAttrHeaderBytes + padded(length);
    }
    return StunError::kNone;
}

StunError parse_binding_request(std::span<const std::uint8_t> bytes, StunMessage& out) {
    const StunError e = parse_stun(bytes, out);
    if (e != StunError::kNone) return e;
    if (out.type != kStunBindingRequest) return StunError::kNotBindingRequest;
    if (!out.username) return StunError::kNoUsername;
    if (!out.integrity_offset) return StunError::kNoIntegrity;
    if (!out.has_fingerprint) return StunError::kNoFingerprint;
    return StunError::kNone;
}

bool integrity_valid(std::span<const std::uint8_t> message, const StunMessage& parsed, std::string_view key) {
    if (!parsed.integrity_offset) return false;
    const std::size_t at = *parsed.integrity_offset;
    if (at < kStunHeaderBytes || message.size() < at + kAttrHeaderBytes + kIntegrityBytes) return false;
    const auto length_field = static_cast<std::uint16_t>(at + kAttrHeaderBytes + kIntegrityBytes - kStunHeaderBytes);
    const auto mac = detail::stun_hmac_sha1(message.first(at), length_field, key);
    return mac && CRYPTO_memcmp(mac->data(), message.data() + at + kAttrHeaderBytes, mac->size()) == 0;
}

bool split_ice_username(std::string_view username, std::string_view& receiver_ufrag, std::string_view& sender_ufrag) {
    const std::size_t colon = username.find(':');
    if (colon == std::string_view::npos || colon == 0 || colon + 1 == username.size()) return false;
    receiver_ufrag = username.substr(0, colon);
    sender_ufrag = username.substr(colon + 1);
    return true;
}

std::string_view to_string(StunError error) {
    switch (error) {
        case StunError::kNone: return "ok";
        case StunError::kNotStun: return "not STUN";
        case StunError::kLengthMismatch: return "length does not match the datagram";
        case StunError::kTruncatedAttribute: return "truncated attribute";
        case StunError::kBadAttribute: return "bad attribute value";
        case StunError::kUnknownRequiredAttribute: return "unknown comprehension-required attribute";
        case StunError::kAfterFingerprint: return "attribute after FINGERPRINT";
        case StunError::kBadFingerprint: return "bad fingerprint";
        case StunError::kNotBindingRequest: return "not a Binding request";
        case StunError::kNoUsername: return "no USERNAME";
        case StunError::kUsernameTooLong: return "USERNAME too long";
        case StunError::kNoIntegrity: return "no MESSAGE-INTEGRITY";
        case StunError::kNoFingerprint: return "no FINGERPRINT";
        case StunError::kBadIntegrity: return "bad MESSAGE-INTEGRITY";
    }
    return "unknown STUN error";
}

}  // namespace jetrace::webrtc
