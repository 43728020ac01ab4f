#include "bot_options.hpp"

#include "bot_report.hpp"

#include "jetrace/auth/connect_token.hpp"
#include "jetrace/cli/finite.hpp"
#include "jetrace/cli/logging.hpp"
#include "jetrace/net/address.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/client/scene_choice.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>

namespace jetrace::bot {

namespace {

/// Most connect tokens read (one bot each).
constexpr std::size_t kMaxTokens = 64;

/// Reads connect tokens (text form) from --token values and a --token-file
/// (one a line; blank lines and lines starting with # skipped). False with
/// a message on an unreadable file or a token that does not parse.
bool read_tokens(const std::vector<std::string>& given, const std::string& file,
                 std::vector<std::vector<std::uint8_t>>& out, std::string& error) {
    std::vector<std::string> texts = given;
    if (!file.empty()) {
        std::ifstream in(file);
        if (!in) {
            error = "cannot read token file '" + file + "'";
            return false;
        }
        std::string line;
        while (std::getline(in, line) && texts.size() <= kMaxTokens) {
            if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
            texts.push_back(line);
        }
    }
    for (const std::string& t : texts) {
        const auto bytes = auth::from_text(t, auth::kMaxTokenBytes);
        std::string why = "not base64url text";
        if (bytes && auth::parse_connect_token(*bytes, &why)) {
            out.push_back(*bytes);
            continue;
        }
        error = "connect token " + std::to_string(out.size() + 1) + " is malformed: " + why;
        return false;
    }
    return true;
}

void add_options(CLI::App& app, BotOptions& o) {
    app.add_option("--connect", o.connects, "server address HOST:PORT; repeated: bot i joins the (i mod N)-th")
        ->required()->expected(1, 8);
    app.add_option("--count", o.count, "number of bots")->check(CLI::Range(1, 256));
    app.add_flag("--thin", o.thin,
                 "thin bots: no prediction, each drives on the newest snapshot (load tests; cheaper per bot)");
    app.add_option("--name", o.prefix, "name prefix (bots are PREFIX0, PREFIX1, ...)");
    app.add_option("--races", o.races, "leave after this many races")->check(CLI::Range(1, 1000000));
    app.add_option("--track", o.track_spec,
                   "the track file the server uses (optional: built-in tracks are found by name, and a track the bot "
                   "lacks is downloaded from the server)");
    app.add_option("--seed", o.seed, "seed for the drivers' skills");
    cli::add_log_level_option(app, o.log_level);
    app.add_option("--time-scale", o.time_scale, "run the clock this many times faster than real time (tests)")
        ->check(cli::finite())->check(CLI::Range(0.01, 100.0));
    app.add_option("--max-seconds", o.max_seconds, "give up after this many wall-clock seconds")
        ->check(cli::finite())->check(CLI::Range(1.0, 1e7));
    app.add_option("--target-margin", o.target_margin,
                   "ticks early the bots aim for their inputs to reach the server, on top of the jitter allowance")
        ->check(cli::finite())->check(CLI::Range(0.0, 30.0));
    app.add_option("--input-delay", o.input_delay,
                   "ticks between the tick a bot's driver decides an input at and the tick it is for (sent at once, "
                   "so the other bots' predictions know it)")
        ->check(CLI::Range(std::uint32_t{0}, client::kMaxInputDelayTicks));
    app.add_option("--join-window", o.join_window_s,
                   "if the server cannot be reached or its pre-Hello cap refuses a connection, keep trying to join "
                   "this long (s; 0: never)")
        ->check(cli::finite())->check(CLI::Range(0.0, 3600.0));
    app.add_option("--join-limit", o.join_limit,
                   "bots of one --connect address joining at a time (connection opened, no Welcome yet); the next "
                   "connects when one is welcomed or gives up. Must not exceed the server's --pre-hello-limit "
                   "(default 4), which refuses further connections from one address")
        ->check(CLI::Range(1, 1000));
    app.add_option("--reconnect-grace", o.reconnect_grace_s,
                   "after a drop, try to get the car back this long (s; the server's --reconnect-grace; 0: never)")
        ->check(cli::finite())->check(CLI::Range(0.0, 3600.0));
    app.add_option("--token", o.token_texts,
                   "connect token of a private race (jetrace-token issue); one per bot, which takes its name")
        ->expected(1, 64);
    app.add_option("--token-file", o.token_file, "file of connect tokens, one a line (with --token: after those)");
}

/// False with a message printed.
bool check_tokens(BotOptions& o, bool count_given) {
    std::string error;
    if (!read_tokens(o.token_texts, o.token_file, o.tokens, error)) {
        std::fprintf(stderr, "jetrace-bot: %s\n", error.c_str());
        return false;
    }
    if (o.tokens.empty()) return true;
    // Each bot presents its own token (a token admits once) under its name.
    if (count_given && static_cast<std::size_t>(o.count) != o.tokens.size()) {
        std::fprintf(stderr, "jetrace-bot: --count %d but %zu connect tokens: one per bot\n", o.count, o.tokens.size());
        return false;
    }
    if (o.addresses.size() > 1) {
        std::fprintf(stderr, "jetrace-bot: connect tokens admit to one private race: one --connect\n");
        return false;
    }
    if (o.tokens.size() > kMaxTokens) {
        std::fprintf(stderr, "jetrace-bot: more than 64 connect tokens\n");
        return false;
    }
    o.count = static_cast<int>(o.tokens.size());
    return true;
}

}  // namespace

int parse_options(int argc, char** argv, BotOptions& o) {
    CLI::App app{"jetrace-bot: AI drivers that connect to a jetrace server"};
    app.footer(kExitCodesHelp);
    add_options(app, o);
    CLI11_PARSE(app, argc, argv);
    cli::log_to_stderr("bot", o.log_level);  // stdout carries only the bots' JSON lines
    if (!proto::valid_text(o.prefix) || o.prefix.size() + 2 > proto::kMaxNameBytes) {
        std::fprintf(stderr, "jetrace-bot: --name must be valid UTF-8 text of at most %zu bytes\n",
                     proto::kMaxNameBytes - 2);
        return kBadArguments;
    }
    for (const std::string& connect : o.connects) {
        Address a;
        if (!net::split_host_port(connect, a.host, a.port)) {
            std::fprintf(stderr, "jetrace-bot: --connect must be HOST:PORT, got '%s'\n", connect.c_str());
            return kBadArguments;
        }
        o.addresses.push_back(a);
    }
    if (!check_tokens(o, app.count("--count") > 0)) return kBadArguments;
    return -1;
}

bool load_scenes(const std::string& track_spec, std::vector<std::unique_ptr<Scene>>& out) {
    std::string error;
    if (client::load_known_scenes(track_spec, out, error)) return true;
    std::fprintf(stderr, "jetrace-bot: %s\n", error.c_str());
    return false;
}

}  // namespace jetrace::bot
