// parse_keys_message() on untrusted bytes (what a driving jetrace-view
// reads from a page's WebSocket). Invariants: a rejected message has a
// reason; an accepted one is at most kMaxPageMessageBytes and, written back
// as JSON, parses to the same keys.
#include "drive_messages.hpp"
#include "fuzz_check.hpp"
#include "page_messages.hpp"

#include <string>
#include <string_view>

namespace {

std::string to_text(const jetrace::view::KeysMessage& k) {
    const auto b = [](bool v) { return v ? "true" : "false"; };
    return std::string(R"({"type":"keys","up":)") + b(k.up) + R"(,"left":)" + b(k.left) + R"(,"right":)" +
           b(k.right) + R"(,"brake":)" + b(k.brake) + "}";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::view;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    KeysMessage k;
    std::string error;
    if (!parse_keys_message(text, k, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(size <= kMaxPageMessageBytes);
    KeysMessage again;
    JETRACE_FUZZ_CHECK(parse_keys_message(to_text(k), again, error) && again == k);
    return 0;
}
