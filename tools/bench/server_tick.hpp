// jetrace-bench server: the authoritative server's tick and its wire bytes,
// in one process. A RaceServer on a built-in track and N AI bots (each a
// predicting RaceClient on its own connection, driven as
// tests/support/live_race.hpp drives them) over net::MemoryHub, stepped on a
// virtual clock in 1 ms steps: the lobby, the server's countdown, then
// `seconds` of race time measured. Everything but the times is
// deterministic: the bytes and the final state hash are the same run after
// run (and every repeat is checked to agree). One JSON object.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace jetrace::bench {

struct ServerTickOptions {
    /// A built-in track (jetrace::builtin_track_names()).
    std::string track = "stadium";
    /// AI bots, each a player on its own connection (unit: bots).
    int bots = 64;
    /// Race time measured after the start (unit: s of the virtual clock).
    double seconds = 20;
    /// Timed runs, each from a fresh server and fresh bots; medians of the
    /// times are reported (unit: runs).
    int repeats = 1;
    /// One-way latency of the in-memory network (unit: ms of the virtual clock).
    int latency_ms = 0;
    /// The server's and clients' log level (on stderr).
    std::string log_level = "warn";
};

/// The `server` subcommand and its options.
CLI::App* add_server_tick(CLI::App& app, ServerTickOptions& o);
int run_server_tick(const ServerTickOptions& o);

}  // namespace jetrace::bench
