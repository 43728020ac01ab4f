// The bit-packed Snapshot payload (packed::unpack: header fields, then the
// world payload whose first field is the server tick), without the
// flatbuffers wrapper. Invariant: pack(unpack(x)) unpacks to the same
// snapshot.
#include "fuzz_check.hpp"
#include "packed_payloads.hpp"

namespace jp = jetrace::proto;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    jp::Snapshot m;
    std::string error;
    if (!jp::packed::unpack(jetrace::fuzz::bytes(data, size), m, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    const std::vector<std::uint8_t> once = jp::packed::pack(m);
    jp::Snapshot again;
    JETRACE_FUZZ_CHECK(jp::packed::unpack(once, again, error));
    JETRACE_FUZZ_CHECK(again.server_tick == m.server_tick && again.baseline_tick == m.baseline_tick &&
                       again.last_applied_input_tick == m.last_applied_input_tick &&
                       again.input_margin_ticks == m.input_margin_ticks && again.phase == m.phase &&
                       again.race_number == m.race_number && again.world == m.world);
    return 0;
}
