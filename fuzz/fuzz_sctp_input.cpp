// SCTP packets as the server feeds them to usrsctp: the plaintext of DTLS
// records from a browser whose handshake succeeded, into an association
// connected to an in-process peer (webrtc::SctpAssociation::feed). The input
// is a flags byte, then packets, each a 2-byte big-endian length and its
// bytes. Flag bit 0 writes the association's ports and verification tag
// into each packet, bit 1 its CRC-32c, so the fuzzer reaches the chunk
// parsers behind usrsctp's checks. Invariants: no crash; what the server
// sends stays within the MTU; messages stay within max_message_bytes.
#include "fuzz_check.hpp"
#include "jetrace/webrtc/sctp.hpp"

#include <usrsctp.h>

#include <algorithm>
#include <cstring>

namespace {

using jetrace::webrtc::SctpAssociation;

void pump(SctpAssociation& a, SctpAssociation& b, std::vector<std::uint8_t>* header) {
    for (int round = 0; round < 16; ++round) {
        auto from_a = a.take_outgoing();
        auto from_b = b.take_outgoing();
        if (from_a.empty() && from_b.empty()) return;
        for (const auto& p : from_a) {
            if (header != nullptr && p.size() >= 8) header->assign(p.begin(), p.begin() + 8);
            b.feed(p);
        }
        for (const auto& p : from_b) a.feed(p);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::webrtc;
    if (size < 1) return 0;
    const SctpSettings settings;
    SctpAssociation browser(settings);
    SctpAssociation server(settings);
    std::vector<std::uint8_t> header;  // ports and verification tag the server accepts
    pump(browser, server, &header);
    JETRACE_FUZZ_CHECK(server.state() == SctpState::kConnected && header.size() == 8);
    const std::uint8_t flags = data[0];
    std::size_t at = 1;
    while (size - at >= 2) {
        const std::size_t n = std::min<std::size_t>((std::size_t{data[at]} << 8) | data[at + 1], size - at - 2);
        std::vector<std::uint8_t> packet(data + at + 2, data + at + 2 + n);
        at += 2 + n;
        if (packet.size() >= 12 && (flags & 1) != 0) std::copy(header.begin(), header.end(), packet.begin());
        if (packet.size() >= 12 && (flags & 2) != 0) {
            std::memset(packet.data() + 8, 0, 4);
            const std::uint32_t crc = usrsctp_crc32c(packet.data(), packet.size());
            std::memcpy(packet.data() + 8, &crc, 4);
        }
        server.feed(packet);
        for (const auto& p : server.take_outgoing()) JETRACE_FUZZ_CHECK(p.size() <= settings.mtu_bytes);
        for (const auto& m : server.take_messages()) JETRACE_FUZZ_CHECK(m.data.size() <= settings.max_message_bytes);
        (void)server.take_reset_streams();
    }
    SctpAssociation::advance_timers(1000);
    return 0;
}
