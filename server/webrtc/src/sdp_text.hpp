// The text rules of SDP (RFC 8866 section 5) and ICE (RFC 8839) shared by
// the offer reader and the answer writer.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace jetrace::webrtc::detail {

/// The next line of `text` (without its LF or CRLF), advancing `text`;
/// false at the end. Empty lines at the very end are the end.
inline bool next_line(std::string_view& text, std::string_view& line) {
    if (text.find_first_not_of("\r\n") == std::string_view::npos) return false;
    const std::size_t lf = text.find('\n');
    line = text.substr(0, lf);
    text = lf == std::string_view::npos ? std::string_view{} : text.substr(lf + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return true;
}

/// "x=..." with x a lower-case letter and no control characters.
inline bool well_formed_line(std::string_view line) {
    if (line.size() < 2 || line[0] < 'a' || line[0] > 'z' || line[1] != '=') return false;
    for (const char c : line) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u == 0x7f) return false;
    }
    return true;
}

/// The fields of `text` between single spaces (empty fields kept).
inline std::vector<std::string_view> split_spaces(std::string_view text) {
    std::vector<std::string_view> fields;
    while (fields.size() < 64) {
        const std::size_t space = text.find(' ');
        fields.push_back(text.substr(0, space));
        if (space == std::string_view::npos) break;
        text = text.substr(space + 1);
    }
    return fields;
}

/// A decimal number of 1..10 digits, at most `max`.
inline bool parse_decimal(std::string_view text, std::uint64_t max, std::uint64_t& out) {
    if (text.empty() || text.size() > 10) return false;
    std::uint64_t v = 0;
    for (const char c : text) {
        if (c < '0' || c > '9') return false;
        v = v * 10 + static_cast<std::uint64_t>(c - '0');
    }
    if (v > max) return false;
    out = v;
    return true;
}

/// RFC 8839's ice-char (ALPHA / DIGIT / "+" / "/"), between min and max of them.
inline bool ice_chars(std::string_view text, std::size_t min, std::size_t max) {
    if (text.size() < min || text.size() > max) return false;
    for (const char c : text) {
        const bool ok = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '+' || c == '/';
        if (!ok) return false;
    }
    return true;
}

}  // namespace jetrace::webrtc::detail
