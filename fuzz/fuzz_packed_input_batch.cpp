// The bit-packed InputBatch payload (packed::unpack), without the
// flatbuffers wrapper around it so that every mutation reaches the bit
// reader. Invariant: pack(unpack(x)) unpacks to the same batch.
#include "fuzz_check.hpp"
#include "packed_payloads.hpp"

namespace jp = jetrace::proto;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    jp::InputBatch m;
    std::string error;
    if (!jp::packed::unpack(jetrace::fuzz::bytes(data, size), m, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(!m.inputs.empty() && m.inputs.size() <= jp::kMaxInputsPerBatch);
    const std::vector<std::uint8_t> once = jp::packed::pack(m);
    jp::InputBatch again;
    JETRACE_FUZZ_CHECK(jp::packed::unpack(once, again, error));
    JETRACE_FUZZ_CHECK(again.first_tick == m.first_tick && again.ack_snapshot_tick == m.ack_snapshot_tick &&
                       again.inputs == m.inputs);
    return 0;
}
