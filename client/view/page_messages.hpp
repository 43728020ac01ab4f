// Messages from the page (untrusted): one JSON object per WebSocket text
// message, checked field by field. Anything else is malformed, and the
// caller closes that page's socket.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

namespace jetrace::view {

/// Longest page message accepted (unit: bytes).
inline constexpr std::size_t kMaxPageMessageBytes = 1024;
/// Playback speeds a page may ask for (unit: times real time).
inline constexpr double kMinSpeed = 0.25;
inline constexpr double kMaxSpeed = 8.0;

struct PlayMessage {
    bool playing = false;
};
struct SpeedMessage {
    double speed = 1.0;
};
struct SeekMessage {
    std::uint32_t tick = 0;
};

using PageMessage = std::variant<PlayMessage, SpeedMessage, SeekMessage>;

/// What a page may ask of the replay it watches.
struct PageLimits {
    std::uint32_t first_tick = 0;
    std::uint32_t last_tick = 0;
};

/// Parses one message:
///   {"type":"play"} | {"type":"pause"} | {"type":"speed","value":S} | {"type":"seek","tick":N}
/// S a finite number in [kMinSpeed, kMaxSpeed], N an integer in
/// [first_tick, last_tick]; no other keys. False with a reason otherwise.
bool parse_page_message(std::string_view text, const PageLimits& limits, PageMessage& out, std::string& error);

}  // namespace jetrace::view
