// jetrace-server: a dedicated authoritative race server over ENet/UDP.
#include "options.hpp"

#include "jetrace/net/transport.hpp"
#include "jetrace/server/host_files.hpp"
#include "jetrace/server/race_server.hpp"
#include "jetrace/server/tick_times.hpp"
#include "jetrace/track_io.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

namespace {

using namespace jetrace;

std::atomic<int> g_signals{0};
std::atomic<int> g_last_signal{0};
void on_signal(int sig) {
    g_last_signal = sig;
    g_signals.fetch_add(1);
}

const char* signal_reason(int sig) {
    return sig == SIGINT ? "server interrupted" : sig == SIGHUP ? "server hung up" : "server terminated";
}

/// Files lost (each logged with what): a non-zero exit.
struct Losses {
    std::uint32_t results = 0;
    std::uint32_t nonces = 0;
};

void print_race_end(const server::RaceEnd& end) {
    std::printf("race %u finished after %u ticks (%s)\n", end.race_number, end.ticks,
                replay::end_reason_name(end.reason));
    int pos = 1;
    for (const auto& s : end.standings) {
        std::printf("  %2d. %-16s %s lap %u %.3f s\n", pos++, s.name.c_str(), s.finished ? "finished" : "dnf     ",
                    s.lap, s.finish_time_s);
    }
    std::printf("state_hash=%s\n", hash_hex(end.state_hash).c_str());
    std::fflush(stdout);
}

void attach_files(server::RaceServer& srv, const server::HostOptions& o, const std::string& track, Losses& lost) {
    srv.on_race_end = [&o, track, &lost](const server::RaceEnd& end) {
        print_race_end(end);
        std::string error;
        if (!o.results_path.empty() && !server::write_results(o.results_path, end, track, o.cfg.laps, error)) {
            ++lost.results;
            spdlog::error("{}", error);
        }
    };
    if (o.nonce_file.empty()) return;
    srv.on_nonce_spent = [&o, &lost](const auth::TokenVerifier& v) {
        std::string error;
        if (!server::save_nonce_file(o.nonce_file, v.spent(), error)) {
            ++lost.nonces;
            spdlog::error("spent connect-token nonces not saved (a restart would accept those tokens again): {}", error);
        }
    };
}

/// Runs until the server is done; signals drain it, a second one stops it.
void run(server::RaceServer& srv, net::Transport& transport, const server::HostOptions& o,
         server::TickTimes& tick_ms, const std::function<std::uint64_t()>& now_us) {
    using Clock = std::chrono::steady_clock;
    int handled = 0;
    while (!srv.done()) {
        const int signals = g_signals.load();
        if (signals > handled) {
            handled = signals;
            srv.drain(signal_reason(g_last_signal), o.drain_timeout_s * o.time_scale);
        }
        const auto t0 = Clock::now();
        // Connect tokens expire by the wall clock, whatever the time scale.
        const auto unix_s = std::chrono::duration_cast<std::chrono::seconds>(
                                std::chrono::system_clock::now().time_since_epoch()).count();
        const int ticks = srv.update(now_us(), static_cast<std::int64_t>(unix_s));
        if (ticks > 0) {
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / ticks;
            tick_ms.add(ms, static_cast<std::uint64_t>(ticks));
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    // Let goodbyes leave.
    std::vector<net::Event> ignored;
    for (int i = 0; i < 20; ++i) {
        transport.service(now_us() / 1000, ignored);
        transport.flush();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

}  // namespace

int main(int argc, char** argv) {
    server::HostOptions o;
    if (const int rc = server::parse_host_options(argc, argv, o); rc >= 0) return rc;
    if (!server::prepare_host(o)) return 2;
    std::string error;
    Track track;
    if (!load_track(o.track_spec, track, error)) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return 2;
    }
    PhysicsSettings physics;
    physics.tick_rate_hz = o.tick_rate;
    std::string invalid = validate(physics);
    if (invalid.empty()) invalid = server::validate(o.cfg, o.tick_rate);
    if (!invalid.empty()) {
        std::fprintf(stderr, "jetrace-server: %s\n", invalid.c_str());
        return 2;
    }
    const Scene scene = Scene::make(std::move(track), physics);
    o.net_cfg.max_connections = static_cast<std::size_t>(o.cfg.max_players) + 8;  // room to refuse politely
    auto transport = net::listen_enet(o.net_cfg, error);
    if (!transport) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return 1;
    }
    std::printf("listening on %s:%u\n", o.net_cfg.bind.c_str(), transport->local_port());
    if (o.cfg.connect_key) spdlog::info("private race: only players with a connect token signed with the key get in");
    std::fflush(stdout);

    server::RaceServer srv(o.cfg, scene, *transport);
    Losses lost;
    attach_files(srv, o, scene.track.name, lost);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, on_signal);

    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const auto now_us = [&] {
        return static_cast<std::uint64_t>(std::chrono::duration<double, std::micro>(Clock::now() - start).count() *
                                          o.time_scale);
    };
    server::TickTimes tick_ms;
    run(srv, *transport, o, tick_ms, now_us);
    // Rates per simulated second (wall time scaled by --time-scale).
    const double wall_s = std::chrono::duration<double>(Clock::now() - start).count() * o.time_scale;
    const auto totals = transport->totals();
    nlohmann::json j;
    j["races"] = srv.races_completed();
    j["ticks"] = srv.ticks();
    j["tick_ms_median"] = tick_ms.percentile(0.5);
    j["tick_ms_p99"] = tick_ms.percentile(0.99);
    j["max_players"] = srv.max_players_seen();
    j["bytes_sent_per_s"] = static_cast<double>(totals.bytes_sent) / wall_s;
    j["bytes_received_per_s"] = static_cast<double>(totals.bytes_received) / wall_s;
    j["wall_s"] = wall_s;
    j["replay_failures"] = srv.replay_failures();
    j["results_failures"] = lost.results;
    j["nonce_failures"] = lost.nonces;
    std::printf("%s\n", j.dump().c_str());
    // A replay, results or nonce table that could not be written is lost data.
    return srv.replay_failures() + lost.results + lost.nonces == 0 ? 0 : 1;
}
