// jetrace-server: a dedicated authoritative race server over ENet/UDP, with
// optional hosting around it (server/ops): the Agones SDK and metrics.
#include "options.hpp"

#include "jetrace/ops/metrics.hpp"
#include "jetrace/ops/unallocated_gate.hpp"
#include "jetrace/server/tick_times.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

namespace {

using jetrace::server_main::Options;
using Clock = std::chrono::steady_clock;

std::atomic<int> g_signal{0};
void on_signal(int sig) { g_signal = sig; }

/// What the server is hosted with: its socket, and the optional ops parts.
struct Host {
    std::unique_ptr<jetrace::net::Transport> transport;
    std::unique_ptr<jetrace::ops::Metrics> metrics;
    std::unique_ptr<jetrace::ops::AgonesClient> agones;
    Clock::time_point start = Clock::now();
    double time_scale = 1.0;
    std::uint64_t refused_unallocated = 0;

    /// The server's clock: wall time scaled by --time-scale (unit: µs).
    std::uint64_t now_us() const {
        return static_cast<std::uint64_t>(std::chrono::duration<double, std::micro>(Clock::now() - start).count() *
                                          time_scale);
    }
};

void print_race_end(const jetrace::server::RaceEnd& end) {
    std::printf("race %u finished after %u ticks\n", end.race_number, end.ticks);
    int pos = 1;
    for (const auto& s : end.standings) {
        std::printf("  %2d. %-16s %s lap %u %.3f s\n", pos++, s.name.c_str(), s.finished ? "finished" : "dnf     ",
                    s.lap, s.finish_time_s);
    }
    std::printf("state_hash=%s\n", jetrace::hash_hex(end.state_hash).c_str());
    std::fflush(stdout);
}

/// Binds the game port and the metrics port, prints them, starts Agones
/// (whose first call is Ready: the track is loaded and the ports bound).
bool open_host(const Options& o, Host& host) {
    std::string error;
    host.time_scale = o.time_scale;
    host.transport = jetrace::net::listen_enet(o.net_cfg, error);
    if (!host.transport) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return false;
    }
    std::printf("listening on %s:%u\n", o.net_cfg.bind.c_str(), host.transport->local_port());
    if (!o.metrics_host.empty()) {
        host.metrics = jetrace::ops::Metrics::serve(o.metrics_host, o.metrics_port, error);
        if (!host.metrics) {
            std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
            return false;
        }
        std::printf("metrics on %s:%d\n", o.metrics_host.c_str(), host.metrics->port());
        host.metrics->publish(jetrace::ops::MetricsSample{});
    }
    if (o.cfg.connect_key) spdlog::info("private race: only players with a connect token signed with the key get in");
    std::fflush(stdout);
    if (o.agones) {
        host.agones = std::make_unique<jetrace::ops::AgonesClient>(*o.agones);
        host.agones->start();
    }
    return true;
}

/// Until Agones allocates the server: refuse players, keep Health going.
/// 0 once allocated (race options applied), else the exit code.
int wait_for_allocation(const jetrace::Scene& scene, Options& o, Host& host) {
    // On the server's (scaled) clock, as RaceServer's hello timeout.
    jetrace::ops::UnallocatedGate gate(static_cast<std::uint64_t>(o.cfg.hello_timeout_s * 1000));
    spdlog::info("waiting for the Agones allocation (players are refused until then)");
    for (;;) {
        host.agones->heartbeat();
        gate.service(*host.transport, host.now_us() / 1000);
        if (host.metrics && gate.refused() != host.refused_unallocated) {
            host.refused_unallocated = gate.refused();
            jetrace::ops::MetricsSample s;
            s.refused_unallocated = host.refused_unallocated;
            s.traffic = host.transport->totals();
            host.metrics->publish(s);
        }
        if (g_signal != 0) {
            spdlog::info("server stopping before its allocation (signal {})", g_signal.load());
            return 0;
        }
        if (!host.agones->failure().empty()) return 1;
        if (const auto gs = host.agones->allocation()) {
            gate.close_all(*host.transport);
            std::string error;
            if (jetrace::server_main::apply_allocation(*gs, scene, o, error)) return 0;
            spdlog::error("bad allocation: {}; shutting down", error);
            return 2;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

/// Hosts races until the server is done; 1 if Agones was lost, else 0.
int run_races(jetrace::server::RaceServer& server, Host& host, jetrace::server::TickTimes& tick_ms) {
    int rc = 0;
    while (!server.done()) {
        if (g_signal != 0) {
            server.shutdown(g_signal == SIGINT ? "server interrupted" : "server terminated");
            break;
        }
        if (host.agones) {
            host.agones->heartbeat();
            if (!host.agones->failure().empty()) {
                server.shutdown("the server lost its Agones sidecar");
                rc = 1;
                break;
            }
        }
        const auto t0 = Clock::now();
        // Connect tokens expire by the wall clock, whatever the time scale.
        const auto unix_s = std::chrono::duration_cast<std::chrono::seconds>(
                                std::chrono::system_clock::now().time_since_epoch())
                                .count();
        const int ticks = server.update(host.now_us(), static_cast<std::int64_t>(unix_s));
        if (ticks > 0) {
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / ticks;
            tick_ms.add(ms, static_cast<std::uint64_t>(ticks));
            if (host.metrics) {
                host.metrics->observe_ticks(ms / 1000.0, ticks);
                auto sample = jetrace::ops::sample_of(server, *host.transport);
                sample.refused_unallocated = host.refused_unallocated;
                host.metrics->publish(sample);
            }
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    // Let goodbyes leave.
    std::vector<jetrace::net::Event> ignored;
    for (int i = 0; i < 20; ++i) {
        host.transport->service(host.now_us() / 1000, ignored);
        host.transport->flush();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (host.metrics) {
        auto sample = jetrace::ops::sample_of(server, *host.transport);
        sample.refused_unallocated = host.refused_unallocated;
        host.metrics->publish(sample);
    }
    return rc;
}

/// One JSON line of figures; rates per simulated second (wall time scaled
/// by --time-scale).
void print_figures(const jetrace::server::RaceServer& server, const Host& host,
                   const jetrace::server::TickTimes& tick_ms) {
    const double wall_s = std::chrono::duration<double>(Clock::now() - host.start).count() * host.time_scale;
    const auto totals = host.transport->totals();
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
}

/// How long Shutdown is retried at exit (unit: s).
constexpr double kAgonesShutdownWait = 3.0;

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const auto rc = jetrace::server_main::parse_options(argc, argv, o)) return *rc;
    std::optional<jetrace::Scene> scene;
    if (!jetrace::server_main::prepare(o, scene)) return 2;
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    Host host;
    if (!open_host(o, host)) return 1;
    if (host.agones) {
        const int rc = wait_for_allocation(*scene, o, host);
        if (rc != 0 || g_signal != 0) {
            host.agones->shutdown(kAgonesShutdownWait);
            return rc;
        }
    }
    jetrace::server::RaceServer server(o.cfg, *scene, *host.transport);
    server.on_race_end = print_race_end;
    jetrace::server::TickTimes tick_ms;
    const int rc = run_races(server, host, tick_ms);
    // After the last race (or a signal): the GameServer is done.
    if (host.agones) host.agones->shutdown(kAgonesShutdownWait);
    print_figures(server, host, tick_ms);
    if (rc != 0) return rc;
    // A replay that could not be written whole is a lost result.
    return server.replay_failures() == 0 ? 0 : 1;
}
