// jetrace-bot's outcome per bot, its exit code and its JSON line.
#pragma once

#include "jetrace/client/race_client.hpp"

#include <cstdint>
#include <string>

namespace jetrace::bot {

/// Exit codes of jetrace-bot (README, --help): the worst bot's outcome.
enum ExitCode : int {
    kFinished = 0,      ///< every bot finished its races
    kDidNotFinish = 1,  ///< a bot raced to the end of its race without finishing
    kBadArguments = 2,  ///< bad arguments, or a track the bot does not have
    kRefused = 3,       ///< the server refused a bot (the reason is on stderr)
    kLostConnection = 4,///< a connection failed or dropped for good
    kServerGone = 5,    ///< the server said goodbye (shut down, drained, lobby cancelled)
    kStopped = 6,       ///< --max-seconds or SIGTERM/SIGINT stopped a bot before it finished
};

/// What one bot's run came to; `stopped` if the bot left by --max-seconds or a signal.
ExitCode outcome_of(const client::RaceClient& c, bool finished, bool stopped);
const char* outcome_name(ExitCode code);
/// The exit code of several bots' outcomes: the most telling one.
ExitCode combine(ExitCode a, ExitCode b);

/// Prints one JSON line (stdout) for a bot; returns whether it finished.
/// `c` nullptr: a bot stopped before it opened its connection (outcome
/// `stopped`, every figure 0).
bool print_bot_line(const client::RaceClient* c, const std::string& name, bool stopped, double wall_s,
                    ExitCode& code);

/// The stderr line of a bot whose outcome is `code`, if it gave up: refused
/// or its connection lost for good. Its name, why (the close code's name
/// and number, the client's reason) and, for codes that have one, what to
/// do; "" for other outcomes.
std::string give_up_line(const std::string& name, ExitCode code, std::uint16_t close_code,
                         const std::string& reason);

inline constexpr const char* kExitCodesHelp =
    "Exit codes: 0 every bot finished; 1 a bot did not finish its race; 2 bad arguments (or a track it does not "
    "have); 3 refused by the server; 4 connection lost; 5 the server said goodbye (shut down, drained, lobby "
    "cancelled); 6 stopped by --max-seconds or SIGTERM/SIGINT.";

}  // namespace jetrace::bot
