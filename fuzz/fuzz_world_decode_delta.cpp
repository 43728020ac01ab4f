// proto::decode_world() against a baseline. The input is a u16
// (little-endian) length L, then a baseline payload of L bytes (decoded
// without a baseline, as a client would have), then the delta payload.
// Invariants: the round trip of world_round_trip.hpp, and decoding in place
// (the baseline is the output, as clients may do) gives the same snapshot.
#include "world_round_trip.hpp"

namespace jp = jetrace::proto;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 2) return 0;
    const std::size_t base_len = data[0] | (std::size_t{data[1]} << 8);
    if (size - 2 < base_len) return 0;
    const auto base_bytes = jetrace::fuzz::bytes(data + 2, base_len);
    const auto delta_bytes = jetrace::fuzz::bytes(data + 2 + base_len, size - 2 - base_len);
    jp::WorldSnapshot base;
    std::string error;
    if (!jp::decode_world(base_bytes, nullptr, base, error)) return 0;
    jp::WorldSnapshot out;
    if (!jp::decode_world(delta_bytes, &base, out, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(out.state.cars.size() == base.state.cars.size() && out.state.tick >= base.state.tick);
    jetrace::fuzz::check_world_round_trip(out, &base);
    jp::WorldSnapshot in_place = base;
    JETRACE_FUZZ_CHECK(jp::decode_world(delta_bytes, &in_place, in_place, error));
    JETRACE_FUZZ_CHECK(jp::encode_world(in_place, &base) == jp::encode_world(out, &base));
    return 0;
}
