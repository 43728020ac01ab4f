// jetrace-bot: K AI drivers, each its own client and ENet connection. The
// bots of one server address join --join-limit at a time (join_pacing.hpp),
// within the server's pre-Hello cap. A dropped bot reconnects to its car
// within --reconnect-grace; with connect tokens (--token, --token-file) it
// joins a private race. The server's Welcome names its track; each bot races
// on the built-in track (or the --track file) with the same identity.
#include "bot_options.hpp"
#include "bot_report.hpp"
#include "join_pacing.hpp"

#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/ai/pilot.hpp"
#include "jetrace/auth/connect_token.hpp"
#include "jetrace/client/race_client.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace {

using jetrace::bot::BotOptions;
using jetrace::client::ClientState;
using Clock = std::chrono::steady_clock;

std::atomic<int> g_signal{0};
void on_signal(int sig) { g_signal = sig; }

struct Bot {
    /// nullptr until its turn to join comes (join_pacing.hpp).
    std::unique_ptr<jetrace::client::RaceClient> client;
    std::string name;
    jetrace::Pilot pilot;  // its AI: skill, course of the scene the client races on, held input
    jetrace::client::ClientConfig config;
    /// Its server: BotOptions::addresses[address].
    std::size_t address = 0;
    bool done = false;
};

jetrace::client::ClientConfig config_for(const BotOptions& o, int i, std::string& name) {
    jetrace::client::ClientConfig cc;
    name = o.prefix + std::to_string(i);
    if (!o.tokens.empty()) {
        cc.connect_token = o.tokens[static_cast<std::size_t>(i)];
        name = jetrace::auth::parse_connect_token(cc.connect_token)->name;
    }
    cc.name = name;
    cc.reconnect_window_s = o.reconnect_grace_s;
    // Real seconds: the bots' clock runs --time-scale times faster.
    cc.join_window_s = o.join_window_s * o.time_scale;
    cc.welcome_timeout_s *= o.time_scale;
    cc.predict = !o.thin;
    cc.target_margin_ticks = o.target_margin;
    cc.input_delay_ticks = o.input_delay;
    return cc;
}

/// The bots, none connected yet.
std::vector<Bot> make_bots(const BotOptions& o) {
    const auto skills = jetrace::skills_for(o.count, o.seed);
    std::vector<Bot> bots;
    for (int i = 0; i < o.count; ++i) {
        Bot b;
        b.pilot = jetrace::Pilot(skills[static_cast<std::size_t>(i)]);
        b.config = config_for(o, i, b.name);
        b.address = static_cast<std::size_t>(i) % o.addresses.size();
        bots.push_back(std::move(b));
    }
    return bots;
}

jetrace::bot::JoinPhase phase_of(const Bot& b) {
    using jetrace::bot::JoinPhase;
    if (!b.client) return JoinPhase::waiting;
    if (b.done) return JoinPhase::through;
    switch (b.client->state()) {
        case ClientState::connecting:
        case ClientState::waiting_welcome:
        case ClientState::reconnecting: return JoinPhase::joining;
        default: return JoinPhase::through;
    }
}

/// Opens the connections of the waiting bots whose turn has come; a bot
/// that cannot open one is done (a message printed).
void start_due(const BotOptions& o, const jetrace::client::KnownScenes& known, std::vector<Bot>& bots,
               std::size_t& done) {
    std::vector<jetrace::bot::JoinPhase> phase;
    std::vector<std::size_t> address;
    for (const Bot& b : bots) {
        phase.push_back(phase_of(b));
        address.push_back(b.address);
    }
    for (const std::size_t i : jetrace::bot::bots_to_start(phase, address, o.addresses.size(), o.join_limit)) {
        Bot& b = bots[i];
        const jetrace::bot::Address to = o.addresses[b.address];
        b.client = std::make_unique<jetrace::client::RaceClient>(b.config, known, [to] {
            std::string e;
            auto t = jetrace::net::connect_enet(to.host, to.port, 5000, e);
            if (!t) spdlog::error("cannot connect: {}", e);
            return t;
        });
        if (b.client->state() != ClientState::closed) continue;
        std::fprintf(stderr, "jetrace-bot: %s: cannot open a connection to %s:%u\n", b.name.c_str(), to.host.c_str(),
                     static_cast<unsigned>(to.port));
        b.done = true;
        ++done;
    }
}

/// Runs the bots until each is done, --max-seconds or a signal; true if
/// stopped (the bots not done then left).
bool run(const BotOptions& o, const jetrace::client::KnownScenes& known, std::vector<Bot>& bots,
         Clock::time_point start) {
    const auto now_us = [&] {
        return static_cast<std::uint64_t>(std::chrono::duration<double, std::micro>(Clock::now() - start).count() *
                                          o.time_scale);
    };
    std::size_t done = 0;
    while (done < bots.size()) {
        start_due(o, known, bots, done);
        const std::uint64_t t = now_us();
        // Every bot's due ticks and inputs first, then the network and the
        // reconciliations: no input waits for the other bots' replays.
        for (Bot& b : bots) {
            if (b.done || !b.client) continue;
            b.client->run_due(t, std::ref(b.pilot));
        }
        for (Bot& b : bots) {
            if (b.done || !b.client) continue;
            b.client->receive(t);
            const bool finished_races = b.client->races_finished() >= static_cast<std::uint32_t>(o.races);
            if (finished_races) b.client->leave("done racing");
            if (finished_races || b.client->state() == ClientState::closed) {
                b.done = true;
                ++done;
            }
        }
        const bool out_of_time = std::chrono::duration<double>(Clock::now() - start).count() > o.max_seconds;
        if (done < bots.size() && (out_of_time || g_signal != 0)) {
            // Say goodbye, so that the server frees the slots at once.
            const std::string why = g_signal != 0 ? "bot stopped by a signal" : "bot gave up (--max-seconds)";
            for (Bot& b : bots) {
                if (!b.done && b.client) b.client->leave(why);
            }
            return true;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    return false;
}

/// Prints each bot's line (stdout), then why the bots that gave up did and
/// the track mismatches (stderr); returns the exit code.
int report(const BotOptions& o, const std::vector<Bot>& bots, bool stopped, double wall_s) {
    auto rc = jetrace::bot::kFinished;
    std::vector<std::string> problems;
    for (const Bot& b : bots) {
        jetrace::bot::ExitCode code{};
        jetrace::bot::print_bot_line(b.client.get(), b.name, stopped && !b.done, wall_s, code);
        rc = jetrace::bot::combine(rc, code);
        if (!b.client) continue;
        const std::string& why = b.client->close_reason();
        const std::uint16_t close = b.client->close_code();
        if (std::string line = jetrace::bot::give_up_line(b.name, code, close, why); !line.empty())
            problems.push_back(std::move(line));
        if (close == static_cast<std::uint16_t>(jetrace::proto::CloseCode::local_incompatible) ||
            close == static_cast<std::uint16_t>(jetrace::proto::CloseCode::local_bad_track)) {
            problems.push_back("jetrace-bot: " + why +
                               (o.track_spec.empty() ? " (pass --track with the server's track file)" : ""));
        }
    }
    std::fflush(stdout);
    for (const std::string& line : problems) std::fprintf(stderr, "%s\n", line.c_str());
    return rc;
}

}  // namespace

int main(int argc, char** argv) {
    BotOptions o;
    if (const int rc = jetrace::bot::parse_options(argc, argv, o); rc >= 0) return rc;
    // The server's Welcome names its track: a bot races on the built-in
    // track with the same identity, or on the --track file (only that one
    // when given, so that a bot never joins a race on another track).
    std::vector<std::unique_ptr<jetrace::Scene>> scenes;
    if (!jetrace::bot::load_scenes(o.track_spec, scenes)) return jetrace::bot::kBadArguments;
    jetrace::client::KnownScenes known;
    for (const auto& sc : scenes) known.push_back(sc.get());
    std::vector<Bot> bots = make_bots(o);
    const auto start = Clock::now();
    std::signal(SIGTERM, on_signal);
    std::signal(SIGINT, on_signal);
    const bool stopped = run(o, known, bots, start);
    // Rates per simulated second (wall time scaled by --time-scale).
    const double wall_s = std::chrono::duration<double>(Clock::now() - start).count() * o.time_scale;
    return report(o, bots, stopped, wall_s);
}
