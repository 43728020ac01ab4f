// jetrace-server's files (results, spent nonces): written whole or not at
// all, and checked before the server listens. The RaceServer library does
// no file I/O for these; jetrace-server calls this.
#pragma once

#include "jetrace/auth/token_verifier.hpp"
#include "jetrace/server/race_server.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace jetrace::server {

/// Writes `content` to `path` durably: a temporary file beside it, written,
/// fsynced and renamed over `path`, then the directory fsynced. False with
/// what failed (the path and strerror(errno)); the temporary file is removed.
bool write_file_atomically(const std::string& path, const std::string& content, std::string& error);

/// Checks that a file can be created where `path` points (by creating and
/// removing a probe file in its directory) and that `path` is no directory.
bool check_can_create(const std::string& path, std::string& error);

/// The results file of one race: race, track, laps, ticks, state_hash,
/// end_reason, aborted, start_utc, end_utc, standings (every racer, a
/// dropped one as not finished with "dropped": true).
nlohmann::json results_json(const RaceEnd& end, const std::string& track, int laps);

/// Writes race `end`'s results to `pattern` expanded (%n, %t). If that
/// fails and the name does not vary per race, a file already there (an
/// earlier race's) is renamed to NAME.stale so that it does not pass for
/// this race's. False with what was lost.
bool write_results(const std::string& pattern, const RaceEnd& end, const std::string& track, int laps,
                   std::string& error);

/// --nonce-file: "jetrace-nonces 1", then one "HEX EXPIRY" line per nonce.
/// A missing file is an empty table; anything malformed is an error.
bool load_nonce_file(const std::string& path, std::vector<auth::SpentNonce>& out, std::string& error);
bool save_nonce_file(const std::string& path, const std::vector<auth::SpentNonce>& nonces, std::string& error);

}  // namespace jetrace::server
