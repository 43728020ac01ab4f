// jetrace-sim's replay modes: --replay, --verify, --diff and --synctest.
// Exit codes: 0 the check holds, 1 it does not (the JSON says why), 2 bad
// arguments or a file that cannot be read at all.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace jetrace::sim {

struct ReplayArgs {
    /// --track: the track file when the replay's track is not built in ("" = the replay's own).
    std::string track;
    /// --key: the signature must be by this public key file.
    std::string key_file;
    /// --expect: the final state hash must be this (16 hex digits).
    std::optional<std::uint64_t> expect;
    /// --rollback: ticks rolled back by --synctest.
    int rollback_ticks = 8;
};

/// Re-simulates a replay, prints "replay FILE: ..." and state_hash=.
int replay_file(const std::string& path, const ReplayArgs& args);
/// Prints the verdict JSON of verify().
int verify_file(const std::string& path, const ReplayArgs& args);
/// Prints the desync finder's JSON; `b` empty: against this build (--rebuild).
int diff_files(const std::string& a, const std::string& b, const ReplayArgs& args);
/// Prints SyncTest's JSON.
int synctest_file(const std::string& path, const ReplayArgs& args);

/// Re-simulates a replay up to world tick `stop_tick` and prints that world
/// as one JSON line: {"tick":N,"cars":[{"slot":S,"p":[x,y,z],"respawns":R},...]}, active
/// cars only, each coordinate with 17 significant digits (reads back bit
/// for bit). Exit 2 if the replay cannot be read or has no such tick.
int state_at_file(const std::string& path, const ReplayArgs& args, std::uint32_t stop_tick);

/// Parses 16 hex digits; nullopt otherwise.
std::optional<std::uint64_t> parse_hash(const std::string& text);

}  // namespace jetrace::sim
