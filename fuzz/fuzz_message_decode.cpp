// proto::decode() on untrusted bytes, every message kind (the file
// identifier picks the kind). Invariant: whatever decodes re-encodes
// without an assertion and decodes again to the same message (compared by
// re-encoding: encoding is deterministic).
#include "fuzz_check.hpp"
#include "jetrace/proto/messages.hpp"

namespace jp = jetrace::proto;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    jp::Message m;
    std::string error;
    if (!jp::decode(jetrace::fuzz::bytes(data, size), m, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    const std::vector<std::uint8_t> once = jp::encode(m);
    JETRACE_FUZZ_CHECK(once.size() <= jp::kMaxMessageBytes);
    jp::Message again;
    JETRACE_FUZZ_CHECK(jp::decode(once, again, error));
    JETRACE_FUZZ_CHECK(again.index() == m.index());
    JETRACE_FUZZ_CHECK(jp::encode(again) == once);
    return 0;
}
