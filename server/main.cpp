// jetrace-server: a dedicated authoritative race server over ENet/UDP.
#include "jetrace/auth/key_file.hpp"
#include "jetrace/cli/logging.hpp"
#include "jetrace/net/transport.hpp"
#include "jetrace/server/race_server.hpp"
#include "jetrace/server/tick_times.hpp"
#include "jetrace/track_io.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

namespace {

std::atomic<int> g_signal{0};
void on_signal(int sig) { g_signal = sig; }

// --sign-key: the secret key that signs each replay (not the connect-token key).
bool load_sign_key(const std::string& path, const std::string& record_path, jetrace::server::ServerConfig& cfg) {
    if (path.empty()) return true;
    std::string error;
    jetrace::auth::LoadedKey key;
    if (record_path.empty()) {
        error = "--sign-key needs --record";
    } else if (jetrace::auth::load_key_file(path, key, error) && !key.has_secret) {
        error = "--sign-key needs a secret key file (jetrace-token keygen's FILE, not FILE.pub)";
    }
    if (!error.empty()) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return false;
    }
    cfg.replay_sign_key = key.secret;
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-server: hosts hovercar races over UDP (ENet)"};
    jetrace::server::ServerConfig cfg;
    jetrace::net::ServerConfig net_cfg;
    net_cfg.port = 27910;
    std::string track_spec = "stadium";
    std::string log_level = "info";
    int tick_rate = 120;
    double time_scale = 1.0;
    double hello_timeout_s = 5.0;
    std::string key_file;
    std::string sign_key_file;
    app.add_option("--port", net_cfg.port, "UDP port (0: any free port, printed at start)");
    app.add_option("--bind", net_cfg.bind, "address to bind");
    app.add_option("--track", track_spec, "built-in track (stadium, ring) or a Wavefront .obj file");
    app.add_option("--laps", cfg.laps, "laps per race")->check(CLI::Range(1, 1000));
    app.add_option("--max-players", cfg.max_players, "most players in a race")->check(CLI::Range(1, 64));
    app.add_option("--min-players", cfg.min_players, "players needed to start the countdown")->check(CLI::Range(1, 64));
    app.add_option("--tick-rate", tick_rate, "simulation steps per second")->check(CLI::Range(10, 1000));
    app.add_option("--snapshot-rate", cfg.snapshot_rate_hz, "snapshots per second (divides the tick rate)")
        ->check(CLI::Range(1, 1000));
    app.add_option("--races", cfg.races, "exit after this many races (0: host forever)")->check(CLI::Range(0, 1000000));
    app.add_option("--countdown", cfg.countdown_s, "countdown before each race (s)")->check(CLI::Range(0.0, 600.0));
    app.add_option("--finish-window", cfg.finish_window_s, "time the others get after the winner finishes (s)")
        ->check(CLI::Range(1.0, 3600.0));
    app.add_option("--reconnect-grace", cfg.reconnect_grace_s,
                   "how long a dropped player's slot and car wait for its reconnect (s; 0: none)")
        ->check(CLI::Range(0.0, 3600.0));
    app.add_option("--hello-timeout", hello_timeout_s,
                   "drop a connection that has not said Hello after this long (s of real time, whatever --time-scale)")
        ->check(CLI::Range(0.1, 600.0));
    net_cfg.max_pending_per_address = 4;
    app.add_option("--pre-hello-limit", net_cfg.max_pending_per_address,
                   "most connections one IP address may hold before their Hello; further requests are dropped "
                   "(0: no limit)")
        ->check(CLI::Range(0, 1000));
    app.add_option("--key-file", key_file,
                   "private race: admit only connect tokens signed with this key (jetrace-token keygen's FILE.pub)");
    app.add_option("--race-id", cfg.race_id, "private race: connect tokens must name this race (default: none)");
    app.add_option("--results", cfg.results_path, "results JSON file, written atomically at each race's end");
    app.add_option("--record", cfg.record_path, "replay file of the race (jetrace-sim --verify checks it)");
    app.add_option("--sign-key", sign_key_file,
                   "sign each replay with this secret key (jetrace-token keygen's FILE; keep it apart from --key-file's)");
    jetrace::cli::add_log_level_option(app, log_level);
    app.add_option("--time-scale", time_scale, "run the clock this many times faster than real time (tests)")
        ->check(CLI::Range(0.01, 100.0));
    CLI11_PARSE(app, argc, argv);
    // The hello timeout waits on the network, whose retransmissions (ENet's)
    // run in real time: on the server's scaled clock it is that many times
    // longer. Unscaled, a Hello retransmitted once by a client at --time-scale
    // 4 could miss it (1.25 s of real time) and the race would wait forever
    // for that player.
    cfg.hello_timeout_s = hello_timeout_s * time_scale;
    jetrace::cli::log_to_stderr("server", log_level);

    std::string error;
    if (!load_sign_key(sign_key_file, cfg.record_path, cfg)) return 2;
    if (!key_file.empty()) {
        jetrace::auth::LoadedKey key;
        if (!jetrace::auth::load_key_file(key_file, key, error)) {
            std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
            return 2;
        }
        if (key.has_secret) spdlog::warn("--key-file holds a secret key: the server needs only its .pub file");
        cfg.connect_key = key.public_key;
    } else if (!cfg.race_id.empty()) {
        std::fprintf(stderr, "jetrace-server: --race-id needs --key-file\n");
        return 2;
    }
    jetrace::Track track;
    if (!jetrace::load_track(track_spec, track, error)) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return 2;
    }
    jetrace::PhysicsSettings physics;
    physics.tick_rate_hz = tick_rate;
    if (const std::string e = jetrace::validate(physics); !e.empty()) {
        std::fprintf(stderr, "jetrace-server: %s\n", e.c_str());
        return 2;
    }
    if (const std::string e = jetrace::server::validate(cfg, tick_rate); !e.empty()) {
        std::fprintf(stderr, "jetrace-server: %s\n", e.c_str());
        return 2;
    }
    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), physics);
    net_cfg.max_connections = static_cast<std::size_t>(cfg.max_players) + 8;  // room to refuse politely
    auto transport = jetrace::net::listen_enet(net_cfg, error);
    if (!transport) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return 1;
    }
    std::printf("listening on %s:%u\n", net_cfg.bind.c_str(), transport->local_port());
    if (cfg.connect_key) spdlog::info("private race: only players with a connect token signed with the key get in");
    std::fflush(stdout);

    jetrace::server::RaceServer server(cfg, scene, *transport);
    server.on_race_end = [](const jetrace::server::RaceEnd& end) {
        std::printf("race %u finished after %u ticks\n", end.race_number, end.ticks);
        int pos = 1;
        for (const auto& s : end.standings) {
            std::printf("  %2d. %-16s %s lap %u %.3f s\n", pos++, s.name.c_str(), s.finished ? "finished" : "dnf     ",
                        s.lap, s.finish_time_s);
        }
        std::printf("state_hash=%s\n", jetrace::hash_hex(end.state_hash).c_str());
        std::fflush(stdout);
    };
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);

    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const auto now_us = [&] {
        return static_cast<std::uint64_t>(std::chrono::duration<double, std::micro>(Clock::now() - start).count() *
                                          time_scale);
    };
    jetrace::server::TickTimes tick_ms;
    while (!server.done()) {
        if (g_signal != 0) {
            server.shutdown(g_signal == SIGINT ? "server interrupted" : "server terminated");
            break;
        }
        const auto t0 = Clock::now();
        // Connect tokens expire by the wall clock, whatever the time scale.
        const auto unix_s = std::chrono::duration_cast<std::chrono::seconds>(
                                std::chrono::system_clock::now().time_since_epoch())
                                .count();
        const int ticks = server.update(now_us(), static_cast<std::int64_t>(unix_s));
        if (ticks > 0) {
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / ticks;
            tick_ms.add(ms, static_cast<std::uint64_t>(ticks));
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    // Let goodbyes leave.
    std::vector<jetrace::net::Event> ignored;
    for (int i = 0; i < 20; ++i) {
        transport->service(now_us() / 1000, ignored);
        transport->flush();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    // Rates per simulated second (wall time scaled by --time-scale).
    const double wall_s = std::chrono::duration<double>(Clock::now() - start).count() * time_scale;
    const auto totals = transport->totals();
    nlohmann::json j;
    j["races"] = server.races_completed();
    j["ticks"] = server.ticks();
    j["tick_ms_median"] = tick_ms.percentile(0.5);
    j["tick_ms_p99"] = tick_ms.percentile(0.99);
    j["max_players"] = server.max_players_seen();
    j["bytes_sent_per_s"] = static_cast<double>(totals.bytes_sent) / wall_s;
    j["bytes_received_per_s"] = static_cast<double>(totals.bytes_received) / wall_s;
    j["wall_s"] = wall_s;
    j["replay_failures"] = server.replay_failures();
    std::printf("%s\n", j.dump().c_str());
    // A replay that could not be written whole is a lost result.
    return server.replay_failures() == 0 ? 0 : 1;
}
