// jetrace-bot: K AI drivers, each its own client and ENet connection. A
// dropped bot reconnects to its car within --reconnect-grace; with connect
// tokens (--token, --token-file) it joins a private race. The server's
// Welcome names its track; each bot races on the built-in track (or the
// --track file) with the same identity.
#include "bot_options.hpp"
#include "bot_report.hpp"

#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/auth/connect_token.hpp"
#include "jetrace/client/race_client.hpp"

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <thread>

namespace {

using jetrace::bot::BotOptions;
using jetrace::client::ClientState;
using Clock = std::chrono::steady_clock;

std::atomic<int> g_signal{0};
void on_signal(int sig) { g_signal = sig; }

struct Bot {
    std::unique_ptr<jetrace::client::RaceClient> client;
    std::string name;
    jetrace::DriverSkill skill;
    jetrace::CourseCache course;  // the AI's view of the scene the client races on
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

/// False (a message printed) if a bot cannot open its connection.
bool make_bots(const BotOptions& o, const jetrace::client::KnownScenes& known, std::vector<Bot>& bots) {
    const auto skills = jetrace::skills_for(o.count, o.seed);
    for (int i = 0; i < o.count; ++i) {
        Bot b;
        b.skill = skills[static_cast<std::size_t>(i)];
        const jetrace::client::ClientConfig cc = config_for(o, i, b.name);
        const jetrace::bot::Address& to = o.addresses[static_cast<std::size_t>(i) % o.addresses.size()];
        b.client = std::make_unique<jetrace::client::RaceClient>(cc, known, [to] {
            std::string e;
            auto t = jetrace::net::connect_enet(to.host, to.port, 5000, e);
            if (!t) spdlog::error("cannot connect: {}", e);
            return t;
        });
        if (b.client->state() == ClientState::closed) {
            std::fprintf(stderr, "jetrace-bot: cannot open a connection to %s:%u\n", to.host.c_str(),
                         static_cast<unsigned>(to.port));
            return false;
        }
        bots.push_back(std::move(b));
    }
    return true;
}

/// Runs the bots until each is done, --max-seconds or a signal; true if
/// stopped (the bots not done then left).
bool run(const BotOptions& o, std::vector<Bot>& bots, Clock::time_point start) {
    const auto now_us = [&] {
        return static_cast<std::uint64_t>(std::chrono::duration<double, std::micro>(Clock::now() - start).count() *
                                          o.time_scale);
    };
    std::size_t done = 0;
    while (done < bots.size()) {
        const std::uint64_t t = now_us();
        // Every bot's due ticks and inputs first, then the network and the
        // reconciliations: no input waits for the other bots' replays.
        for (Bot& b : bots) {
            if (b.done) continue;
            const auto skill = b.skill;
            b.client->run_due(t, [&](const jetrace::Scene& sc, const jetrace::WorldState& w, int slot) {
                return jetrace::drive(b.course(sc), w, slot, skill);
            });
        }
        for (Bot& b : bots) {
            if (b.done) continue;
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
                if (!b.done) b.client->leave(why);
            }
            return true;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    return false;
}

/// Prints the refusals and mismatches (stderr) and each bot's line (stdout);
/// returns the exit code.
int report(const BotOptions& o, const std::vector<Bot>& bots, bool stopped, double wall_s) {
    for (const Bot& b : bots) {
        const std::string& why = b.client->close_reason();
        const std::uint16_t code = b.client->close_code();
        if (jetrace::proto::close_class(code) == jetrace::proto::CloseClass::refused)
            std::fprintf(stderr, "jetrace-bot: %s: %s\n", b.name.c_str(), why.c_str());
        if (code == static_cast<std::uint16_t>(jetrace::proto::CloseCode::local_incompatible) ||
            code == static_cast<std::uint16_t>(jetrace::proto::CloseCode::local_bad_track)) {
            std::fprintf(stderr, "jetrace-bot: %s%s\n", why.c_str(),
                         o.track_spec.empty() ? " (pass --track with the server's track file)" : "");
        }
    }
    auto rc = jetrace::bot::kFinished;
    for (const Bot& b : bots) {
        jetrace::bot::ExitCode code{};
        jetrace::bot::print_bot_line(*b.client, b.name, stopped && !b.done, wall_s, code);
        rc = jetrace::bot::combine(rc, code);
    }
    std::fflush(stdout);
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
    std::vector<Bot> bots;
    const auto start = Clock::now();
    if (!make_bots(o, known, bots)) return jetrace::bot::kLostConnection;
    std::signal(SIGTERM, on_signal);
    std::signal(SIGINT, on_signal);
    const bool stopped = run(o, bots, start);
    // Rates per simulated second (wall time scaled by --time-scale).
    const double wall_s = std::chrono::duration<double>(Clock::now() - start).count() * o.time_scale;
    return report(o, bots, stopped, wall_s);
}
