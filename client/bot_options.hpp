// jetrace-bot's command line: its options, checked, and the tracks the bots
// know.
#pragma once

#include "jetrace/client/client_config.hpp"
#include "jetrace/core/world.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetrace::bot {

struct Address {
    std::string host;
    std::uint16_t port = 0;
};

struct BotOptions {
    std::vector<std::string> connects;
    /// Bots (unit: bots); with connect tokens, one per token.
    int count = 1;
    bool thin = false;
    /// Bots are PREFIX0, PREFIX1, ...
    std::string prefix = "bot";
    /// Races each bot stays for (unit: races).
    int races = 1;
    std::string track_spec;
    std::string log_level = "warn";
    /// The bots' clock runs this many times faster than real time (unit: 1).
    double time_scale = 1.0;
    /// Wall-clock time before giving up (unit: s).
    double max_seconds = 3600;
    std::uint64_t seed = 1;
    /// (unit: s)
    double reconnect_grace_s = 10.0;
    /// (unit: s of real time)
    double join_window_s = 10.0;
    /// Bots of one --connect address joining at a time: connection opened,
    /// no Welcome yet (join_pacing.hpp). At most the server's
    /// --pre-hello-limit (4 by default), which refuses connections beyond it
    /// (unit: bots).
    int join_limit = 4;
    /// (unit: ticks)
    double target_margin = client::ClientConfig{}.target_margin_ticks;
    /// Bots decide their inputs this many ticks ahead (ClientConfig::
    /// input_delay_ticks), so the other bots' predictions know them instead
    /// of guessing (docs/PERFORMANCE.md, "Load"); the AI reacts 33 ms later
    /// (unit: ticks).
    std::uint32_t input_delay = 4;
    std::vector<std::string> token_texts;
    std::string token_file;

    /// From --connect, checked.
    std::vector<Address> addresses;
    /// From --token and --token-file, checked (binary form).
    std::vector<std::vector<std::uint8_t>> tokens;
};

/// Parses and checks the command line (and starts logging). Returns the
/// code to exit with (--help, bad arguments; messages printed), or -1 to run.
int parse_options(int argc, char** argv, BotOptions& o);

/// The tracks the bots know: the --track file only, if given, else every
/// built-in track. False with a message printed.
bool load_scenes(const std::string& track_spec, std::vector<std::unique_ptr<Scene>>& out);

}  // namespace jetrace::bot
