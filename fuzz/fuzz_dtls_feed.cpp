// Datagrams from an unknown address fed to a fresh server DtlsEndpoint, as
// the WebRTC port does with what follows a browser's STUN check. The input
// is datagrams, each a 2-byte big-endian length then its bytes. Invariants:
// OpenSSL reads them without a crash, what the server sends is at most the
// MTU, and without the private key of the expected certificate no input
// completes the handshake.
#include "fuzz_check.hpp"
#include "jetrace/webrtc/dtls.hpp"

#include <memory>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::webrtc;
    static const std::unique_ptr<DtlsContext> context = DtlsContext::create(DtlsSettings{});
    static const std::unique_ptr<DtlsContext> peer = DtlsContext::create(DtlsSettings{});
    JETRACE_FUZZ_CHECK(context != nullptr && peer != nullptr);
    DtlsEndpoint server(*context, DtlsRole::kServer, peer->fingerprint());
    std::size_t at = 0;
    while (size - at >= 2) {
        const std::size_t n = std::min<std::size_t>((std::size_t{data[at]} << 8) | data[at + 1], size - at - 2);
        server.feed({data + at + 2, n});
        at += 2 + n;
        for (const auto& d : server.take_outgoing()) JETRACE_FUZZ_CHECK(d.size() <= context->settings().mtu_bytes);
        JETRACE_FUZZ_CHECK(!server.handshake_done());
        (void)server.take_received();
    }
    server.handle_timeout();
    (void)server.next_timeout();
    return 0;
}
