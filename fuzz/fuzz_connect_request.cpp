// read_connect_request() on untrusted datagrams: what jetrace-server's
// pre-Hello gate reads from a datagram addressed to no peer, to answer a
// refused connection request (net/src/connect_request.hpp). Invariants: an
// accepted request is at least a header and a whole CONNECT, names a client
// slot below 0xFFF and reads the same from a copy; its refusal is smaller
// than the request, addressed to that slot, a DISCONNECT carrying the code,
// and no connection request itself.
#include "connect_request.hpp"
#include "fuzz_check.hpp"

#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace nd = jetrace::net::detail;
    nd::ConnectRequest request;
    if (!nd::read_connect_request(data, size, request)) return 0;
    JETRACE_FUZZ_CHECK(size >= 2 + sizeof(ENetProtocolConnect));
    JETRACE_FUZZ_CHECK(request.client_peer < ENET_PROTOCOL_MAXIMUM_PEER_ID);
    const std::vector<std::uint8_t> copy(data, data + size);
    nd::ConnectRequest again;
    JETRACE_FUZZ_CHECK(nd::read_connect_request(copy.data(), copy.size(), again));
    JETRACE_FUZZ_CHECK(again.client_peer == request.client_peer && again.connect_id == request.connect_id);
    constexpr enet_uint32 kCode = 2008;
    const auto answer = nd::refusal_datagram(request, kCode);
    JETRACE_FUZZ_CHECK(answer.size() < size);
    JETRACE_FUZZ_CHECK(static_cast<unsigned>((answer[0] << 8) | answer[1]) == request.client_peer);
    JETRACE_FUZZ_CHECK((answer[2] & ENET_PROTOCOL_COMMAND_MASK) == ENET_PROTOCOL_COMMAND_DISCONNECT);
    const enet_uint32 carried = (static_cast<enet_uint32>(answer[6]) << 24) |
                                (static_cast<enet_uint32>(answer[7]) << 16) |
                                (static_cast<enet_uint32>(answer[8]) << 8) | answer[9];
    JETRACE_FUZZ_CHECK(carried == kCode);
    nd::ConnectRequest none;
    JETRACE_FUZZ_CHECK(!nd::read_connect_request(answer.data(), answer.size(), none));
    return 0;
}
