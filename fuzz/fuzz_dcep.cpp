// A PPID 50 message on a data channel's SCTP stream read as DCEP
// (webrtc::parse_dcep_open), as the server does when a browser opens a
// channel. Invariants: an accepted open is written back byte for byte by
// build_dcep_open; a refusal leaves an empty DataChannelOpen.
#include "fuzz_check.hpp"
#include "jetrace/webrtc/dcep.hpp"

#include <algorithm>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::webrtc;
    const auto bytes = jetrace::fuzz::bytes(data, size);
    DataChannelOpen open;
    const DcepError error = parse_dcep_open(bytes, open);
    (void)is_dcep_ack(bytes);
    if (error != DcepError::kNone) {
        JETRACE_FUZZ_CHECK(open == DataChannelOpen{} && !to_string(error).empty());
        return 0;
    }
    const auto again = build_dcep_open(open);
    JETRACE_FUZZ_CHECK(again.size() == size && std::equal(again.begin(), again.end(), data));
    return 0;
}
