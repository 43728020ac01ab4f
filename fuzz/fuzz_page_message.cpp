// parse_page_message() on untrusted bytes (what jetrace-view reads from a
// page's WebSocket). Invariants: a rejected message has a reason; an
// accepted one is in range (a seek tick within the replay's ticks, a speed
// finite and within [0.25, 8]) and, written back as JSON, parses to the
// same message.
#include "fuzz_check.hpp"
#include "page_messages.hpp"

#include <cmath>
#include <string>
#include <string_view>

namespace {

std::string to_text(const jetrace::view::PageMessage& m) {
    using namespace jetrace::view;
    if (const auto* p = std::get_if<PlayMessage>(&m)) return p->playing ? R"({"type":"play"})" : R"({"type":"pause"})";
    if (const auto* s = std::get_if<SpeedMessage>(&m)) {
        char buf[64];
        std::snprintf(buf, sizeof buf, R"({"type":"speed","value":%.17g})", s->speed);
        return buf;
    }
    return R"({"type":"seek","tick":)" + std::to_string(std::get<SeekMessage>(m).tick) + "}";
}

bool same(const jetrace::view::PageMessage& a, const jetrace::view::PageMessage& b) {
    using namespace jetrace::view;
    if (a.index() != b.index()) return false;
    if (const auto* p = std::get_if<PlayMessage>(&a)) return p->playing == std::get<PlayMessage>(b).playing;
    if (const auto* s = std::get_if<SpeedMessage>(&a)) return s->speed == std::get<SpeedMessage>(b).speed;
    return std::get<SeekMessage>(a).tick == std::get<SeekMessage>(b).tick;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::view;
    const PageLimits limits{100, 36000};
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    PageMessage m;
    std::string error;
    if (!parse_page_message(text, limits, m, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(size <= kMaxPageMessageBytes);
    if (const auto* s = std::get_if<SpeedMessage>(&m)) {
        JETRACE_FUZZ_CHECK(std::isfinite(s->speed) && s->speed >= kMinSpeed && s->speed <= kMaxSpeed);
    }
    if (const auto* k = std::get_if<SeekMessage>(&m)) {
        JETRACE_FUZZ_CHECK(k->tick >= limits.first_tick && k->tick <= limits.last_tick);
    }
    PageMessage again;
    JETRACE_FUZZ_CHECK(parse_page_message(to_text(m), limits, again, error) && same(m, again));
    return 0;
}
