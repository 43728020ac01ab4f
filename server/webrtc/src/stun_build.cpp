// Writing STUN messages (RFC 8489): the Binding success response of an
// ICE-lite server, and the browser's Binding request for tests.
#include "jetrace/webrtc/stun.hpp"

#include "byte_io.hpp"
#include "stun_hash.hpp"

#include <cassert>

namespace jetrace::webrtc {

using detail::append_u16;
using detail::append_u32;
using detail::append_u64;

namespace {

std::vector<std::uint8_t> header(std::uint16_t type, const StunTransactionId& tid) {
    std::vector<std::uint8_t> m;
    m.reserve(128);
    append_u16(m, type);
    append_u16(m, 0);  // the length, set when the message is complete
    append_u32(m, kStunMagicCookie);
    m.insert(m.end(), tid.begin(), tid.end());
    return m;
}

// An attribute with its value zero-padded to 4 bytes (RFC 8489 section 14).
void append_attribute(std::vector<std::uint8_t>& m, std::uint16_t type, std::span<const std::uint8_t> value) {
    assert(value.size() <= 0xFFFF);
    append_u16(m, type);
    append_u16(m, static_cast<std::uint16_t>(value.size()));
    m.insert(m.end(), value.begin(), value.end());
    while (m.size() % 4 != 0) m.push_back(0);
}

void append_text(std::vector<std::uint8_t>& m, std::uint16_t type, std::string_view text) {
    append_attribute(m, type, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

void set_length(std::vector<std::uint8_t>& m, std::size_t body_bytes) {
    assert(body_bytes <= 0xFFFF && body_bytes % 4 == 0);
    detail::store_u16(m, 2, static_cast<std::uint16_t>(body_bytes));
}

std::vector<std::uint8_t> xor_address_value(const StunAddress& a, const StunTransactionId& tid) {
    std::vector<std::uint8_t> v;
    v.push_back(0);
    v.push_back(a.ipv6 ? 0x02 : 0x01);
    append_u16(v, static_cast<std::uint16_t>(a.port ^ (kStunMagicCookie >> 16)));
    std::array<std::uint8_t, 16> mask{};
    for (std::size_t i = 0; i < 4; ++i) mask[i] = static_cast<std::uint8_t>(kStunMagicCookie >> (24 - 8 * i));
    for (std::size_t i = 0; i < tid.size(); ++i) mask[4 + i] = tid[i];
    const std::size_t ip_bytes = a.ipv6 ? 16 : 4;
    for (std::size_t i = 0; i < ip_bytes; ++i) v.push_back(static_cast<std::uint8_t>(a.ip[i] ^ mask[i]));
    return v;
}

}  // namespace

StunAddress StunAddress::v4(std::array<std::uint8_t, 4> ip4, std::uint16_t port) {
    StunAddress a;
    for (std::size_t i = 0; i < ip4.size(); ++i) a.ip[i] = ip4[i];
    a.port = port;
    return a;
}

StunAddress StunAddress::v6(const std::array<std::uint8_t, 16>& ip6, std::uint16_t port) {
    StunAddress a;
    a.ipv6 = true;
    a.ip = ip6;
    a.port = port;
    return a;
}

void append_integrity_and_fingerprint(std::vector<std::uint8_t>& m, std::string_view key) {
    assert(m.size() >= kStunHeaderBytes && m.size() % 4 == 0);
    const std::size_t at = m.size();
    const auto mac = detail::stun_hmac_sha1(m, static_cast<std::uint16_t>(at + 4 + 20 - kStunHeaderBytes), key);
    assert(mac.has_value());  // a key (the server's ice-pwd) is never empty
    append_attribute(m, kStunAttrMessageIntegrity, mac.value_or(std::array<std::uint8_t, 20>{}));
    const std::size_t fp_at = m.size();
    const std::uint32_t crc = detail::stun_fingerprint(m, static_cast<std::uint16_t>(fp_at + 4 + 4 - kStunHeaderBytes));
    std::vector<std::uint8_t> value;
    append_u32(value, crc);
    append_attribute(m, kStunAttrFingerprint, value);
    set_length(m, m.size() - kStunHeaderBytes);
}

std::vector<std::uint8_t> build_binding_success(const StunTransactionId& transaction_id, const StunAddress& mapped,
                                                std::string_view key, std::string_view software) {
    auto m = header(kStunBindingSuccess, transaction_id);
    if (!software.empty()) append_text(m, kStunAttrSoftware, software);
    append_attribute(m, kStunAttrXorMappedAddress, xor_address_value(mapped, transaction_id));
    append_integrity_and_fingerprint(m, key);
    return m;
}

std::vector<std::uint8_t> build_binding_request(const BindingRequestFields& f, std::string_view key) {
    assert(f.username.size() <= kStunMaxUsernameBytes);
    auto m = header(kStunBindingRequest, f.transaction_id);
    append_text(m, kStunAttrUsername, f.username);
    std::vector<std::uint8_t> v;
    append_u32(v, f.priority);
    append_attribute(m, kStunAttrPriority, v);
    v.clear();
    append_u64(v, f.ice_controlling);
    append_attribute(m, kStunAttrIceControlling, v);
    if (f.use_candidate) append_attribute(m, kStunAttrUseCandidate, {});
    append_integrity_and_fingerprint(m, key);
    return m;
}

}  // namespace jetrace::webrtc
