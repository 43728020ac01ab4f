// The invariant of both world payload targets: a decoded snapshot encodes
// without an assertion (decoding accepted only what encoding allows), and
// that encoding decodes to the same snapshot. Snapshots are compared by
// their encodings, which are deterministic and carry every field.
#pragma once

#include "fuzz_check.hpp"
#include "jetrace/proto/world_codec.hpp"

#include <string>
#include <vector>

namespace jetrace::fuzz {

inline void check_world_round_trip(const proto::WorldSnapshot& decoded, const proto::WorldSnapshot* baseline) {
    const std::vector<std::uint8_t> once = proto::encode_world(decoded, baseline);
    proto::WorldSnapshot again;
    std::string error;
    JETRACE_FUZZ_CHECK(proto::decode_world(once, baseline, again, error));
    JETRACE_FUZZ_CHECK(proto::encode_world(again, baseline) == once);
    JETRACE_FUZZ_CHECK(state_hash(again.state) == state_hash(decoded.state));
}

}  // namespace jetrace::fuzz
