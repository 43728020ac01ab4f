// The viewer's settings: plain values with defaults, checked once by
// validate(); the command line's ranges are these constants.
#pragma once

#include <cstdint>
#include <string>

namespace jetrace::view {

inline constexpr int kMinFrameRateHz = 1;
inline constexpr int kMaxFrameRateHz = 120;
inline constexpr int kMaxPages = 1024;

struct ViewSettings {
    /// Address the page is served on (loopback unless asked otherwise).
    std::string http_host = "127.0.0.1";
    /// (0 = any free port; the bound one is printed).
    std::uint16_t http_port = 8080;
    /// Frames sent to a page per second of real time while it plays (unit: Hz).
    int frame_rate_hz = 30;
    /// Playback speed a page starts at (unit: times real time).
    double speed = 1.0;
    /// Pages (WebSockets) open at once; more are refused with 503 (unit: pages).
    int max_pages = 32;
    /// Pages start paused at the first tick instead of playing.
    bool paused = false;
    /// The page's own files (index.html, app.js, style.css).
    std::string web_dir;
    /// node_modules of the repository (three.js is served from it).
    std::string node_modules_dir;
};

/// "" if valid, else the problem.
std::string validate(const ViewSettings& s);

/// Splits "ADDR:PORT" (ADDR an IPv4 or IPv6 address, [v6]:PORT too; PORT
/// 0..65535). False with a reason.
bool parse_http_address(const std::string& text, std::string& host, std::uint16_t& port, std::string& error);

}  // namespace jetrace::view
