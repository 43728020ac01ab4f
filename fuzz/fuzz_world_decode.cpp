// proto::decode_world() without a baseline (a client's first snapshot).
// Invariants: the round trip of world_round_trip.hpp, and the decoded
// snapshot delta-encoded against itself decodes back to itself.
#include "world_round_trip.hpp"

namespace jp = jetrace::proto;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    jp::WorldSnapshot out;
    std::string error;
    if (!jp::decode_world(jetrace::fuzz::bytes(data, size), nullptr, out, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(out.state.cars.size() == out.last_inputs.size() &&
                       out.upcoming.size() == out.state.cars.size());
    jetrace::fuzz::check_world_round_trip(out, nullptr);
    jetrace::fuzz::check_world_round_trip(out, &out);
    return 0;
}
