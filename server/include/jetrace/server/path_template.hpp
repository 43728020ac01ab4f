// File names of a race's results and replay: %n is the race number, %t the
// race's UTC start time (20261201T231500Z), %% a percent sign.
#pragma once

#include <cstdint>
#include <string>

namespace jetrace::server {

/// `pattern` with %n, %t and %% expanded; any other % sequence is kept.
std::string expand_path(const std::string& pattern, std::uint32_t race_number, std::int64_t start_unix_s);
/// True if `pattern` names a different file for each race (it has %n or %t).
bool path_varies(const std::string& pattern);
/// 20261201T231500Z for `unix_s` (unit: s since 1970 UTC).
std::string utc_compact(std::int64_t unix_s);
/// 2026-12-01T23:15:00Z for `unix_s` (ISO 8601, UTC).
std::string utc_iso8601(std::int64_t unix_s);

}  // namespace jetrace::server
