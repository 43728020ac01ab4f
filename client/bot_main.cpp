// jetrace-bot: K AI drivers, each its own client and ENet connection. A
// dropped bot reconnects to its car within --reconnect-grace; with connect
// tokens (--token, --token-file) it joins a private race. The server's
// Welcome names its track; each bot races on the built-in track (or the
// --track file) with the same identity.
#include "bot_report.hpp"

#include "jetrace/auth/connect_token.hpp"
#include "jetrace/builtin_tracks.hpp"
#include "jetrace/cli/finite.hpp"
#include "jetrace/cli/logging.hpp"
#include "jetrace/client/race_client.hpp"
#include "jetrace/driver_ai.hpp"
#include "jetrace/net/address.hpp"
#include "jetrace/offline_race.hpp"
#include "jetrace/track_io.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <memory>
#include <thread>

namespace {

std::atomic<int> g_signal{0};
void on_signal(int sig) { g_signal = sig; }

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
        while (std::getline(in, line) && texts.size() <= 64) {
            if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
            texts.push_back(line);
        }
    }
    for (const std::string& t : texts) {
        const auto bytes = jetrace::auth::from_text(t, jetrace::auth::kMaxTokenBytes);
        std::string why = "not base64url text";
        if (bytes && jetrace::auth::parse_connect_token(*bytes, &why)) {
            out.push_back(*bytes);
            continue;
        }
        error = "connect token " + std::to_string(out.size() + 1) + " is malformed: " + why;
        return false;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-bot: AI drivers that connect to a jetrace server"};
    app.footer(jetrace::bot::kExitCodesHelp);
    std::vector<std::string> connects;
    int count = 1;
    bool thin = false;
    std::string prefix = "bot";
    int races = 1;
    std::string track_spec;
    std::string log_level = "warn";
    double time_scale = 1.0;
    double max_seconds = 3600;
    std::uint64_t seed = 1;
    double reconnect_grace_s = 10.0;
    double join_window_s = 10.0;
    double target_margin = jetrace::client::ClientConfig{}.target_margin_ticks;
    std::vector<std::string> token_texts;
    std::string token_file;
    app.add_option("--connect", connects, "server address HOST:PORT; repeated: bot i joins the (i mod N)-th")
        ->required()->expected(1, 8);
    auto* count_opt = app.add_option("--count", count, "number of bots")->check(CLI::Range(1, 256));
    app.add_flag("--thin", thin,
                 "thin bots: no prediction, each drives on the newest snapshot (load tests; cheaper per bot)");
    app.add_option("--name", prefix, "name prefix (bots are PREFIX0, PREFIX1, ...)");
    app.add_option("--races", races, "leave after this many races")->check(CLI::Range(1, 1000000));
    app.add_option("--track", track_spec, "the .obj file the server uses (built-in tracks are found by name)");
    app.add_option("--seed", seed, "seed for the drivers' skills");
    jetrace::cli::add_log_level_option(app, log_level);
    app.add_option("--time-scale", time_scale, "run the clock this many times faster than real time (tests)")
        ->check(jetrace::cli::finite())->check(CLI::Range(0.01, 100.0));
    app.add_option("--max-seconds", max_seconds, "give up after this many wall-clock seconds")
        ->check(jetrace::cli::finite())->check(CLI::Range(1.0, 1e7));
    app.add_option("--target-margin", target_margin,
                   "ticks early the bots aim for their inputs to reach the server, on top of the jitter allowance")
        ->check(jetrace::cli::finite())->check(CLI::Range(0.0, 30.0));
    app.add_option("--join-window", join_window_s,
                   "if the server cannot be reached, keep trying to join this long (s; 0: never)")
        ->check(jetrace::cli::finite())->check(CLI::Range(0.0, 3600.0));
    app.add_option("--reconnect-grace", reconnect_grace_s,
                   "after a drop, try to get the car back this long (s; the server's --reconnect-grace; 0: never)")
        ->check(jetrace::cli::finite())->check(CLI::Range(0.0, 3600.0));
    app.add_option("--token", token_texts,
                   "connect token of a private race (jetrace-token issue); one per bot, which takes its name")
        ->expected(1, 64);
    app.add_option("--token-file", token_file, "file of connect tokens, one a line (with --token: after those)");
    CLI11_PARSE(app, argc, argv);
    jetrace::cli::log_to_stderr("bot", log_level);  // stdout carries only the bots' JSON lines
    if (!jetrace::proto::valid_text(prefix) || prefix.size() + 2 > jetrace::proto::kMaxNameBytes) {
        std::fprintf(stderr, "jetrace-bot: --name must be valid UTF-8 text of at most %zu bytes\n",
                     jetrace::proto::kMaxNameBytes - 2);
        return 2;
    }

    struct Address {
        std::string host;
        std::uint16_t port = 0;
    };
    std::vector<Address> addresses;
    for (const std::string& connect : connects) {
        Address a;
        if (!jetrace::net::split_host_port(connect, a.host, a.port)) {
            std::fprintf(stderr, "jetrace-bot: --connect must be HOST:PORT, got '%s'\n", connect.c_str());
            return 2;
        }
        addresses.push_back(a);
    }
    std::vector<std::vector<std::uint8_t>> tokens;
    std::string error;
    if (!read_tokens(token_texts, token_file, tokens, error)) {
        std::fprintf(stderr, "jetrace-bot: %s\n", error.c_str());
        return 2;
    }
    if (!tokens.empty()) {
        // Each bot presents its own token (a token admits once) under its name.
        if (count_opt->count() > 0 && static_cast<std::size_t>(count) != tokens.size()) {
            std::fprintf(stderr, "jetrace-bot: --count %d but %zu connect tokens: one per bot\n", count, tokens.size());
            return 2;
        }
        if (addresses.size() > 1) {
            std::fprintf(stderr, "jetrace-bot: connect tokens admit to one private race: one --connect\n");
            return 2;
        }
        if (tokens.size() > 64) {
            std::fprintf(stderr, "jetrace-bot: more than 64 connect tokens\n");
            return 2;
        }
        count = static_cast<int>(tokens.size());
        if (track_spec.empty()) {
            // A bot admitted to a race on a track it does not know leaves,
            // and its token (which admits once) is spent.
            std::fprintf(stderr, "jetrace-bot: connect tokens need --track (the track the private race runs on)\n");
            return 2;
        }
    }

    // The server's Welcome names its track: a bot races on the built-in
    // track with the same identity, or on the --track file (only that one
    // when given, so that a bot never joins a race on another track).
    std::vector<std::unique_ptr<jetrace::Scene>> scenes;
    const jetrace::PhysicsSettings physics;
    if (!track_spec.empty()) {
        jetrace::Track t;
        if (!jetrace::load_track(track_spec, t, error)) {
            std::fprintf(stderr, "jetrace-bot: %s\n", error.c_str());
            return 2;
        }
        scenes.push_back(std::make_unique<jetrace::Scene>(jetrace::Scene::make(std::move(t), physics)));
    } else {
        for (const std::string& name : jetrace::builtin_track_names()) {
            jetrace::Track t;
            jetrace::make_builtin_track(name, t);
            scenes.push_back(std::make_unique<jetrace::Scene>(jetrace::Scene::make(std::move(t), physics)));
        }
    }
    jetrace::client::KnownScenes known;
    for (const auto& sc : scenes) known.push_back(sc.get());
    struct Bot {
        std::unique_ptr<jetrace::client::RaceClient> client;
        std::string name;
        jetrace::DriverSkill skill;
        bool done = false;
    };
    const auto skills = jetrace::skills_for(count, seed);
    std::vector<Bot> bots;
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const auto now_us = [&] {
        return static_cast<std::uint64_t>(std::chrono::duration<double, std::micro>(Clock::now() - start).count() *
                                          time_scale);
    };
    for (int i = 0; i < count; ++i) {
        Bot b;
        b.name = prefix + std::to_string(i);
        b.skill = skills[static_cast<std::size_t>(i)];
        jetrace::client::ClientConfig cc;
        if (!tokens.empty()) {
            cc.connect_token = tokens[static_cast<std::size_t>(i)];
            b.name = jetrace::auth::parse_connect_token(cc.connect_token)->name;
        }
        cc.name = b.name;
        cc.reconnect_window_s = reconnect_grace_s;
        // Real seconds: the bots' clock runs --time-scale times faster.
        cc.join_window_s = join_window_s * time_scale;
        cc.welcome_timeout_s *= time_scale;
        cc.predict = !thin;
        cc.target_margin_ticks = target_margin;
        const Address& to = addresses[static_cast<std::size_t>(i) % addresses.size()];
        b.client = std::make_unique<jetrace::client::RaceClient>(cc, known, [to] {
            std::string e;
            auto t = jetrace::net::connect_enet(to.host, to.port, 5000, e);
            if (!t) spdlog::error("cannot connect: {}", e);
            return t;
        });
        if (b.client->state() == jetrace::client::ClientState::closed) {
            std::fprintf(stderr, "jetrace-bot: cannot open a connection to %s:%u\n", to.host.c_str(),
                         static_cast<unsigned>(to.port));
            return jetrace::bot::kLostConnection;
        }
        bots.push_back(std::move(b));
    }
    std::signal(SIGTERM, on_signal);
    std::signal(SIGINT, on_signal);
    std::size_t done = 0;
    bool stopped = false;
    while (done < bots.size()) {
        const std::uint64_t t = now_us();
        for (Bot& b : bots) {
            if (b.done) continue;
            const auto skill = b.skill;
            b.client->update(t, [&](const jetrace::Scene& sc, const jetrace::WorldState& w, int slot) {
                return jetrace::drive(sc, w, slot, skill);
            });
            const bool finished_races = b.client->races_finished() >= static_cast<std::uint32_t>(races);
            if (finished_races) b.client->leave("done racing");
            if (finished_races || b.client->state() == jetrace::client::ClientState::closed) {
                b.done = true;
                ++done;
            }
        }
        const bool out_of_time = std::chrono::duration<double>(Clock::now() - start).count() > max_seconds;
        if (done < bots.size() && (out_of_time || g_signal != 0)) {
            // Say goodbye, so that the server frees the slots at once.
            const std::string why = g_signal != 0 ? "bot stopped by a signal" : "bot gave up (--max-seconds)";
            for (Bot& b : bots) {
                if (!b.done) b.client->leave(why);
            }
            stopped = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    for (const Bot& b : bots) {
        const std::string& why = b.client->close_reason();
        const std::uint16_t code = b.client->close_code();
        if (jetrace::proto::close_class(code) == jetrace::proto::CloseClass::refused)
            std::fprintf(stderr, "jetrace-bot: %s: %s\n", b.name.c_str(), why.c_str());
        if (code == static_cast<std::uint16_t>(jetrace::proto::CloseCode::local_incompatible)) {
            std::fprintf(stderr, "jetrace-bot: %s%s\n", why.c_str(),
                         track_spec.empty() ? " (not a built-in track: pass --track FILE.obj)" : "");
        }
    }
    // Rates per simulated second (wall time scaled by --time-scale).
    const double wall_s = std::chrono::duration<double>(Clock::now() - start).count() * time_scale;
    auto rc = jetrace::bot::kFinished;
    for (Bot& b : bots) {
        jetrace::bot::ExitCode code{};
        jetrace::bot::print_bot_line(*b.client, b.name, stopped && !b.done, wall_s, code);
        rc = jetrace::bot::combine(rc, code);
    }
    std::fflush(stdout);
    return rc;
}
