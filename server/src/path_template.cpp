// %n / %t file-name patterns and UTC time stamps.
#include "jetrace/server/path_template.hpp"

#include <ctime>

namespace jetrace::server {

namespace {

std::string utc_format(std::int64_t unix_s, const char* fmt) {
    const std::time_t t = static_cast<std::time_t>(unix_s);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    const std::size_t n = std::strftime(buf, sizeof buf, fmt, &tm);
    return std::string(buf, n);
}

}  // namespace

std::string utc_compact(std::int64_t unix_s) { return utc_format(unix_s, "%Y%m%dT%H%M%SZ"); }

std::string utc_iso8601(std::int64_t unix_s) { return utc_format(unix_s, "%Y-%m-%dT%H:%M:%SZ"); }

std::string expand_path(const std::string& pattern, std::uint32_t race_number, std::int64_t start_unix_s) {
    std::string out;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        const char c = pattern[i];
        const char next = i + 1 < pattern.size() ? pattern[i + 1] : '\0';
        if (c != '%' || (next != 'n' && next != 't' && next != '%')) {
            out += c;
            continue;
        }
        ++i;
        if (next == 'n') out += std::to_string(race_number);
        if (next == 't') out += utc_compact(start_unix_s);
        if (next == '%') out += '%';
    }
    return out;
}

bool path_varies(const std::string& pattern) {
    for (std::size_t i = 0; i + 1 < pattern.size(); ++i) {
        if (pattern[i] != '%') continue;
        if (pattern[i + 1] == 'n' || pattern[i + 1] == 't') return true;
        if (pattern[i + 1] == '%') ++i;
    }
    return false;
}

}  // namespace jetrace::server
