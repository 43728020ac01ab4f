// A datagram on the WebRTC UDP port read as STUN (webrtc::parse_stun and
// parse_binding_request), as the ICE-lite server does before it looks up
// the ufrag's password. Invariants: what parses is STUN by is_stun(); a
// Binding request has USERNAME, MESSAGE-INTEGRITY and FINGERPRINT; checking
// integrity never reads out of bounds; the response to a parsed request
// reads back with its address and a valid integrity.
#include "fuzz_check.hpp"
#include "jetrace/webrtc/stun.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::webrtc;
    const auto bytes = jetrace::fuzz::bytes(data, size);
    constexpr std::string_view kKey = "VOkJxbRl1RmTxUk/WvJxBt";
    StunMessage m;
    const StunError error = parse_stun(bytes, m);
    JETRACE_FUZZ_CHECK((error == StunError::kNotStun) == !is_stun(bytes));
    if (error != StunError::kNone) return 0;
    JETRACE_FUZZ_CHECK(!m.username || m.username->size() <= kStunMaxUsernameBytes);
    (void)integrity_valid(bytes, m, kKey);
    if (parse_binding_request(bytes, m) != StunError::kNone) return 0;
    JETRACE_FUZZ_CHECK(m.username && m.integrity_offset && m.has_fingerprint);
    std::string_view receiver, sender;
    if (split_ice_username(*m.username, receiver, sender)) JETRACE_FUZZ_CHECK(!receiver.empty() && !sender.empty());
    const StunAddress from = m.xor_mapped_address.value_or(StunAddress::v4({127, 0, 0, 1}, 5000));
    const auto response = build_binding_success(m.transaction_id, from, kKey);
    StunMessage back;
    JETRACE_FUZZ_CHECK(parse_stun(response, back) == StunError::kNone);
    JETRACE_FUZZ_CHECK(back.xor_mapped_address == from && back.transaction_id == m.transaction_id);
    JETRACE_FUZZ_CHECK(integrity_valid(response, back, kKey));
    return 0;
}
