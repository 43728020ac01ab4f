// STUN's two checksums over a message prefix whose header length field is
// replaced (RFC 8489 sections 14.5 and 14.7): both count the length up to
// the end of their own attribute, whatever follows it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace jetrace::webrtc::detail {

/// HMAC-SHA1 with `key` over `prefix` (header and attributes before
/// MESSAGE-INTEGRITY), its length field read as `length_field`; nullopt if
/// OpenSSL fails (or the key is empty), which no MESSAGE-INTEGRITY matches.
std::optional<std::array<std::uint8_t, 20>> stun_hmac_sha1(std::span<const std::uint8_t> prefix, std::uint16_t length_field,
                                            std::string_view key);

/// CRC-32 of `prefix` (its length field read as `length_field`) XOR 0x5354554e.
std::uint32_t stun_fingerprint(std::span<const std::uint8_t> prefix, std::uint16_t length_field);

}  // namespace jetrace::webrtc::detail
