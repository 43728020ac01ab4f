#include "view_settings.hpp"

#include "page_messages.hpp"

#include <boost/asio/ip/address.hpp>

#include <charconv>
#include <cmath>
#include <filesystem>

namespace jetrace::view {

std::string validate(const ViewSettings& s) {
    boost::system::error_code ec;
    boost::asio::ip::make_address(s.http_host, ec);
    if (ec) return "http address '" + s.http_host + "' is not an IP address";
    if (s.frame_rate_hz < kMinFrameRateHz || s.frame_rate_hz > kMaxFrameRateHz) return "frame rate out of range";
    if (s.max_pages < 1 || s.max_pages > kMaxPages) return "max pages out of range";
    if (!std::isfinite(s.speed) || s.speed < kMinSpeed || s.speed > kMaxSpeed) return "speed out of [0.25, 8]";
    if (!std::filesystem::is_regular_file(std::filesystem::path(s.web_dir) / "index.html")) {
        return "no index.html in the web directory '" + s.web_dir + "'";
    }
    if (!std::filesystem::is_regular_file(std::filesystem::path(s.node_modules_dir) / "three/build/three.module.js")) {
        return "three.js is not installed in '" + s.node_modules_dir + "' (run npm ci in the repository, or tools/setup.sh)";
    }
    return "";
}

bool parse_http_address(const std::string& text, std::string& host, std::uint16_t& port, std::string& error) {
    const auto colon = text.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) {
        error = "'" + text + "' is not ADDR:PORT";
        return false;
    }
    std::string h = text.substr(0, colon);
    if (h.size() > 2 && h.front() == '[' && h.back() == ']') h = h.substr(1, h.size() - 2);
    const std::string p = text.substr(colon + 1);
    unsigned value = 0;
    const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), value);
    if (ec != std::errc{} || end != p.data() + p.size() || value > 65535) {
        error = "'" + p + "' is not a port (0..65535)";
        return false;
    }
    boost::system::error_code bad;
    boost::asio::ip::make_address(h, bad);
    if (bad) {
        error = "'" + h + "' is not an IP address";
        return false;
    }
    host = h;
    port = static_cast<std::uint16_t>(value);
    return true;
}

}  // namespace jetrace::view
