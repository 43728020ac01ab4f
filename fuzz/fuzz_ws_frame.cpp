// A WebSocket frame from a page or from the server (net::read_ws_frame),
// then its message through proto::decode(), as both WebSocket ends do.
// Invariants: an accepted frame names a channel and a non-empty message,
// and ws_frame() of what was read is the frame again byte for byte.
#include "fuzz_check.hpp"
#include "jetrace/net/ws_frame.hpp"
#include "jetrace/proto/messages.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> frame(data, size);
    jetrace::net::Channel channel{};
    std::span<const std::uint8_t> message;
    if (!jetrace::net::read_ws_frame(frame, channel, message)) {
        JETRACE_FUZZ_CHECK(size < 2 || data[0] >= jetrace::net::kChannelCount);
        return 0;
    }
    JETRACE_FUZZ_CHECK(!message.empty() && static_cast<int>(channel) < jetrace::net::kChannelCount);
    const std::string again = jetrace::net::ws_frame(channel, message);
    JETRACE_FUZZ_CHECK(again.size() == size && std::equal(again.begin(), again.end(), data, data + size,
                                                          [](char a, std::uint8_t b) { return static_cast<std::uint8_t>(a) == b; }));
    jetrace::proto::Message m;
    std::string error;
    if (!jetrace::proto::decode(std::vector<std::uint8_t>(message.begin(), message.end()), m, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
    }
    return 0;
}
